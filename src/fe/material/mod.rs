//! Hyperelastic material laws with the isochoric / volumetric split.
//!
//! Every law stores its isochoric strain energy `W_iso(F) = Ŵ(F̄)`, `F̄ = J^{-1/3} F`,
//! `J = det F`, and shares the volumetric energy `U(J) = κ/2 (J − 1)²` (ANSYS: `d = 2/κ`).
//! A [`Material`] may add an anisotropic fibre term `W_f(F̄)` to the isochoric part (below):
//!
//! ```text
//!   W(F) = W_iso(F) + U(J)
//!   P    = ∂W/∂F = F S_iso + U'(J) J F^{-T},           S_iso = 2 ∂W_iso/∂C,  C = FᵀF
//!   A    = ∂P/∂F:  A_iJkL = δ_ik S_JL + F_iM ℂ_MJNL F_kN
//!                         + (U''J + U') J F^{-T}_iJ F^{-T}_kL − U' J F^{-T}_iL F^{-T}_kJ,
//!                                                      ℂ = 4 ∂²W_iso/∂C∂C
//! ```
//!
//! The laws (isochoric stretches `λ̄_a = J^{-1/3} λ_a`, invariants of `C̄ = J^{-2/3} C`):
//!
//! * [`Ogden2`]: `W_iso = Σ_{i=1,2} (μ_i/α_i) (λ̄1^α_i + λ̄2^α_i + λ̄3^α_i − 3)`,
//!   `μ0 = ½ Σ μ_i α_i`; see [`ogden`].
//! * [`MooneyRivlin5`]: `W_iso = C10(Ī1−3) + C01(Ī2−3) + C20(Ī1−3)² + C11(Ī1−3)(Ī2−3) + C02(Ī2−3)²`,
//!   `μ0 = 2 (C10 + C01)`; see [`mooney_rivlin`].
//! * [`NeoHookean`]: `W_iso = μ/2 (Ī1 − 3)`, `μ0 = μ`; see [`neo_hookean`].
//!
//! Print anisotropy (optional, [`Material::fibre`]): [`Fibre`] adds
//! `W_f = (k/2)(Ī4 − 1)²`, `Ī4 = J^{-2/3} a0·C a0`, along the filament direction `a0` of the
//! FDM print, `k` in MPa, `−μ0/4 ≤ k ≤ 4μ0`. It is a function of `F̄` only, so it is part of
//! the isochoric energy: `W_iso(F) = Ŵ(F̄) + W_f(F̄)` in everything above, and the `iso_*`
//! functions of [`Material`] include it. See [`fibre`].
//!
//! Index convention for fourth-order tangents stored as 9×9 matrices:
//! `A[(3*i + J, 3*k + L)] = ∂P_iJ / ∂F_kL`, with `P` the first Piola–Kirchhoff stress
//! and `F` the deformation gradient (`nalgebra::Matrix3`, row `i`, column `J`).
//!
//! Outside the admissible set `J > 0` the energies return `+∞` and stresses and tangents are
//! filled with `NaN` (a solver should treat that as a failed trial state); nothing panics.
//! The `*_into` functions write into caller buffers and never allocate.

pub mod fibre;
mod isotropic;
mod literature;
pub mod mooney_rivlin;
pub mod neo_hookean;
pub mod ogden;
mod spec;

pub use fibre::{Fibre, FibreParams, FIBRE_MODULUS_RANGE};
pub use literature::literature_sets;
pub use mooney_rivlin::{MooneyRivlin5, MooneyRivlinParams};
pub use neo_hookean::{NeoHookean, NeoHookeanParams};
pub use ogden::{Ogden2, OgdenParams};

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::case::OgdenSet;

/// The bulk modulus of every shipped result as a multiple of the initial shear modulus,
/// `κ = 1000 μ0`: nearly incompressible, as the printed elastomer (`docs/MODEL.md`).
pub const DEFAULT_BULK_RATIO: f64 = 1000.0;

pub use isotropic::Tangent9;
// public for the tests in tests/fe/
#[doc(hidden)]
pub use isotropic::jacobian_and_inverse_transpose;

/// Errors of material parameters.
#[derive(Debug, Error)]
pub enum MaterialError {
    /// A parameter outside its admissible range.
    #[error("inadmissible material parameter {field} = {value}: expected {expected}")]
    Inadmissible {
        /// Parameter name.
        field: String,
        /// Offending value.
        value: f64,
        /// What was expected.
        expected: String,
    },
    /// A material name that is not a known literature set.
    #[error("unknown material {name:?}: expected one of {known}")]
    UnknownName {
        /// The name as given.
        name: String,
        /// The accepted names and forms.
        known: String,
    },
    /// A material specification or data row that cannot be read.
    #[error("cannot read material specification {spec:?}: {reason}")]
    Parse {
        /// The specification (or data row) as given.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
}

impl MaterialError {
    /// What was expected, for messages that name the field and the value themselves
    /// (`invalid material = "x": expected …`).
    pub fn expected(&self) -> String {
        match self {
            MaterialError::Inadmissible {
                field,
                value,
                expected,
            } => format!("an admissible set ({field} = {value}, expected {expected})"),
            MaterialError::UnknownName { known, .. } => format!("one of {known}"),
            MaterialError::Parse { reason, .. } => reason.clone(),
        }
    }
}

/// Builds an [`MaterialError::Inadmissible`].
pub(crate) fn inadmissible(field: &str, value: f64, expected: &str) -> MaterialError {
    MaterialError::Inadmissible {
        field: field.to_owned(),
        value,
        expected: expected.to_owned(),
    }
}

/// Checks that `value` is finite; the error names `field`.
pub(crate) fn finite(field: &str, value: f64) -> Result<f64, MaterialError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(inadmissible(field, value, "a finite number"))
    }
}

/// One hyperelastic law: its isochoric energy `W_iso(F) = Ŵ(J^{-1/3} F)` and derivatives.
///
/// Implementations are validated at construction, so every method works on admissible
/// parameters. For `det F ≤ 0` the energy is `+∞` and the stress and tangent are `NaN`.
pub trait Hyperelastic {
    /// The law's parameters.
    type Params;
    /// The (validated) parameters.
    fn params(&self) -> &Self::Params;
    /// Isochoric strain energy density `W_iso(F)`.
    fn iso_energy(&self, f: &Matrix3<f64>) -> f64;
    /// Isochoric first Piola–Kirchhoff stress `P_iso = ∂W_iso/∂F` written into `p`.
    fn iso_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>);
    /// Isochoric stress into `p` and tangent `∂P_iso/∂F` into `a` (see [`Tangent9`]).
    fn iso_stress_tangent_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>, a: &mut Tangent9);
    /// Initial (small-strain) shear modulus `μ0`.
    fn initial_shear_modulus(&self) -> f64;
}

/// Any of the supported laws (static dispatch by `match`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum MaterialLaw {
    /// Second-order Ogden.
    Ogden(Ogden2),
    /// Five-parameter Mooney–Rivlin.
    MooneyRivlin(MooneyRivlin5),
    /// Neo-Hookean.
    NeoHookean(NeoHookean),
}

impl From<Ogden2> for MaterialLaw {
    fn from(law: Ogden2) -> Self {
        MaterialLaw::Ogden(law)
    }
}

impl From<MooneyRivlin5> for MaterialLaw {
    fn from(law: MooneyRivlin5) -> Self {
        MaterialLaw::MooneyRivlin(law)
    }
}

impl From<NeoHookean> for MaterialLaw {
    fn from(law: NeoHookean) -> Self {
        MaterialLaw::NeoHookean(law)
    }
}

macro_rules! dispatch {
    ($self:ident, $law:ident => $e:expr) => {
        match $self {
            MaterialLaw::Ogden($law) => $e,
            MaterialLaw::MooneyRivlin($law) => $e,
            MaterialLaw::NeoHookean($law) => $e,
        }
    };
}

impl MaterialLaw {
    /// Isochoric strain energy density, see [`Hyperelastic::iso_energy`].
    pub fn iso_energy(&self, f: &Matrix3<f64>) -> f64 {
        dispatch!(self, law => law.iso_energy(f))
    }

    /// Isochoric stress, see [`Hyperelastic::iso_stress_into`].
    pub fn iso_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        dispatch!(self, law => law.iso_stress_into(f, p))
    }

    /// Isochoric stress and tangent, see [`Hyperelastic::iso_stress_tangent_into`].
    pub fn iso_stress_tangent_into(
        &self,
        f: &Matrix3<f64>,
        p: &mut Matrix3<f64>,
        a: &mut Tangent9,
    ) {
        dispatch!(self, law => law.iso_stress_tangent_into(f, p, a))
    }

    /// Initial shear modulus `μ0`, see [`Hyperelastic::initial_shear_modulus`].
    pub fn initial_shear_modulus(&self) -> f64 {
        dispatch!(self, law => law.initial_shear_modulus())
    }
}

/// A material: an isochoric law, optionally a fibre term, and the volumetric energy
/// `U(J) = κ/2 (J − 1)²`.
///
/// The fields are public for reading; build it with [`Material::new`],
/// [`Material::with_kappa`] or [`Material::from_spec`], then [`Material::with_fibre`]
/// (deserialisation validates too). Without a fibre the serialised form has no `fibre` key,
/// exactly as before the field existed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MaterialFields")]
pub struct Material {
    /// The isochoric law.
    pub law: MaterialLaw,
    /// Bulk modulus `κ` (same unit as the law's moduli, MPa in this crate).
    pub kappa: f64,
    /// Print anisotropy: a fibre term added to the isochoric energy (see [`fibre`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fibre: Option<Fibre>,
}

/// Unvalidated mirror of [`Material`] for deserialisation.
#[derive(Deserialize)]
struct MaterialFields {
    law: MaterialLaw,
    kappa: f64,
    #[serde(default)]
    fibre: Option<Fibre>,
}

impl TryFrom<MaterialFields> for Material {
    type Error = MaterialError;
    fn try_from(m: MaterialFields) -> Result<Self, MaterialError> {
        let material = Material::with_kappa(m.law, m.kappa)?;
        match m.fibre {
            Some(fibre) => material.with_fibre(fibre),
            None => Ok(material),
        }
    }
}

impl Material {
    /// A material with bulk modulus `κ = bulk_ratio · μ0`.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `bulk_ratio` unless it is finite and `> 0`.
    pub fn new(law: MaterialLaw, bulk_ratio: f64) -> Result<Self, MaterialError> {
        if !(bulk_ratio.is_finite() && bulk_ratio > 0.0) {
            return Err(inadmissible(
                "bulk_ratio",
                bulk_ratio,
                "a finite number > 0",
            ));
        }
        let kappa = bulk_ratio * law.initial_shear_modulus();
        Self::with_kappa(law, kappa)
    }

    /// A material with the given bulk modulus `κ` (and no fibre term).
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `kappa` unless it is finite and `> 0`.
    pub fn with_kappa(law: MaterialLaw, kappa: f64) -> Result<Self, MaterialError> {
        if !(kappa.is_finite() && kappa > 0.0) {
            return Err(inadmissible("kappa", kappa, "a finite number > 0"));
        }
        Ok(Self {
            law,
            kappa,
            fibre: None,
        })
    }

    /// This material with the fibre term `fibre` (replacing any previous one).
    ///
    /// ```
    /// use surrogate::fe::material::{Fibre, Material};
    /// let m = Material::from_spec("ogden_002", 1000.0)?;
    /// let k = m.mu0(); // uniaxial modulus along z: 3μ0 + 4k instead of 3μ0 (incompressible)
    /// let printed = m.with_fibre(Fibre::new(Fibre::ALONG_LENGTH, k)?)?;
    /// assert!(printed.fibre.is_some());
    /// # Ok::<(), surrogate::fe::material::MaterialError>(())
    /// ```
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `fibre.modulus` unless
    /// `−μ0/4 ≤ k ≤ 4μ0` ([`FIBRE_MODULUS_RANGE`], `μ0` of the law; see [`fibre`]).
    pub fn with_fibre(self, fibre: Fibre) -> Result<Self, MaterialError> {
        fibre.check_modulus(self.mu0())?;
        Ok(Self {
            fibre: Some(fibre),
            ..self
        })
    }

    /// Initial shear modulus `μ0` of the law (a fibre term leaves every small-strain shear
    /// modulus along and across its direction unchanged, see [`fibre`]).
    pub fn mu0(&self) -> f64 {
        self.law.initial_shear_modulus()
    }

    /// The Ogden set `(μ1, α1, μ2, α2)` if the law is [`Ogden2`].
    pub fn ogden_set(&self) -> Option<OgdenSet> {
        match &self.law {
            MaterialLaw::Ogden(o) => Some(OgdenSet::from(o)),
            _ => None,
        }
    }

    /// Isochoric strain energy density `W_iso(F)`: the law's, plus the fibre term's if any.
    pub fn iso_energy(&self, f: &Matrix3<f64>) -> f64 {
        let w = self.law.iso_energy(f);
        match &self.fibre {
            Some(fibre) => w + fibre.energy(f),
            None => w,
        }
    }

    /// Isochoric first Piola–Kirchhoff stress into `p` (law plus fibre term).
    pub fn iso_stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        self.law.iso_stress_into(f, p);
        if let Some(fibre) = &self.fibre {
            fibre.add_stress_into(f, p);
        }
    }

    /// Isochoric stress into `p` and its tangent into `a` (law plus fibre term).
    pub fn iso_stress_tangent_into(
        &self,
        f: &Matrix3<f64>,
        p: &mut Matrix3<f64>,
        a: &mut Tangent9,
    ) {
        self.law.iso_stress_tangent_into(f, p, a);
        if let Some(fibre) = &self.fibre {
            fibre.add_stress_tangent_into(f, p, a);
        }
    }

    /// Volumetric energy `U(J) = κ/2 (J − 1)²`.
    pub fn vol_energy(&self, j: f64) -> f64 {
        0.5 * self.kappa * (j - 1.0) * (j - 1.0)
    }

    /// Pressure-like derivative `U'(J) = κ (J − 1)`.
    pub fn vol_pressure(&self, j: f64) -> f64 {
        self.kappa * (j - 1.0)
    }

    /// Second derivative `U''(J) = κ`.
    pub fn vol_stiffness(&self, _j: f64) -> f64 {
        self.kappa
    }

    /// Total strain energy density `W_iso(F) + U(det F)` (`+∞` for `det F ≤ 0`).
    pub fn energy(&self, f: &Matrix3<f64>) -> f64 {
        self.iso_energy(f) + self.vol_energy(f.determinant())
    }

    /// Total first Piola–Kirchhoff stress `P = P_iso + U'(J) J F^{-T}` into `p`.
    pub fn stress_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>) {
        self.iso_stress_into(f, p);
        match isotropic::jacobian_and_inverse_transpose(f) {
            Some((j, f_inv_t)) => *p += f_inv_t * (self.vol_pressure(j) * j),
            None => p.fill(f64::NAN),
        }
    }

    /// Total stress into `p` and total tangent `∂P/∂F` into `a`.
    pub fn stress_tangent_into(&self, f: &Matrix3<f64>, p: &mut Matrix3<f64>, a: &mut Tangent9) {
        self.iso_stress_tangent_into(f, p, a);
        let Some((j, g)) = isotropic::jacobian_and_inverse_transpose(f) else {
            p.fill(f64::NAN);
            a.fill(f64::NAN);
            return;
        };
        let du = self.vol_pressure(j);
        let d2u = self.vol_stiffness(j);
        *p += g * (du * j);
        let c_outer = (d2u * j + du) * j;
        let c_swap = du * j;
        for i in 0..3 {
            for jj in 0..3 {
                for k in 0..3 {
                    for l in 0..3 {
                        a[(3 * i + jj, 3 * k + l)] +=
                            c_outer * g[(i, jj)] * g[(k, l)] - c_swap * g[(i, l)] * g[(k, jj)];
                    }
                }
            }
        }
    }

    /// Total stress `P` (convenience wrapper of [`Material::stress_into`]).
    pub fn stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let mut p = Matrix3::zeros();
        self.stress_into(f, &mut p);
        p
    }

    /// Total stress and tangent (convenience wrapper of [`Material::stress_tangent_into`]).
    pub fn stress_tangent(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, Tangent9) {
        let mut p = Matrix3::zeros();
        let mut a = Tangent9::zeros();
        self.stress_tangent_into(f, &mut p, &mut a);
        (p, a)
    }
}
