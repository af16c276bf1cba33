//! Second-order Ogden law (ANSYS convention).
//!
//! ```text
//!   W_iso = Σ_{i=1,2} (μ_i/α_i) (λ̄1^α_i + λ̄2^α_i + λ̄3^α_i − 3),   λ̄_a = J^{-1/3} λ_a,
//!   μ0    = ½ Σ_i μ_i α_i,   admissible iff every μ_i α_i > 0 (hence μ0 > 0).
//! ```
//!
//! Written in the principal values `c_a = λ_a²` of `C`, with `x_a = ln λ̄_a = ½(ln c_a − ⅓ Σ_b ln c_b)`
//! (so `Σ x_a = 0`), `t_a = λ̄_a^α = exp(α x_a)`, `d_a = t_a − ⅓ Σ_b t_b`, `s = Σ_b t_b`, per term:
//!
//! ```text
//!   W       = (μ/α) Σ_a (exp(α x_a) − 1 − α x_a)          (equal to the form above since Σ x_a = 0)
//!   S_a     = 2 ∂W/∂c_a = μ d_a / c_a
//!   ∂S_a/∂c_b = μ [ −δ_ab d_a / c_a² + α/(2 c_a c_b) (δ_ab t_a − (t_a + t_b)/3 + s/9) ]
//! ```
//!
//! The energy form with `exp(y) − 1 − y` avoids the cancellation of `Σ λ̄^α − 3` for tiny
//! `α` (the literature set `ogden_005` has `α2 = −0.0054`, `μ2 = −1214`).
//! Stress and tangent follow the spectral formulas of the `isotropic` module.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::isotropic::{fill_nan, principal_frame, principal_values, push_forward_into};
use super::isotropic::{spectral_material_tangent, spectral_stress};
use super::{finite, inadmissible, Hyperelastic, MaterialError, Tangent9};
use crate::case::OgdenSet;

/// Raw parameters of [`Ogden2`]: moduli `μ_i` (MPa) and exponents `α_i`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OgdenParams {
    /// Moduli `[μ1, μ2]`.
    pub mu: [f64; 2],
    /// Exponents `[α1, α2]`.
    pub alpha: [f64; 2],
}

/// Second-order Ogden law with validated parameters (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "OgdenParams", into = "OgdenParams")]
pub struct Ogden2 {
    params: OgdenParams,
}

impl TryFrom<OgdenParams> for Ogden2 {
    type Error = MaterialError;
    fn try_from(p: OgdenParams) -> Result<Self, MaterialError> {
        Self::new(p.mu[0], p.alpha[0], p.mu[1], p.alpha[1])
    }
}

impl From<Ogden2> for OgdenParams {
    fn from(o: Ogden2) -> Self {
        o.params
    }
}

/// The case's set as the law's raw parameters (no check; [`Ogden2`] checks).
impl From<OgdenSet> for OgdenParams {
    fn from(p: OgdenSet) -> Self {
        OgdenParams {
            mu: [p.mu1_mpa, p.mu2_mpa],
            alpha: [p.alpha1, p.alpha2],
        }
    }
}

/// The law's raw parameters as the case's set (no check).
impl From<OgdenParams> for OgdenSet {
    fn from(p: OgdenParams) -> Self {
        OgdenSet {
            mu1_mpa: p.mu[0],
            alpha1: p.alpha[0],
            mu2_mpa: p.mu[1],
            alpha2: p.alpha[1],
        }
    }
}

/// The law of a set, checked by [`Ogden2::new`].
impl TryFrom<OgdenSet> for Ogden2 {
    type Error = MaterialError;
    fn try_from(p: OgdenSet) -> Result<Self, MaterialError> {
        Self::new(p.mu1_mpa, p.alpha1, p.mu2_mpa, p.alpha2)
    }
}

/// The set of a law (admissible: the law was checked).
impl From<&Ogden2> for OgdenSet {
    fn from(o: &Ogden2) -> Self {
        OgdenSet::from(o.params)
    }
}

/// `exp(y) − 1 − y`, accurate for small `|y|`.
fn exp_minus_linear(y: f64) -> f64 {
    if y.abs() < 1e-3 {
        0.5 * y * y * (1.0 + y / 3.0 * (1.0 + y / 4.0 * (1.0 + y / 5.0)))
    } else {
        y.exp_m1() - y
    }
}

/// `x_a = ln λ̄_a` from the principal values of `C`.
fn log_iso_stretches(c: &Vector3<f64>) -> Vector3<f64> {
    let l = c.map(f64::ln);
    let mean = l.sum() / 3.0;
    l.map(|la| 0.5 * (la - mean))
}

impl Ogden2 {
    /// Ogden law `(μ1, α1, μ2, α2)`, moduli in MPa.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming the field if a value is not finite, an `α_i` is
    /// zero, or a term has `μ_i α_i ≤ 0`.
    pub fn new(mu1: f64, alpha1: f64, mu2: f64, alpha2: f64) -> Result<Self, MaterialError> {
        let mu = [finite("mu1", mu1)?, finite("mu2", mu2)?];
        let alpha = [finite("alpha1", alpha1)?, finite("alpha2", alpha2)?];
        for i in 0..2 {
            if alpha[i] == 0.0 {
                return Err(inadmissible(
                    &format!("alpha{}", i + 1),
                    0.0,
                    "a non-zero exponent",
                ));
            }
            let product = mu[i] * alpha[i];
            if !(product > 0.0 && product.is_finite()) {
                let field = format!("mu{n}*alpha{n}", n = i + 1);
                return Err(inadmissible(
                    &field,
                    product,
                    "a finite value > 0 (each Ogden term needs mu_i alpha_i > 0)",
                ));
            }
        }
        let ogden = Self {
            params: OgdenParams { mu, alpha },
        };
        let mu0 = ogden.initial_shear_modulus();
        if !mu0.is_finite() {
            return Err(inadmissible("mu0", mu0, "a finite initial shear modulus"));
        }
        Ok(ogden)
    }

    /// Terms `(μ_i, α_i)`.
    fn terms(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.params
            .mu
            .iter()
            .copied()
            .zip(self.params.alpha.iter().copied())
    }

    /// Principal stresses `S_a` and, if asked, `∂S_a/∂c_b`.
    fn principal_response(&self, c: &Vector3<f64>, ds: Option<&mut Matrix3<f64>>) -> Vector3<f64> {
        let x = log_iso_stretches(c);
        let mut s = Vector3::zeros();
        let mut dsum = Matrix3::zeros();
        for (mu, alpha) in self.terms() {
            let e = x.map(|xa| (alpha * xa).exp_m1());
            let mean_e = e.sum() / 3.0;
            let t = e.add_scalar(1.0);
            let t_sum = t.sum();
            for a in 0..3 {
                let d_a = e[a] - mean_e;
                s[a] += mu * d_a / c[a];
                for b in 0..3 {
                    let delta = if a == b { 1.0 } else { 0.0 };
                    let bracket = delta * t[a] - (t[a] + t[b]) / 3.0 + t_sum / 9.0;
                    dsum[(a, b)] +=
                        mu * (-delta * d_a / (c[a] * c[a]) + 0.5 * alpha * bracket / (c[a] * c[b]));
                }
            }
        }
        if let Some(ds) = ds {
            *ds = dsum;
        }
        s
    }
}

impl Hyperelastic for Ogden2 {
    type Params = OgdenParams;

    fn params(&self) -> &OgdenParams {
        &self.params
    }

    fn iso_energy(&self, f: &Matrix3<f64>) -> f64 {
        let Some(c) = principal_values(f) else {
            return f64::INFINITY;
        };
        let x = log_iso_stretches(&c);
        self.terms()
            .map(|(mu, alpha)| {
                mu / alpha
                    * x.iter()
                        .map(|&xa| exp_minus_linear(alpha * xa))
                        .sum::<f64>()
            })
            .sum()
    }

    fn iso_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        let Some((c, n)) = principal_frame(f) else {
            return fill_nan(p, None);
        };
        let s = self.principal_response(&c, None);
        *p = f * spectral_stress(&n, &s);
    }

    fn iso_stress_tangent_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>, a: &mut Tangent9) {
        let Some((c, n)) = principal_frame(f) else {
            return fill_nan(p, Some(a));
        };
        let mut ds = Matrix3::zeros();
        let s = self.principal_response(&c, Some(&mut ds));
        let cc = spectral_material_tangent(&c, &n, &s, &ds);
        push_forward_into(f, &spectral_stress(&n, &s), &cc, p, a);
    }

    fn initial_shear_modulus(&self) -> f64 {
        0.5 * self.terms().map(|(mu, alpha)| mu * alpha).sum::<f64>()
    }
}
