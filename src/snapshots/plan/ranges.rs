//! The sampling ranges: their checks, the map from the unit box to a case and back, and the
//! box as a domain.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::cases::PlannedCase;
use crate::case::{Domain, OgdenSet};
use crate::fe::effects::{Effect, EffectError, Effects};
use crate::fe::geometry::{DesignParams, MIN_CAVITY_LENGTH, N_RANGE};
use crate::fe::material::{literature_sets, MaterialError, MaterialLaw};
use crate::fe::preset::Geometry;
use crate::snapshots::SnapshotError;

/// Sampling ranges (see the [module docs](crate::snapshots::plan) for the parametrisation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ranges {
    /// The values of `N` (strata), increasing.
    pub n_bellows: Vec<usize>,
    /// Wall thickness `T` (mm), capped per `N` by the cavity rule.
    pub wall_thickness_mm: [f64; 2],
    /// Initial shear modulus `μ0` (MPa), log-uniform.
    pub mu0_mpa: [f64; 2],
    /// Share `s = μ₁α₁ / (2 μ0)` of term 1, inside (0, 1).
    pub term1_share: [f64; 2],
    /// Exponent `α₁ > 0`.
    pub alpha1: [f64; 2],
    /// Exponent `α₂ < 0`.
    pub alpha2: [f64; 2],
    /// Sampled effects: name → `[lo, hi]` in the effect's unit, uniform (none: not written).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub effects: BTreeMap<String, [f64; 2]>,
}

impl Default for Ranges {
    fn default() -> Self {
        Self {
            n_bellows: (N_RANGE.0..=N_RANGE.1).collect(),
            wall_thickness_mm: [1.2, 2.8],
            mu0_mpa: [1.5, 15.0],
            term1_share: [0.02, 0.95],
            alpha1: [1.0, 8.0],
            alpha2: [-3.0, -0.004],
            effects: BTreeMap::new(),
        }
    }
}

/// Checks `lo ≤ hi`, both finite, and `pred(lo) && pred(hi)`.
fn check_interval(
    field: &str,
    r: [f64; 2],
    pred: impl Fn(f64) -> bool,
    expected: &str,
) -> Result<(), SnapshotError> {
    let ok = r[0].is_finite() && r[1].is_finite() && r[0] <= r[1] && pred(r[0]) && pred(r[1]);
    if ok {
        Ok(())
    } else {
        Err(SnapshotError::field(
            field,
            format!("[{}, {}]", r[0], r[1]),
            &format!("[lo, hi] with lo ≤ hi, {expected}"),
        ))
    }
}

/// Largest wall thickness that leaves a cavity of at least [`MIN_CAVITY_LENGTH`] for `n`
/// bellows with the SPEC's default free length and gap: `(Lf/N − g − 0.5)/2`, less 10⁻⁹ mm.
pub fn max_wall_thickness(n: usize) -> f64 {
    let d = DesignParams::default();
    (d.free_length / n as f64 - d.gap - MIN_CAVITY_LENGTH) / 2.0 - 1e-9
}

/// The largest buildable wall thickness of `n` bellows with `geometry`'s dimensions:
/// [`max_wall_thickness`] as modelled (bit for bit), [`Geometry::max_wall_thickness`]
/// otherwise (`−∞` when no `T` in range is buildable).
pub fn max_wall_thickness_in(geometry: &Geometry, n: usize) -> f64 {
    if geometry.is_as_modelled() {
        max_wall_thickness(n)
    } else {
        geometry.max_wall_thickness(n).unwrap_or(f64::NEG_INFINITY)
    }
}

impl Ranges {
    /// Checks every range, for the geometry as modelled.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the first bad range (`ranges.<name>`).
    pub fn validate(&self) -> Result<(), SnapshotError> {
        self.validate_in(&Geometry::as_modelled())
    }

    /// Checks every range; every `N` must be buildable at the smallest `T` with `geometry`.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the first bad range (`ranges.<name>`).
    pub fn validate_in(&self, geometry: &Geometry) -> Result<(), SnapshotError> {
        let n = &self.n_bellows;
        let n_ok = !n.is_empty()
            && n.windows(2).all(|w| w[0] < w[1])
            && n.iter().all(|v| (N_RANGE.0..=N_RANGE.1).contains(v));
        if !n_ok {
            return Err(SnapshotError::field(
                "ranges.n_bellows",
                format!("{n:?}"),
                &format!(
                    "a non-empty increasing list of integers in {}..={}",
                    N_RANGE.0, N_RANGE.1
                ),
            ));
        }
        let (t_lo, t_hi) = crate::fe::geometry::T_RANGE;
        let t_expected = format!("a thickness range inside [{t_lo}, {t_hi}] mm");
        check_interval(
            "ranges.wall_thickness_mm",
            self.wall_thickness_mm,
            |t| (t_lo..=t_hi).contains(&t),
            &t_expected,
        )?;
        for &v in n {
            let t_max = max_wall_thickness_in(geometry, v);
            if t_max < self.wall_thickness_mm[0] {
                return Err(SnapshotError::field(
                    "ranges.n_bellows",
                    v,
                    &format!(
                        "values of N that leave a cavity at T = {} mm with geometry '{}' (N = \
                         {v} needs T ≤ {t_max:.3} mm)",
                        self.wall_thickness_mm[0], geometry.name
                    ),
                ));
            }
        }
        check_interval("ranges.mu0_mpa", self.mu0_mpa, |v| v > 0.0, "both > 0 MPa")?;
        check_interval(
            "ranges.term1_share",
            self.term1_share,
            |v| v > 0.0 && v < 1.0,
            "both inside (0, 1)",
        )?;
        check_interval("ranges.alpha1", self.alpha1, |v| v > 0.0, "both > 0")?;
        check_interval("ranges.alpha2", self.alpha2, |v| v < 0.0, "both < 0")?;
        self.sampled_effects().map(|_| ())
    }

    /// The sampled effects and their ranges, in the library's order (the order of their axes
    /// and columns). A program's own effect is known inside its registry's
    /// [`reading`](crate::fe::effects::EffectRegistry::reading) scope.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] for an unknown effect or a range outside the effect's own.
    pub fn sampled_effects(&self) -> Result<Vec<(Effect, [f64; 2])>, SnapshotError> {
        let mut out = Vec::with_capacity(self.effects.len());
        for (name, &r) in &self.effects {
            let e = Effect::read_name(name)
                .map_err(|err| SnapshotError::field("ranges.effects", name, &err.to_string()))?;
            let info = e.info();
            let expected = format!(
                "inside the effect's range [{}, {}] {}",
                info.range.0, info.range.1, info.unit
            );
            check_interval(
                &format!("ranges.effects.{name}"),
                r,
                |v| Effects::neutral().with(e, v).is_ok(),
                &expected,
            )?;
            out.push((e, r));
        }
        out.sort_by_key(|&(e, _)| e);
        Ok(out)
    }

    /// Maps a point `u ∈ [0, 1]⁵` (T, μ0, s, α₁, α₂), `N` and the points `v` of the sampled
    /// effects' axes to a case.
    pub(super) fn case_at(
        &self,
        id: usize,
        n: usize,
        t_max: f64,
        u: [f64; 5],
        sampled: &[(Effect, [f64; 2])],
        v: &[f64],
    ) -> Result<PlannedCase, EffectError> {
        let lerp = |r: [f64; 2], x: f64| r[0] + x * (r[1] - r[0]);
        let t_range = [
            self.wall_thickness_mm[0],
            self.wall_thickness_mm[1].min(t_max),
        ];
        let mu0 = lerp([self.mu0_mpa[0].ln(), self.mu0_mpa[1].ln()], u[1]).exp();
        let s = lerp(self.term1_share, u[2]);
        let alpha1 = lerp(self.alpha1, u[3]);
        let alpha2 = lerp(self.alpha2, u[4]);
        let mut effects = Effects::default();
        for (&(e, r), &x) in sampled.iter().zip(v) {
            // the end points are inside the effect's range (validated), so is every value between
            effects.set(e, lerp(r, x).clamp(r[0], r[1]))?;
        }
        Ok(PlannedCase {
            id,
            n_bellows: n,
            wall_thickness_mm: lerp(t_range, u[0]),
            material: OgdenSet {
                mu1_mpa: 2.0 * s * mu0 / alpha1,
                alpha1,
                mu2_mpa: 2.0 * (1.0 - s) * mu0 / alpha2,
                alpha2,
            },
            effects,
        })
    }

    /// A case's place in the unit box of `(N, T, ln μ0, s, α₁, α₂)` over these ranges (the
    /// sampling axes; 0.5 on a degenerate axis).
    pub fn unit_coordinates(&self, c: &PlannedCase) -> [f64; 6] {
        let unit = |v: f64, lo: f64, hi: f64| if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        let n_lo = self.n_bellows.iter().copied().min().unwrap_or(0) as f64;
        let n_hi = self.n_bellows.iter().copied().max().unwrap_or(0) as f64;
        let m = &c.material;
        let (k1, k2) = (m.mu1_mpa * m.alpha1, m.mu2_mpa * m.alpha2);
        let mu0 = 0.5 * (k1 + k2);
        let t = self.wall_thickness_mm;
        [
            unit(c.n_bellows as f64, n_lo, n_hi),
            unit(c.wall_thickness_mm, t[0], t[1]),
            unit(mu0.ln(), self.mu0_mpa[0].ln(), self.mu0_mpa[1].ln()),
            unit(k1 / (2.0 * mu0), self.term1_share[0], self.term1_share[1]),
            unit(m.alpha1, self.alpha1[0], self.alpha1[1]),
            unit(m.alpha2, self.alpha2[0], self.alpha2[1]),
        ]
    }

    /// The sampling box as a [`Domain`] (every `N` of the plan, the whole `T` range, the
    /// pressures `pressures`): what the plan aims to cover. The box its cases actually span,
    /// what a surrogate trained on them accepts, is [`Plan::sampled_domain`].
    ///
    /// [`Plan::sampled_domain`]: crate::snapshots::plan::Plan::sampled_domain
    pub fn domain(&self, pressures: &[f64]) -> Domain {
        let n: Vec<u32> = self.n_bellows.iter().map(|&n| n as u32).collect();
        let lo = pressures.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = pressures.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Domain {
            n_bellows: n,
            ranges: [
                None,
                Some(self.wall_thickness_mm),
                Some([lo, hi]),
                Some(self.mu0_mpa),
                Some(self.term1_share),
                Some(self.alpha1),
                Some(self.alpha2),
            ],
        }
    }

    /// Whether the Ogden set lies inside the material ranges (terms taken in either order),
    /// by the same test as a surrogate's domain ([`Domain::violations`]).
    pub fn contains_ogden(&self, p: OgdenSet) -> bool {
        let set = if p.alpha1 > 0.0 {
            p
        } else {
            OgdenSet {
                mu1_mpa: p.mu2_mpa,
                alpha1: p.alpha2,
                mu2_mpa: p.mu1_mpa,
                alpha2: p.alpha1,
            }
        };
        set.alpha1 > 0.0 && set.alpha2 < 0.0 && self.domain(&[0.0]).contains_material(set)
    }

    /// The literature Ogden sets and whether each lies inside the ranges.
    ///
    /// # Errors
    /// If the shipped literature file cannot be read.
    pub fn literature_inside(&self) -> Result<Vec<(String, bool)>, MaterialError> {
        Ok(literature_sets()?
            .into_iter()
            .filter_map(|(name, law)| match law {
                MaterialLaw::Ogden(o) => Some((name, self.contains_ogden(OgdenSet::from(&o)))),
                _ => None,
            })
            .collect())
    }
}
