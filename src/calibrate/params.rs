//! The fitted quantities: the coordinates the fit moves in and the bounded boxes it moves
//! inside. The Ogden set and its sampling coordinates are the ground floor's
//! ([`OgdenSet`], [`MaterialCoords`], re-exported here; their equations in
//! [`crate::case::material`]); a literature set by name ([`OgdenSet::literature`]) is here.
//!
//! ## Spaces
//!
//! Every point of a box in `(ln μ0, s, α₁, α₂)` with `0 < s < 1`, `α₁ > 0 > α₂` is admissible
//! by construction: the calibrator moves in such a box ([`ParamSpace::Training`], the
//! surrogate's training domain) and never outside it. The study's procedure moves in a ±10 %
//! box around a literature set in the raw parameters `(μ₁, α₁, μ₂, α₂)` ([`ParamSpace::Raw`]),
//! checked to be admissible and inside the training domain at every corner.
//!
//! Both spaces map the unit box `u ∈ [0, 1]⁴` linearly onto their box; [`ParamSpace::ogden`]
//! and [`ParamSpace::ogden_jacobian`] give the set and `∂(μ₁, α₁, μ₂, α₂)/∂u`.

use serde::{Deserialize, Serialize};

use super::CalibrateError;
pub use crate::case::material::{MaterialCoords, OgdenSet, COORD_NAMES, NAMES};
use crate::rom::Surrogate;

impl OgdenSet {
    /// A literature set by name (`ogden_002`, `ogden_005`).
    ///
    /// # Errors
    /// An unknown name or a set that is not a two-term Ogden material.
    pub fn literature(name: &str) -> Result<Self, CalibrateError> {
        let m =
            crate::fe::material::Material::from_spec(name, crate::fe::material::DEFAULT_BULK_RATIO)
                .map_err(|e| CalibrateError::input("material", name, &e.expected()))?;
        let set = m
            .ogden_set()
            .ok_or_else(|| CalibrateError::input("material", name, "a two-term Ogden set"))?;
        Ok(Self::new(set.mu1_mpa, set.alpha1, set.mu2_mpa, set.alpha2)?)
    }
}

/// The box the fit moves in; `u ∈ [0, 1]⁴` maps linearly onto `[lo, hi]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "space", rename_all = "snake_case")]
pub enum ParamSpace {
    /// A box in `(ln μ0, s, α₁, α₂)`: the surrogate's training domain (or a part of it).
    Training {
        /// Lower corner.
        lo: [f64; 4],
        /// Upper corner.
        hi: [f64; 4],
    },
    /// A box in `(μ₁, α₁, μ₂, α₂)` (the study's ±10 % box).
    Raw {
        /// Lower corner.
        lo: [f64; 4],
        /// Upper corner.
        hi: [f64; 4],
    },
}

/// A box around a set against a domain ([`ParamSpace::raw_box_in`]).
#[derive(Debug, Clone, PartialEq)]
pub enum BoxFit {
    /// Every corner inside: the box.
    Inside(ParamSpace),
    /// The first corner found outside the domain.
    Outside {
        /// That corner, as a set.
        corner: OgdenSet,
    },
}

impl ParamSpace {
    /// The surrogate's training domain in `(ln μ0, s, α₁, α₂)` (from its feature scaling: the
    /// box the snapshot plan sampled).
    ///
    /// # Errors
    /// A model whose feature scaling lacks a material feature, or whose box is not admissible.
    pub fn training_domain(model: &Surrogate) -> Result<Self, CalibrateError> {
        // raw feature order: (N, T, ln μ0, α1, s, α2); our order: (ln μ0, s, α1, α2)
        let mut lo = [f64::NAN; 4];
        let mut hi = [f64::NAN; 4];
        let f = &model.features;
        for (j, &feat) in f.index.iter().enumerate() {
            let slot = match feat {
                2 => 0,
                4 => 1,
                3 => 2,
                5 => 3,
                _ => continue,
            };
            let half = 1.0 / f.inv_half[j];
            lo[slot] = f.center[j] - half;
            hi[slot] = f.center[j] + half;
        }
        let ok = lo.iter().chain(&hi).all(|v| v.is_finite())
            && lo[1] > 0.0
            && hi[1] < 1.0
            && lo[2] > 0.0
            && hi[3] < 0.0;
        if !ok {
            return Err(CalibrateError::input(
                "model feature scaling",
                format!("{lo:?} .. {hi:?}"),
                "a material box with 0 < s < 1, alpha1 > 0 > alpha2",
            ));
        }
        Ok(ParamSpace::Training { lo, hi })
    }

    /// The box `center · (1 ± fraction)` in the raw parameters (the study's ±10 % box for
    /// `fraction = 0.1`), checked against `domain` at every corner.
    ///
    /// # Errors
    /// A fraction outside (0, 0.5], or a corner that is outside `domain`.
    pub fn raw_box(
        center: &OgdenSet,
        fraction: f64,
        domain: &ParamSpace,
    ) -> Result<Self, CalibrateError> {
        match Self::raw_box_in(center, fraction, domain)? {
            BoxFit::Inside(space) => Ok(space),
            BoxFit::Outside { corner } => Err(CalibrateError::input(
                "box",
                format!("corner {:?}", corner.as_array()),
                "inside the surrogate's training domain",
            )),
        }
    }

    /// The box `center · (1 ± fraction)` in the raw parameters, and whether it lies inside
    /// `domain` (every corner): a box that leaves it is an outcome, not an error, for a caller
    /// that reports it (`calibrate` skips the study's procedure and says why).
    ///
    /// # Errors
    /// A fraction outside (0, 0.5].
    pub fn raw_box_in(
        center: &OgdenSet,
        fraction: f64,
        domain: &ParamSpace,
    ) -> Result<BoxFit, CalibrateError> {
        if !(fraction > 0.0 && fraction <= 0.5) {
            return Err(CalibrateError::input(
                "box fraction",
                fraction,
                "in (0, 0.5]",
            ));
        }
        let c = center.as_array();
        let mut lo = [0.0; 4];
        let mut hi = [0.0; 4];
        for i in 0..4 {
            let (a, b) = (c[i] * (1.0 - fraction), c[i] * (1.0 + fraction));
            lo[i] = a.min(b);
            hi[i] = a.max(b);
        }
        let space = ParamSpace::Raw { lo, hi };
        for corner in 0..16u32 {
            let u: [f64; 4] = std::array::from_fn(|i| f64::from((corner >> i) & 1));
            let p = space.ogden(&u)?;
            if !domain.contains(&p) {
                return Ok(BoxFit::Outside { corner: p });
            }
        }
        Ok(BoxFit::Inside(space))
    }

    /// The unit-box coordinates' names.
    pub fn names(&self) -> [&'static str; 4] {
        match self {
            ParamSpace::Training { .. } => COORD_NAMES,
            ParamSpace::Raw { .. } => NAMES,
        }
    }

    fn corners(&self) -> (&[f64; 4], &[f64; 4]) {
        match self {
            ParamSpace::Training { lo, hi } | ParamSpace::Raw { lo, hi } => (lo, hi),
        }
    }

    /// The box coordinates `x = lo + u (hi − lo)` of a unit-box point.
    pub fn x(&self, u: &[f64; 4]) -> [f64; 4] {
        let (lo, hi) = self.corners();
        std::array::from_fn(|i| lo[i] + u[i] * (hi[i] - lo[i]))
    }

    /// The coordinates of a set in this space's unit box (may lie outside `[0, 1]`).
    pub fn unit(&self, p: &OgdenSet) -> [f64; 4] {
        let (lo, hi) = self.corners();
        let x = match self {
            ParamSpace::Training { .. } => {
                let c = p.coords();
                [c.mu0_mpa.ln(), c.share, c.alpha1, c.alpha2]
            }
            ParamSpace::Raw { .. } => p.as_array(),
        };
        std::array::from_fn(|i| (x[i] - lo[i]) / (hi[i] - lo[i]))
    }

    /// Whether a set lies in the box (with a relative tolerance of 1e-9 of the box size).
    pub fn contains(&self, p: &OgdenSet) -> bool {
        self.unit(p)
            .iter()
            .all(|&v| (-1e-9..=1.0 + 1e-9).contains(&v))
    }

    /// The Ogden set of a unit-box point.
    ///
    /// # Errors
    /// A point that is not admissible (only possible for a raw box that crosses a sign).
    pub fn ogden(&self, u: &[f64; 4]) -> Result<OgdenSet, CalibrateError> {
        let x = self.x(u);
        match self {
            ParamSpace::Training { .. } => Ok(OgdenSet::from_coords(MaterialCoords {
                mu0_mpa: x[0].exp(),
                share: x[1],
                alpha1: x[2],
                alpha2: x[3],
            })?),
            ParamSpace::Raw { .. } => Ok(OgdenSet::new(x[0], x[1], x[2], x[3])?),
        }
    }

    /// `∂(μ₁, α₁, μ₂, α₂)/∂u` at a unit-box point (row per Ogden parameter).
    pub fn ogden_jacobian(&self, u: &[f64; 4]) -> [[f64; 4]; 4] {
        let (lo, hi) = self.corners();
        let w: [f64; 4] = std::array::from_fn(|i| hi[i] - lo[i]);
        let x = self.x(u);
        let mut d = [[0.0; 4]; 4];
        match self {
            ParamSpace::Training { .. } => {
                let (mu0, s, a1, a2) = (x[0].exp(), x[1], x[2], x[3]);
                let mu1 = 2.0 * s * mu0 / a1;
                let mu2 = 2.0 * (1.0 - s) * mu0 / a2;
                // μ1 = 2 s μ0 / α1
                d[0] = [mu1, 2.0 * mu0 / a1, -mu1 / a1, 0.0];
                d[1] = [0.0, 0.0, 1.0, 0.0];
                // μ2 = 2 (1 − s) μ0 / α2
                d[2] = [mu2, -2.0 * mu0 / a2, 0.0, -mu2 / a2];
                d[3] = [0.0, 0.0, 0.0, 1.0];
            }
            ParamSpace::Raw { .. } => {
                for (i, row) in d.iter_mut().enumerate() {
                    row[i] = 1.0;
                }
            }
        }
        for row in &mut d {
            for (j, v) in row.iter_mut().enumerate() {
                *v *= w[j];
            }
        }
        d
    }

    /// The physical value of box coordinate `i` at unit value `u_i` (`μ0` in MPa, not its
    /// logarithm).
    pub fn physical(&self, i: usize, u_i: f64) -> f64 {
        let (lo, hi) = self.corners();
        let x = lo[i] + u_i * (hi[i] - lo[i]);
        match self {
            ParamSpace::Training { .. } if i == 0 => x.exp(),
            _ => x,
        }
    }
}
