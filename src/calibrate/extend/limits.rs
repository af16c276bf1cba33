//! The physical limits of the material parametrisation: how far the box may ever be extended.

use serde::{Deserialize, Serialize};

use crate::calibrate::CalibrateError;
use crate::case::material::COORD_NAMES;

/// The physical limits of the sampling coordinates `(μ0, s, α₁, α₂)`
/// ([`crate::calibrate::params`]): the box extension never moves a bound beyond them.
///
/// The parametrisation itself only requires `μ0 > 0`, `0 < s < 1`, `α₁ > 0 > α₂` (then
/// `μ₁ = 2sμ0/α₁ > 0` and `μ₂ = 2(1 − s)μ0/α₂ < 0`, every set admissible); the limits close
/// these open ends at values beyond which the set is no longer an elastomer the two-term Ogden
/// model describes:
///
/// - **`μ0` from 0.01 to 100 MPa**: from the softest cast silicones (Ecoflex 00-10, μ0 ≈
///   0.01 MPa) to the stiffest polyurethanes still printed as elastomers (Shore 70D, E ≈
///   300 MPa, μ0 ≈ 100 MPa). Below is a gel, above a rigid plastic.
/// - **`s` from 0.001 to 0.999**: `s = 0` or `1` makes `μ₁` or `μ₂` zero, a one-term material
///   that the two-term set (`μᵢαᵢ > 0`) and the snapshot plan refuse; a term carrying less than
///   1 ‰ of `μ0` is already that material.
/// - **`|α₁|`, `|α₂|` from 0.001 to 20**: Ogden fits of rubbers and elastomers use
///   `|αᵢ| ≲ 10` (Treloar's data: 1.3, 5.0, −2.0; the literature sets here: 3.11, −0.6 and
///   3.05, −0.0054). A term's stress grows as `λ^α`, so at 50 % stretch `α = 20` stiffens it
///   3300-fold: a material that locks at moderate strain, as no elastomer does and as the
///   FE's Newton iterations cannot follow. Small exponents are the smooth Hencky-like limit
///   with `μᵢαᵢ` fixed, already reached at 10⁻³ (`ogden_005`'s `α₂ = −0.0054`); below it
///   `μᵢ = 2sᵢμ0/αᵢ` exceeds 10³ `μ0` and loses digits in the strain energy.
///
/// Each limit is a setting: a study that knows its material better narrows them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalLimits {
    /// `μ0` (MPa), `[lo, hi]` with `0 < lo < hi`.
    pub mu0_mpa: [f64; 2],
    /// `s`, inside `(0, 1)`.
    pub term1_share: [f64; 2],
    /// `α₁`, both `> 0`.
    pub alpha1: [f64; 2],
    /// `α₂`, both `< 0`.
    pub alpha2: [f64; 2],
}

impl Default for PhysicalLimits {
    fn default() -> Self {
        PhysicalLimits {
            mu0_mpa: [0.01, 100.0],
            term1_share: [0.001, 0.999],
            alpha1: [0.001, 20.0],
            alpha2: [-20.0, -0.001],
        }
    }
}

impl PhysicalLimits {
    /// The limits of coordinate `i` (`μ0, s, α₁, α₂`; μ0 in MPa).
    pub fn range(&self, i: usize) -> [f64; 2] {
        [self.mu0_mpa, self.term1_share, self.alpha1, self.alpha2][i]
    }

    /// Finite, increasing limits inside the parametrisation's own (`μ0 > 0`, `0 < s < 1`,
    /// `α₁ > 0 > α₂`).
    ///
    /// # Errors
    /// [`CalibrateError::Input`] naming the first bad limit.
    pub fn validate(&self) -> Result<(), CalibrateError> {
        let expected = [
            "0 < lo < hi (MPa)",
            "0 < lo < hi < 1",
            "0 < lo < hi",
            "lo < hi < 0",
        ];
        let inside = |i: usize, v: f64| match i {
            1 => v > 0.0 && v < 1.0,
            3 => v < 0.0,
            _ => v > 0.0,
        };
        for (i, expected) in expected.iter().enumerate() {
            let [lo, hi] = self.range(i);
            if !(lo.is_finite() && hi.is_finite() && lo < hi && inside(i, lo) && inside(i, hi)) {
                return Err(CalibrateError::input(
                    &format!("physical limits of {}", COORD_NAMES[i]),
                    format!("[{lo}, {hi}]"),
                    expected,
                ));
            }
        }
        Ok(())
    }
}
