//! Print anisotropy: a transversely isotropic fibre term added to the isochoric law.
//!
//! # Physics
//!
//! The actuators are printed by fused deposition (FDM) lying on their side: the bending plane
//! `y–z` is parallel to the build plate and the layers stack along `x`. Within a layer the
//! filament is deposited in the `y–z` plane, by default along the actuator's length `z`
//! ([`Fibre::ALONG_LENGTH`]). A printed part is therefore not isotropic: the deposited strand
//! may be stiffer than the bond between neighbouring strands and layers (`k > 0` along the
//! filament), or a weak interlayer bond may make one direction softer (`k < 0` along it).
//! This module models either as a single preferred unit direction `a0` in the reference
//! configuration.
//!
//! # Equations
//!
//! With `C = FᵀF`, `J = det F`, the isochoric pseudo-invariant `Ī4 = J^{-2/3} a0·C a0`
//! (the squared isochoric stretch along `a0`) and the modulus `k` (MPa):
//!
//! ```text
//!   W_f = (k/2) (Ī4 − 1)²
//!   P_f = ∂W_f/∂F = k (Ī4 − 1) G,        G = ∂Ī4/∂F = r (2 b − (2/3) I4 g),
//!           r = J^{-2/3},  I4 = a0·C a0 = |m|²,  m = F a0,  b = m⊗a0,  g = F^{-T}
//!   A_f = ∂P_f/∂F:  A_iJkL = k G_iJ G_kL
//!         + k (Ī4 − 1) r [ 2 δ_ik a_J a_L − (4/3)(b_iJ g_kL + g_iJ b_kL)
//!                          + (4/9) I4 g_iJ g_kL + (2/3) I4 g_iL g_kJ ]
//! ```
//!
//! (`a_J` the components of `a0`). `A_f` is major-symmetric. Units: `W_f` in
//! MPa = N/mm² (energy per reference volume), `P_f` in MPa, `a0` dimensionless.
//!
//! # What the term does
//!
//! * It depends on `F` only through `F̄ = J^{-1/3} F`, so it belongs to the isochoric part:
//!   its Cauchy stress `σ_f = J⁻¹ P_f Fᵀ = J⁻¹ k (Ī4 − 1) r (2 m⊗m − ⅔ I4 I)` is traceless at
//!   **every** `F`, not only at small strain: it adds no hydrostatic stress, and a pure volume
//!   change leaves it unstressed.
//! * It vanishes, with its stress, in the reference state and under any rigid rotation
//!   (`Ī4 = 1`), and is invariant under rotations of the material about `a0` and under
//!   `a0 → −a0` (transverse isotropy).
//! * Small strain `ε`: `Ī4 − 1 ≈ 2 a0·ε_dev a0`, so `W_f ≈ 2k (D:ε)²` with
//!   `D = dev(a0⊗a0)`, `|D|² = ⅔`: the elasticity tensor gains `4k D⊗D`. The shear moduli
//!   along and across `a0` (strains `sym(a0⊗b)`, `sym(b⊗c)`, `b⊗b − c⊗c` with `b, c ⟂ a0`)
//!   are unchanged and a volume change is unresisted; only the mode `D` stiffens (it contains
//!   shear at 45° to `a0` in planes containing it). With the isotropic small-strain response
//!   `2μ0 dev + κ vol` of the law, uniaxial stress along `a0` behaves like an isotropic solid
//!   with shear modulus `μ' = μ0 + 4k/3`: `E_a = 9κμ'/(3κ + μ')`, which tends to `3μ0 + 4k`
//!   for `κ/μ0 → ∞`. So the extra uniaxial modulus along `a0` is `4k` in the incompressible
//!   limit; for finite `κ` it is `E_a − E_iso = 4k − (μ'² − μ0²)/κ + O(μ0³/κ²)`, a relative
//!   change of order `μ0/κ` (10⁻³ at the default `κ = 1000 μ0`). Across `a0`
//!   (incompressible): `E_⊥ = μ0 (3μ0 + 4k)/(μ0 + k)`, between `3μ0` and `4μ0` for `k > 0`.
//!   To target `E_a / E_iso = ρ`, take `k = ¾ μ0 (ρ − 1)`.
//!
//! # Admissible modulus
//!
//! The small-strain energy is `μ0|ε_dev|² + κ/2 (tr ε)² + 2k (D:ε_dev)²
//! ≥ (μ0 + 4k/3)|ε_dev|² + κ/2 (tr ε)²` (Cauchy–Schwarz, equality for `ε_dev ∝ D`), so it is
//! positive-definite iff `k > −¾ μ0`. [`Material::with_fibre`](super::Material::with_fibre)
//! accepts `k ∈ [−μ0/4, 4μ0]` ([`FIBRE_MODULUS_RANGE`], in units of `μ0`):
//!
//! * `−μ0/4`: the weakest mode keeps `μ' ≥ ⅔ μ0` and `E_a ≥ 2μ0` (a third softer than the
//!   isotropic `3μ0`), margin enough over the loss of definiteness at `−¾ μ0`. A negative `k`
//!   is a small-to-moderate strain model only: `W_f ~ (k/2) λ⁴` is unbounded below for a
//!   stretch `λ` along `a0`, so uniaxial tension along `a0` reaches a maximum nominal stress
//!   (a limit point, beyond which the material is unstable). For `ogden_002` it lies at
//!   `λ ≈ 1.23` for `k = −μ0/4` and `λ ≈ 1.54` for `k = −μ0/10` (tested).
//! * `4μ0`: `E_a ≈ 19 μ0`, 6.3 times the isotropic `3μ0`, far beyond the along/across-strand
//!   stiffness ratios of printed elastomers; a larger value is taken for a unit or definition
//!   error (e.g. the along-strand Young's modulus given instead of `k`).
//!
//! Outside `det F > 0` the energy is `+∞` and stress and tangent are `NaN`, as for the laws.
//! Nothing here allocates.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::isotropic::{fill_nan, jacobian_and_inverse_transpose};
use super::{finite, inadmissible, MaterialError, Tangent9};

/// Admissible fibre modulus `k` in units of the law's `μ0`: `[−¼, 4]` (see the module docs).
pub const FIBRE_MODULUS_RANGE: (f64, f64) = (-0.25, 4.0);

/// Raw parameters of [`Fibre`]: the direction as given and the modulus `k` (MPa).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FibreParams {
    /// Reference direction `a0` (any finite non-zero vector; normalised on construction).
    pub direction: [f64; 3],
    /// Modulus `k` (MPa).
    pub modulus: f64,
}

/// A fibre term `W_f = (k/2)(Ī4 − 1)²` with a validated unit direction (see the
/// [module docs](self)).
///
/// Serialised as its [`FibreParams`] (the direction as given), so a round trip is exact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "FibreParams", into = "FibreParams")]
pub struct Fibre {
    params: FibreParams,
    /// The unit direction `a0`.
    a0: Vector3<f64>,
}

impl TryFrom<FibreParams> for Fibre {
    type Error = MaterialError;
    fn try_from(p: FibreParams) -> Result<Self, MaterialError> {
        Self::new(p.direction, p.modulus)
    }
}

impl From<Fibre> for FibreParams {
    fn from(f: Fibre) -> Self {
        f.params
    }
}

/// Kinematics of the fibre term at one `F`.
struct FibreKinematics {
    /// `r = J^{-2/3}`.
    r: f64,
    /// `I4 = a0·C a0`.
    i4: f64,
    /// `Ī4 − 1`.
    excess: f64,
    /// `b = (F a0)⊗a0`.
    b: Matrix3<f64>,
    /// `g = F^{-T}`.
    g: Matrix3<f64>,
    /// `G = ∂Ī4/∂F`.
    grad: Matrix3<f64>,
}

impl Fibre {
    /// The default filament direction: along the actuator's length `z`.
    pub const ALONG_LENGTH: [f64; 3] = [0.0, 0.0, 1.0];

    /// A fibre term along `direction` (normalised) with modulus `k = modulus` (MPa).
    ///
    /// The range of `k` depends on the law and is checked by
    /// [`Material::with_fibre`](super::Material::with_fibre).
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `fibre.modulus` unless it is finite, or
    /// `fibre.direction` unless every component is finite and the vector is non-zero.
    pub fn new(direction: [f64; 3], modulus: f64) -> Result<Self, MaterialError> {
        let modulus = finite("fibre.modulus", modulus)?;
        let expected = "a finite non-zero direction vector";
        if let Some(&bad) = direction.iter().find(|c| !c.is_finite()) {
            return Err(inadmissible("fibre.direction", bad, expected));
        }
        let v = Vector3::from(direction);
        let largest = v.amax();
        if largest == 0.0 {
            return Err(inadmissible("fibre.direction", 0.0, expected));
        }
        // scaling by the largest component first avoids overflow and underflow of |v|
        let a0 = (v / largest).normalize();
        Ok(Self {
            params: FibreParams { direction, modulus },
            a0,
        })
    }

    /// The raw parameters (the direction as given).
    pub fn params(&self) -> &FibreParams {
        &self.params
    }

    /// The unit reference direction `a0`.
    pub fn direction(&self) -> &Vector3<f64> {
        &self.a0
    }

    /// The modulus `k` (MPa).
    pub fn modulus(&self) -> f64 {
        self.params.modulus
    }

    /// The admissible interval of `k` for a law with initial shear modulus `mu0`
    /// ([`FIBRE_MODULUS_RANGE`] times `μ0`).
    pub fn admissible_modulus(mu0: f64) -> (f64, f64) {
        (FIBRE_MODULUS_RANGE.0 * mu0, FIBRE_MODULUS_RANGE.1 * mu0)
    }

    /// Checks `k` against [`Fibre::admissible_modulus`] of `mu0`.
    pub(crate) fn check_modulus(&self, mu0: f64) -> Result<(), MaterialError> {
        let (lo, hi) = Self::admissible_modulus(mu0);
        let k = self.params.modulus;
        if (lo..=hi).contains(&k) {
            return Ok(());
        }
        Err(inadmissible(
            "fibre.modulus",
            k,
            &format!(
                "a value in [{lo}, {hi}] MPa, i.e. [{}, {}] times the law's mu0 = {mu0} \
                 (the small-strain stiffness is positive-definite only for k > -0.75 mu0)",
                FIBRE_MODULUS_RANGE.0, FIBRE_MODULUS_RANGE.1
            ),
        ))
    }

    /// `Ī4 = J^{-2/3} a0·C a0`, or `None` unless `det F > 0`.
    pub fn pseudo_invariant(&self, f: &Matrix3<f64>) -> Option<f64> {
        let j = f.determinant();
        (j.is_finite() && j > 0.0).then(|| j.powf(-2.0 / 3.0) * (f * self.a0).norm_squared())
    }

    /// Strain energy density `W_f = (k/2)(Ī4 − 1)²` (MPa; `+∞` unless `det F > 0`).
    pub fn energy(&self, f: &Matrix3<f64>) -> f64 {
        match self.pseudo_invariant(f) {
            Some(i4b) => 0.5 * self.params.modulus * (i4b - 1.0) * (i4b - 1.0),
            None => f64::INFINITY,
        }
    }

    /// Kinematics at `f`, or `None` unless `det F > 0`.
    fn kinematics(&self, f: &Matrix3<f64>) -> Option<FibreKinematics> {
        let (j, g) = jacobian_and_inverse_transpose(f)?;
        let r = j.powf(-2.0 / 3.0);
        let m = f * self.a0;
        let i4 = m.norm_squared();
        let b = m * self.a0.transpose();
        let grad = (b * 2.0 - g * (2.0 / 3.0 * i4)) * r;
        Some(FibreKinematics {
            r,
            i4,
            excess: r * i4 - 1.0,
            b,
            g,
            grad,
        })
    }

    /// Adds the stress `P_f = k (Ī4 − 1) ∂Ī4/∂F` to `p`; fills `p` with `NaN` unless
    /// `det F > 0`.
    pub fn add_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        match self.kinematics(f) {
            Some(kin) => *p += kin.grad * (self.params.modulus * kin.excess),
            None => fill_nan(p, None),
        }
    }

    /// Adds the stress to `p` and the tangent `∂P_f/∂F` to `a` (see the module docs and
    /// [`Tangent9`]); fills both with `NaN` unless `det F > 0`.
    pub fn add_stress_tangent_into(
        &self,
        f: &Matrix3<f64>,
        p: &mut Matrix3<f64>,
        a: &mut Tangent9,
    ) {
        let Some(kin) = self.kinematics(f) else {
            return fill_nan(p, Some(a));
        };
        let k = self.params.modulus;
        *p += kin.grad * (k * kin.excess);
        let FibreKinematics { r, i4, b, g, .. } = kin;
        let c = k * kin.excess * r;
        let (c_bg, c_gg, c_swap) = (-4.0 / 3.0 * c, 4.0 / 9.0 * i4 * c, 2.0 / 3.0 * i4 * c);
        let a0 = &self.a0;
        for row in 0..9 {
            let (i, jj) = (row / 3, row % 3);
            let grad_row = k * kin.grad[(i, jj)];
            for col in 0..9 {
                let (kk, l) = (col / 3, col % 3);
                let same = if i == kk {
                    2.0 * c * a0[jj] * a0[l]
                } else {
                    0.0
                };
                a[(row, col)] += grad_row * kin.grad[(kk, l)]
                    + same
                    + c_bg * (b[(i, jj)] * g[(kk, l)] + g[(i, jj)] * b[(kk, l)])
                    + c_gg * g[(i, jj)] * g[(kk, l)]
                    + c_swap * g[(i, l)] * g[(kk, jj)];
            }
        }
    }
}
