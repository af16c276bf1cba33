//! The material of a case: a second-order Ogden set `(μ₁, α₁, μ₂, α₂)` (ANSYS convention, μ
//! in MPa), the one type every layer names it by ([`OgdenSet`]), and its sampling coordinates.
//!
//! ## Admissibility and coordinates
//!
//! A set is admissible when `μ₁α₁ > 0` and `μ₂α₂ > 0`. The snapshot plans sample, and the
//! surrogate regresses on,
//!
//! ```text
//!   μ0 = ½ (μ₁α₁ + μ₂α₂)      initial shear modulus (MPa)
//!   s  = μ₁α₁ / (2 μ0)         share of term 1 in μ0, in (0, 1)
//!   α₁ > 0,  α₂ < 0
//!   ⇒ μ₁ = 2 s μ0 / α₁,  μ₂ = 2 (1 − s) μ0 / α₂
//! ```
//!
//! so every point of a box in `(ln μ0, s, α₁, α₂)` with `0 < s < 1`, `α₁ > 0 > α₂` is
//! admissible by construction ([`MaterialCoords`], [`OgdenSet::from_coords`]).
//!
//! ## Conversions
//!
//! - `[μ₁, α₁, μ₂, α₂]`: [`OgdenSet::as_array`] and [`OgdenSet::from_array`] (an optimiser's
//!   vector, a numeric loop);
//! - the FE model's law: `From`/`TryFrom` between [`OgdenSet`] and
//!   `fe::material::ogden::{OgdenParams, Ogden2}` (in `fe`, which stands above this floor);
//! - the material spec the FE model and the CLI accept: [`OgdenSet::spec`].
//!
//! The fields are public: a set built by a struct literal, [`OgdenSet::from_array`] or read
//! from a file is not checked; [`OgdenSet::new`] and [`OgdenSet::check`] are the check.

use serde::{Deserialize, Serialize};

use super::CaseError;
use crate::schema;

/// A second-order Ogden parameter set (ANSYS convention); admissible (`μᵢαᵢ > 0`) when built by
/// [`Self::new`] or [`Self::from_coords`] (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OgdenSet {
    /// `μ₁` (MPa).
    pub mu1_mpa: f64,
    /// `α₁`.
    pub alpha1: f64,
    /// `μ₂` (MPa).
    pub mu2_mpa: f64,
    /// `α₂`.
    pub alpha2: f64,
}

impl OgdenSet {
    /// A validated set.
    ///
    /// # Errors
    /// [`CaseError::Input`] for a non-finite value or `μᵢαᵢ ≤ 0`, naming the parameter.
    pub fn new(mu1_mpa: f64, alpha1: f64, mu2_mpa: f64, alpha2: f64) -> Result<Self, CaseError> {
        let p = OgdenSet {
            mu1_mpa,
            alpha1,
            mu2_mpa,
            alpha2,
        };
        p.check()?;
        Ok(p)
    }

    /// Checks that the set is admissible: every value finite and `μᵢαᵢ > 0`.
    ///
    /// # Errors
    /// [`CaseError::Input`] naming the first non-finite parameter or inadmissible term.
    pub fn check(&self) -> Result<(), CaseError> {
        for (name, v) in NAMES.iter().zip(self.as_array()) {
            if !v.is_finite() {
                return Err(CaseError::input(name, v, "a finite number"));
            }
        }
        if self.mu1_mpa * self.alpha1 <= 0.0 {
            return Err(CaseError::input(
                "mu1*alpha1",
                self.mu1_mpa * self.alpha1,
                "> 0 (admissible Ogden term)",
            ));
        }
        if self.mu2_mpa * self.alpha2 <= 0.0 {
            return Err(CaseError::input(
                "mu2*alpha2",
                self.mu2_mpa * self.alpha2,
                "> 0 (admissible Ogden term)",
            ));
        }
        Ok(())
    }

    /// The set `[μ₁, α₁, μ₂, α₂]`, unchecked (as a struct literal; see [`Self::check`]).
    pub const fn from_array(p: [f64; 4]) -> Self {
        OgdenSet {
            mu1_mpa: p[0],
            alpha1: p[1],
            mu2_mpa: p[2],
            alpha2: p[3],
        }
    }

    /// `[μ₁, α₁, μ₂, α₂]`.
    pub const fn as_array(&self) -> [f64; 4] {
        [self.mu1_mpa, self.alpha1, self.mu2_mpa, self.alpha2]
    }

    /// From the sampling coordinates `(μ0, s, α₁, α₂)`.
    ///
    /// # Errors
    /// `μ0 ≤ 0`, `s ∉ (0, 1)`, `α₁ ≤ 0` or `α₂ ≥ 0`.
    pub fn from_coords(c: MaterialCoords) -> Result<Self, CaseError> {
        if !(c.mu0_mpa > 0.0 && c.share > 0.0 && c.share < 1.0 && c.alpha1 > 0.0 && c.alpha2 < 0.0)
        {
            return Err(CaseError::input(
                "material coordinates",
                format!("{c:?}"),
                "mu0 > 0, 0 < share < 1, alpha1 > 0 > alpha2",
            ));
        }
        Self::new(
            2.0 * c.share * c.mu0_mpa / c.alpha1,
            c.alpha1,
            2.0 * (1.0 - c.share) * c.mu0_mpa / c.alpha2,
            c.alpha2,
        )
    }

    /// Each parameter rounded to `digits` significant digits (the set as reported; the FE
    /// verification runs this set, so that its cached ramps survive changes in the last
    /// digits of the optimiser).
    pub fn rounded(&self, digits: i32) -> Self {
        let r = |v: f64| {
            if v == 0.0 {
                return 0.0;
            }
            let e = digits - 1 - v.abs().log10().floor() as i32;
            let f = 10f64.powi(e);
            (v * f).round() / f
        };
        OgdenSet {
            mu1_mpa: r(self.mu1_mpa),
            alpha1: r(self.alpha1),
            mu2_mpa: r(self.mu2_mpa),
            alpha2: r(self.alpha2),
        }
    }

    /// Initial shear modulus `μ0 = ½ Σ μᵢαᵢ` (MPa).
    pub fn mu0_mpa(&self) -> f64 {
        0.5 * (self.mu1_mpa * self.alpha1 + self.mu2_mpa * self.alpha2)
    }

    /// The sampling coordinates `(μ0, s, α₁, α₂)`.
    pub fn coords(&self) -> MaterialCoords {
        let (k1, k2) = (self.mu1_mpa * self.alpha1, self.mu2_mpa * self.alpha2);
        MaterialCoords {
            mu0_mpa: 0.5 * (k1 + k2),
            share: k1 / (k1 + k2),
            alpha1: self.alpha1,
            alpha2: self.alpha2,
        }
    }

    /// The material spec the FE model and the CLI accept: `mu1,alpha1,mu2,alpha2`.
    pub fn spec(&self) -> String {
        format!(
            "{},{},{},{}",
            self.mu1_mpa, self.alpha1, self.mu2_mpa, self.alpha2
        )
    }
}

/// Names of the Ogden parameters, in [`OgdenSet::as_array`] order ([`schema::OGDEN_COLUMNS`]).
pub const NAMES: [&str; 4] = schema::names(&schema::OGDEN_COLUMNS);

/// Names of the sampling coordinates, in [`MaterialCoords::as_array`] order
/// ([`schema::OGDEN_COORDINATES`]).
pub const COORD_NAMES: [&str; 4] = schema::names(&schema::OGDEN_COORDINATES);

/// The sampling coordinates of an Ogden set (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialCoords {
    /// Initial shear modulus `μ0` (MPa).
    pub mu0_mpa: f64,
    /// Share `s` of term 1 in `μ0`.
    pub share: f64,
    /// `α₁`.
    pub alpha1: f64,
    /// `α₂`.
    pub alpha2: f64,
}

impl MaterialCoords {
    /// `[μ0, s, α₁, α₂]`.
    pub fn as_array(&self) -> [f64; 4] {
        [self.mu0_mpa, self.share, self.alpha1, self.alpha2]
    }
}

/// The serde shape `[μ₁, α₁, μ₂, α₂]` of an [`OgdenSet`], for the files that store the set as
/// an array (a model's model-form source, a design report): `#[serde(with =
/// "crate::case::material::array")]` on an `OgdenSet` field keeps such a file as it was
/// ([`arrays`] for a `Vec<OgdenSet>`).
pub mod array {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::OgdenSet;

    /// Writes the set as `[μ₁, α₁, μ₂, α₂]`.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer>(p: &OgdenSet, s: S) -> Result<S::Ok, S::Error> {
        p.as_array().serialize(s)
    }

    /// Reads the set from `[μ₁, α₁, μ₂, α₂]` (unchecked, as [`OgdenSet::from_array`]).
    ///
    /// # Errors
    /// Anything but an array of four numbers.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<OgdenSet, D::Error> {
        <[f64; 4]>::deserialize(d).map(OgdenSet::from_array)
    }
}

/// The serde shape `[[μ₁, α₁, μ₂, α₂], …]` of a list of sets (see [`array`]).
pub mod arrays {
    use serde::{Deserialize, Deserializer, Serializer};

    use super::OgdenSet;

    /// Writes each set as `[μ₁, α₁, μ₂, α₂]`.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer>(v: &[OgdenSet], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(OgdenSet::as_array))
    }

    /// Reads each set from `[μ₁, α₁, μ₂, α₂]` (unchecked).
    ///
    /// # Errors
    /// Anything but a list of arrays of four numbers.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<OgdenSet>, D::Error> {
        let v = Vec::<[f64; 4]>::deserialize(d)?;
        Ok(v.into_iter().map(OgdenSet::from_array).collect())
    }
}
