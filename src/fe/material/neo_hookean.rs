//! Neo-Hookean law.
//!
//! ```text
//!   W_iso = μ/2 (Ī1 − 3),   Ī1 = J^{-2/3} tr C,   μ0 = μ > 0.
//! ```
//!
//! Stress and tangent use the invariant formulas of the `isotropic` module
//! (`∂Ŵ/∂Ī1 = μ/2`, all other derivatives zero).

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use super::isotropic::{
    fill_nan, invariant_stress_into, invariant_stress_tangent_into, InvariantDerivatives,
    IsoInvariants,
};
use super::{inadmissible, Hyperelastic, MaterialError, Tangent9};

/// Raw parameters of [`NeoHookean`] (MPa).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NeoHookeanParams {
    /// Shear modulus `μ`.
    pub mu: f64,
}

/// Neo-Hookean law with a validated shear modulus (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "NeoHookeanParams", into = "NeoHookeanParams")]
pub struct NeoHookean {
    params: NeoHookeanParams,
}

impl TryFrom<NeoHookeanParams> for NeoHookean {
    type Error = MaterialError;
    fn try_from(p: NeoHookeanParams) -> Result<Self, MaterialError> {
        Self::new(p.mu)
    }
}

impl From<NeoHookean> for NeoHookeanParams {
    fn from(n: NeoHookean) -> Self {
        n.params
    }
}

impl NeoHookean {
    /// Neo-Hookean law with shear modulus `mu` (MPa).
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `mu` unless it is finite and `> 0`.
    pub fn new(mu: f64) -> Result<Self, MaterialError> {
        if !(mu.is_finite() && mu > 0.0) {
            return Err(inadmissible("mu", mu, "a finite shear modulus > 0"));
        }
        Ok(Self {
            params: NeoHookeanParams { mu },
        })
    }

    /// Derivatives of `Ŵ(Ī1)`.
    fn derivatives(&self) -> InvariantDerivatives {
        InvariantDerivatives {
            w1: 0.5 * self.params.mu,
            ..InvariantDerivatives::default()
        }
    }
}

impl Hyperelastic for NeoHookean {
    type Params = NeoHookeanParams;

    fn params(&self) -> &NeoHookeanParams {
        &self.params
    }

    fn iso_energy(&self, f: &Matrix3<f64>) -> f64 {
        IsoInvariants::new(f).map_or(f64::INFINITY, |inv| 0.5 * self.params.mu * (inv.i1b - 3.0))
    }

    fn iso_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        match IsoInvariants::new(f) {
            Some(inv) => invariant_stress_into(f, &inv, &self.derivatives(), p),
            None => fill_nan(p, None),
        }
    }

    fn iso_stress_tangent_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>, a: &mut Tangent9) {
        match IsoInvariants::new(f) {
            Some(inv) => invariant_stress_tangent_into(f, &inv, &self.derivatives(), p, a),
            None => fill_nan(p, Some(a)),
        }
    }

    fn initial_shear_modulus(&self) -> f64 {
        self.params.mu
    }
}
