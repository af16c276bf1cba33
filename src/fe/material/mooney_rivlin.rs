//! Five-parameter Mooney–Rivlin law.
//!
//! ```text
//!   W_iso = C10 (Ī1 − 3) + C01 (Ī2 − 3) + C20 (Ī1 − 3)² + C11 (Ī1 − 3)(Ī2 − 3) + C02 (Ī2 − 3)²,
//!   Ī1 = J^{-2/3} tr C,  Ī2 = J^{-4/3} ½((tr C)² − tr C²),  μ0 = 2 (C10 + C01) > 0.
//! ```
//!
//! The individual constants may be negative (the literature set `mooney_rivlin_5` has
//! `C10 = −0.233`); only `μ0 > 0` is required. Stress and tangent use the invariant
//! formulas of the `isotropic` module.

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use super::isotropic::{
    fill_nan, invariant_stress_into, invariant_stress_tangent_into, InvariantDerivatives,
    IsoInvariants,
};
use super::{finite, inadmissible, Hyperelastic, MaterialError, Tangent9};

/// Raw parameters of [`MooneyRivlin5`] (MPa).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MooneyRivlinParams {
    /// `C10`.
    pub c10: f64,
    /// `C01`.
    pub c01: f64,
    /// `C20`.
    pub c20: f64,
    /// `C11`.
    pub c11: f64,
    /// `C02`.
    pub c02: f64,
}

/// Five-parameter Mooney–Rivlin law with validated parameters (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MooneyRivlinParams", into = "MooneyRivlinParams")]
pub struct MooneyRivlin5 {
    params: MooneyRivlinParams,
}

impl TryFrom<MooneyRivlinParams> for MooneyRivlin5 {
    type Error = MaterialError;
    fn try_from(p: MooneyRivlinParams) -> Result<Self, MaterialError> {
        Self::new(p.c10, p.c01, p.c20, p.c11, p.c02)
    }
}

impl From<MooneyRivlin5> for MooneyRivlinParams {
    fn from(m: MooneyRivlin5) -> Self {
        m.params
    }
}

impl MooneyRivlin5 {
    /// Mooney–Rivlin law `(C10, C01, C20, C11, C02)` in MPa.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming the field if a constant is not finite or
    /// `μ0 = 2 (C10 + C01) ≤ 0`.
    pub fn new(c10: f64, c01: f64, c20: f64, c11: f64, c02: f64) -> Result<Self, MaterialError> {
        let params = MooneyRivlinParams {
            c10: finite("c10", c10)?,
            c01: finite("c01", c01)?,
            c20: finite("c20", c20)?,
            c11: finite("c11", c11)?,
            c02: finite("c02", c02)?,
        };
        let mu0 = 2.0 * (c10 + c01);
        if !(mu0 > 0.0 && mu0.is_finite()) {
            return Err(inadmissible(
                "mu0 = 2*(c10 + c01)",
                mu0,
                "a finite initial shear modulus > 0",
            ));
        }
        Ok(Self { params })
    }

    /// Derivatives of `Ŵ(Ī1, Ī2)`.
    fn derivatives(&self, i1b: f64, i2b: f64) -> InvariantDerivatives {
        let p = &self.params;
        let (x, y) = (i1b - 3.0, i2b - 3.0);
        InvariantDerivatives {
            w1: p.c10 + 2.0 * p.c20 * x + p.c11 * y,
            w2: p.c01 + p.c11 * x + 2.0 * p.c02 * y,
            w11: 2.0 * p.c20,
            w12: p.c11,
            w22: 2.0 * p.c02,
        }
    }
}

impl Hyperelastic for MooneyRivlin5 {
    type Params = MooneyRivlinParams;

    fn params(&self) -> &MooneyRivlinParams {
        &self.params
    }

    fn iso_energy(&self, f: &Matrix3<f64>) -> f64 {
        let Some(inv) = IsoInvariants::new(f) else {
            return f64::INFINITY;
        };
        let p = &self.params;
        let (x, y) = (inv.i1b - 3.0, inv.i2b - 3.0);
        p.c10 * x + p.c01 * y + p.c20 * x * x + p.c11 * x * y + p.c02 * y * y
    }

    fn iso_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        let Some(inv) = IsoInvariants::new(f) else {
            return fill_nan(p, None);
        };
        let d = self.derivatives(inv.i1b, inv.i2b);
        invariant_stress_into(f, &inv, &d, p);
    }

    fn iso_stress_tangent_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>, a: &mut Tangent9) {
        let Some(inv) = IsoInvariants::new(f) else {
            return fill_nan(p, Some(a));
        };
        let d = self.derivatives(inv.i1b, inv.i2b);
        invariant_stress_tangent_into(f, &inv, &d, p, a);
    }

    fn initial_shear_modulus(&self) -> f64 {
        2.0 * (self.params.c10 + self.params.c01)
    }
}
