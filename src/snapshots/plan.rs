//! The sampling plan: ranges, a seeded maximin Latin hypercube stratified over `N`, the
//! pressure ramp and the FE settings, and the explicit list of cases.
//!
//! ## Parametrisation
//!
//! A case is `(N, T, μ₁, α₁, μ₂, α₂)` (second-order Ogden, ANSYS convention). The material is
//! sampled through quantities whose every combination is admissible:
//!
//! ```text
//!   μ0 = ½ (μ₁α₁ + μ₂α₂)      initial shear modulus, log-uniform in ranges.mu0_mpa
//!   s  = μ₁α₁ / (2 μ0)         share of term 1 in μ0, uniform in ranges.term1_share ⊂ (0, 1)
//!   α₁ > 0, α₂ < 0             uniform in ranges.alpha1, ranges.alpha2
//!   ⇒ μ₁ = 2 s μ0 / α₁,  μ₂ = 2 (1 − s) μ0 / α₂,   μ₁α₁ = 2 s μ0 > 0,  μ₂α₂ = 2 (1 − s) μ0 > 0.
//! ```
//!
//! `μ0` carries most of the response (the small-strain stiffness) and is kept to a physically
//! plausible interval; the split between the terms and the exponents (the strain stiffening)
//! are explored widely. Fixed `μᵢαᵢ` makes `α₂ → 0⁻` a smooth limit (a Hencky-like term), so
//! the range of `α₂` reaches close to 0 (the literature set `ogden_005` has `α₂ = −0.0054`).
//!
//! ## Default ranges (what lies inside)
//!
//! | quantity | range | ogden_002 | ogden_005 |
//! |---|---|---|---|
//! | `N` | 7, 8, …, 15 (stratified) | — | — |
//! | `T` (mm) | 1.2 … 2.8, capped per `N` so the cavity stays ≥ 0.5 mm | — | — |
//! | `μ0` (MPa) | 1.5 … 15, log-uniform | 5.708 | 3.476 |
//! | `s` | 0.02 … 0.95 | 0.308 | 0.057 |
//! | `α₁` | 1 … 8 | 3.11 | 3.05 |
//! | `α₂` | −3 … −0.004 | −0.6 | −0.0054 |
//!
//! Both literature Ogden sets (`ogden_002`, `ogden_005`) lie inside these ranges (tested;
//! [`Ranges::literature_inside`] lists them); `mooney_rivlin_5` is not an Ogden set. The
//! domain a trained model accepts ([`Plan::sampled_domain`]) is the box its cases actually
//! span, reaching the plan's nominal end wherever the cases come within one stratum
//! (`1/K` of the range) of it ([`crate::case::domain`]); for a plan whose cases miss an end by
//! more it stays narrower than the ranges and can leave a literature set outside (`ogden_005`'s
//! `α₂` = −0.0054 lies near the range's end); `snapshots plan` reports both
//! ([`Plan::literature_in_sampled_domain`]), and the model's domain check agrees with the
//! second. `μ0` spans
//! a factor 10 around the literature values and NinjaFlex's data-sheet modulus (E ≈ 12 MPa,
//! μ0 ≈ 4 MPa), so a calibrated optimum near the experiments lies inside: the calibrator
//! searches the box of the training cases of a model trained on the plan
//! ([`crate::calibrate::ParamSpace::Training`]), which lies inside the model's domain.
//!
//! **Why all of 7..15 for `N`**: the SPEC's model range is 7..15 and the surrogate accepts only
//! trained values of `N`; a case costs the same whatever its `N`, so covering every integer
//! gives the design space at no extra cost, with the experimental 9, 11, 13 among them
//! (`--n-values 9,11,13` restricts a plan to the experiments). `T`'s upper end is capped per `N`:
//! `T ≤ (Lf/N − g − 0.5)/2` (92/15 − 1 − 0.5 → T ≤ 2.32 at N = 15).
//!
//! ## Sampling
//!
//! A maximin Latin hypercube in the unit cube `[0, 1]⁶` (egobox-doe's `Lhs`, kind `Optimized`:
//! the enhanced stochastic evolutionary algorithm, Jin et al. 2005) seeded with
//! `Xoshiro256Plus::seed_from_u64(seed)`. Dimension 0 is **stratified over N**: case `i` gets
//! the `N` value number `⌊rank_i · m / K⌋` (rank of its coordinate among the `K` cases, `m`
//! values of `N`), so every `N` gets `⌊K/m⌋` or `⌈K/m⌉` cases. The other dimensions map linearly
//! (`μ0` logarithmically) onto the ranges; `T`'s range is the one capped for the case's `N`.
//!
//! ## Effects
//!
//! A plan can add physics beyond the nominal model ([`crate::fe::effects`]) in two ways:
//!
//! * **fixed** for every case: `settings.effects`, a map `{name: value}`;
//! * **sampled**: `ranges.effects`, a map `{name: [lo, hi]}` (inside the effect's own range):
//!   each sampled effect is one more axis of the Latin hypercube, `[0, 1]^(6 + k)` for `k`
//!   sampled effects in the library's order, mapped linearly onto its range, and every case
//!   carries its values in `cases[i].effects`.
//!
//! An effect is fixed or sampled, not both. A plan without effects writes neither field, so a
//! plan written before effects existed reads, re-serialises and hashes exactly as before
//! (tested on the committed plans), and its sampler is the 6-dimensional one above. The
//! snapshot CSV of a plan with effects carries one column per effect after the provenance
//! ([`crate::schema::effect_column`]); the trainer ignores them. [`Plan::subset`] picks its
//! cases by the 6 design and material axes.

use std::collections::BTreeMap;
use std::path::Path;

use egobox_doe::{Lhs, LhsKind, SamplingMethod};
use ndarray::Array2;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;
use serde::{Deserialize, Serialize};

use super::{Shard, SnapshotError};
use crate::case::{CaseInputs, Domain, DomainViolation, PlanDomain, Query};
use crate::fe::effects::{Effect, EffectError, Effects};
use crate::fe::geometry::{Design, DesignParams, GeometryError, MIN_CAVITY_LENGTH, N_RANGE};
use crate::fe::material::{
    literature_sets, Hyperelastic, Material, MaterialError, MaterialLaw, Ogden2,
};
use crate::fe::mesh::{MeshLevel, MeshOptions};
use crate::fe::simulate::ContactSettings;
use crate::fe::simulate::{validate_pressures, SimulateError};
use crate::fe::solver::SolverSettings;
use crate::schema;

/// Version of the plan format written and accepted.
pub const FORMAT_VERSION: u32 = 1;

/// Description of the sampler recorded in generated plans.
pub const SAMPLER: &str =
    "egobox-doe 0.35 Lhs(Optimized: maximin ESE) on [0,1]^6, Xoshiro256Plus::seed_from_u64(seed); \
     N stratified by rank";

/// Sampling ranges (see the [module docs](self) for the parametrisation).
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

/// The FE settings shared by every case of a plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanSettings {
    /// The pressure ramp (bar), increasing, every level one snapshot.
    pub pressures_bar: Vec<f64>,
    /// Self-weight on/off.
    pub gravity: bool,
    /// Mesh level and optional element size.
    pub mesh: MeshOptions,
    /// Bulk modulus as a multiple of `μ0`.
    pub bulk_ratio: f64,
    /// Nonlinear solver settings.
    pub solver: SolverSettings,
    /// Contact settings (bellows, clamp, force plate).
    #[serde(default)]
    pub contact: ContactSettings,
    /// Effects fixed for every case (none: not written).
    #[serde(default, skip_serializing_if = "no_effects")]
    pub effects: Effects,
}

/// Whether no effect is set (a plan without effects writes no `effects` field).
fn no_effects(e: &Effects) -> bool {
    e.iter().next().is_none()
}

impl Default for PlanSettings {
    /// 0 → 3.5 bar in steps of 0.25 (15 levels), gravity, `standard` mesh, κ = 1000 μ0,
    /// default solver.
    fn default() -> Self {
        Self {
            pressures_bar: (0..=14).map(|i| f64::from(i) * 0.25).collect(),
            gravity: true,
            mesh: MeshOptions::level(MeshLevel::Standard),
            bulk_ratio: crate::fe::material::DEFAULT_BULK_RATIO,
            solver: SolverSettings::default(),
            contact: ContactSettings::default(),
            effects: Effects::default(),
        }
    }
}

/// One case of a plan: a design and an Ogden material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlannedCase {
    /// Identifier, unique in the plan (names the case file).
    pub id: usize,
    /// Number of bellows `N`.
    pub n_bellows: usize,
    /// Wall thickness `T` (mm).
    pub wall_thickness_mm: f64,
    /// Ogden `μ₁` (MPa).
    pub mu1_mpa: f64,
    /// Ogden `α₁`.
    pub alpha1: f64,
    /// Ogden `μ₂` (MPa).
    pub mu2_mpa: f64,
    /// Ogden `α₂`.
    pub alpha2: f64,
    /// Values of the plan's sampled effects (none: not written).
    #[serde(default, skip_serializing_if = "no_effects")]
    pub effects: Effects,
}

/// A sampling plan (see the [module docs](self) and the format in [`super`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Must be [`FORMAT_VERSION`].
    pub format_version: u32,
    /// Seed of the sampler.
    pub seed: u64,
    /// How the cases were sampled.
    pub sampler: String,
    /// The sampling ranges.
    pub ranges: Ranges,
    /// FE settings of every case.
    pub settings: PlanSettings,
    /// The cases.
    pub cases: Vec<PlannedCase>,
}

/// Only the version, read before the rest so an old or new format gets a clear error.
#[derive(Deserialize)]
struct VersionProbe {
    format_version: Option<serde_json::Value>,
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

impl Ranges {
    /// Checks every range.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the first bad range (`ranges.<name>`).
    pub fn validate(&self) -> Result<(), SnapshotError> {
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
            if max_wall_thickness(v) < self.wall_thickness_mm[0] {
                return Err(SnapshotError::field(
                    "ranges.n_bellows",
                    v,
                    &format!(
                        "values of N that leave a cavity at T = {} mm (N = {v} needs T ≤ {:.3} mm)",
                        self.wall_thickness_mm[0],
                        max_wall_thickness(v)
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
    /// and columns).
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] for an unknown effect or a range outside the effect's own.
    pub fn sampled_effects(&self) -> Result<Vec<(Effect, [f64; 2])>, SnapshotError> {
        let mut out = Vec::with_capacity(self.effects.len());
        for (name, &r) in &self.effects {
            let e = Effect::from_name(name)
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
    fn case_at(
        &self,
        id: usize,
        n: usize,
        u: [f64; 5],
        sampled: &[(Effect, [f64; 2])],
        v: &[f64],
    ) -> Result<PlannedCase, EffectError> {
        let lerp = |r: [f64; 2], x: f64| r[0] + x * (r[1] - r[0]);
        let t_range = [
            self.wall_thickness_mm[0],
            self.wall_thickness_mm[1].min(max_wall_thickness(n)),
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
            mu1_mpa: 2.0 * s * mu0 / alpha1,
            alpha1,
            mu2_mpa: 2.0 * (1.0 - s) * mu0 / alpha2,
            alpha2,
            effects,
        })
    }

    /// A case's place in the unit box of `(N, T, ln μ0, s, α₁, α₂)` over these ranges (the
    /// sampling axes; 0.5 on a degenerate axis).
    pub fn unit_coordinates(&self, c: &PlannedCase) -> [f64; 6] {
        let unit = |v: f64, lo: f64, hi: f64| if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        let n_lo = self.n_bellows.iter().copied().min().unwrap_or(0) as f64;
        let n_hi = self.n_bellows.iter().copied().max().unwrap_or(0) as f64;
        let (k1, k2) = (c.mu1_mpa * c.alpha1, c.mu2_mpa * c.alpha2);
        let mu0 = 0.5 * (k1 + k2);
        let t = self.wall_thickness_mm;
        [
            unit(c.n_bellows as f64, n_lo, n_hi),
            unit(c.wall_thickness_mm, t[0], t[1]),
            unit(mu0.ln(), self.mu0_mpa[0].ln(), self.mu0_mpa[1].ln()),
            unit(k1 / (2.0 * mu0), self.term1_share[0], self.term1_share[1]),
            unit(c.alpha1, self.alpha1[0], self.alpha1[1]),
            unit(c.alpha2, self.alpha2[0], self.alpha2[1]),
        ]
    }

    /// The sampling box as a [`Domain`] (every `N` of the plan, the whole `T` range, the
    /// pressures `pressures`): what the plan aims to cover. The box its cases actually span,
    /// what a surrogate trained on them accepts, is [`Plan::sampled_domain`].
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

    /// Whether the Ogden set `[μ₁, α₁, μ₂, α₂]` lies inside the material ranges (terms taken
    /// in either order), by the same test as a surrogate's domain ([`Domain::violations`]).
    pub fn contains_ogden(&self, p: [f64; 4]) -> bool {
        let set = if p[1] > 0.0 {
            p
        } else {
            [p[2], p[3], p[0], p[1]]
        };
        set[1] > 0.0 && set[3] < 0.0 && self.domain(&[0.0]).contains_material(set)
    }

    /// The literature Ogden sets and whether each lies inside the ranges.
    ///
    /// # Errors
    /// If the shipped literature file cannot be read.
    pub fn literature_inside(&self) -> Result<Vec<(String, bool)>, MaterialError> {
        Ok(literature_sets()?
            .into_iter()
            .filter_map(|(name, law)| match law {
                MaterialLaw::Ogden(o) => {
                    let p = o.params();
                    let set = [p.mu[0], p.alpha[0], p.mu[1], p.alpha[1]];
                    Some((name, self.contains_ogden(set)))
                }
                _ => None,
            })
            .collect())
    }
}

impl PlanSettings {
    /// Checks the pressures, bulk ratio, mesh and solver settings.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the field (`settings.<name>`).
    pub fn validate(&self) -> Result<(), SnapshotError> {
        if let Err(SimulateError::Pressure {
            index,
            value,
            expected,
        }) = validate_pressures(&self.pressures_bar)
        {
            return Err(SnapshotError::field(
                format!("settings.pressures_bar[{index}]"),
                value,
                &expected,
            ));
        }
        if !(self.bulk_ratio.is_finite() && self.bulk_ratio > 0.0) {
            return Err(SnapshotError::field(
                "settings.bulk_ratio",
                self.bulk_ratio,
                "a finite number > 0 (κ/μ0)",
            ));
        }
        let named = |e: crate::fe::InvalidSetting, prefix: &str| {
            SnapshotError::field(format!("{prefix}{}", e.field), e.value, &e.expected)
        };
        self.mesh
            .validate()
            .map_err(|e| named(e, "settings.mesh."))?;
        self.solver
            .validate()
            .map_err(|e| named(e, "settings.solver."))?;
        if let Err(crate::fe::contact::ContactError::OutOfRange {
            field,
            value,
            expected,
        }) = self.contact.validate()
        {
            let field = field.trim_start_matches("contact ");
            return Err(SnapshotError::field(
                format!("settings.contact.{field}"),
                value,
                &expected,
            ));
        }
        Ok(())
    }
}

impl PlannedCase {
    /// The case's design (SPEC defaults with this `N` and `T`).
    ///
    /// # Errors
    /// [`GeometryError`] if `N` or `T` is out of range or leaves no cavity.
    pub fn design(&self) -> Result<Design, GeometryError> {
        DesignParams::new(self.n_bellows, self.wall_thickness_mm).validate()
    }

    /// The case's Ogden parameters `[μ₁, α₁, μ₂, α₂]`.
    pub fn ogden(&self) -> [f64; 4] {
        [self.mu1_mpa, self.alpha1, self.mu2_mpa, self.alpha2]
    }

    /// The case's material with `κ = bulk_ratio · μ0`.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] for an inadmissible Ogden set or bulk ratio.
    pub fn material(&self, bulk_ratio: f64) -> Result<Material, MaterialError> {
        let law = Ogden2::new(self.mu1_mpa, self.alpha1, self.mu2_mpa, self.alpha2)?;
        Material::new(MaterialLaw::Ogden(law), bulk_ratio)
    }

    /// The effects of the case's FE runs: the plan's fixed effects and the case's sampled ones.
    ///
    /// # Errors
    /// An effect both fixed and sampled with different values (a validated plan has none).
    pub fn effects_with(&self, settings: &PlanSettings) -> Result<Effects, EffectError> {
        let mut all = settings.effects.clone();
        for (e, v) in self.effects.iter() {
            let fixed = settings.effects.iter().find(|&(f, _)| f == e);
            if let Some((_, first)) = fixed.filter(|&(_, first)| first != v) {
                return Err(EffectError::Duplicate {
                    name: e.name(),
                    first,
                    second: v,
                });
            }
            all.set(e, v)?;
        }
        Ok(all)
    }

    /// Checks that the case carries a value of every sampled effect and no other.
    fn validate_effects(&self, index: usize, sampled: &[Effect]) -> Result<(), SnapshotError> {
        let mine: Vec<Effect> = self.effects.iter().map(|(e, _)| e).collect();
        if mine != sampled {
            let names = |v: &[Effect]| v.iter().map(|e| e.name()).collect::<Vec<_>>().join(", ");
            return Err(SnapshotError::field(
                format!("cases[{index}] (id {}).effects", self.id),
                format!("{{{}}}", names(&mine)),
                &format!(
                    "a value of each effect sampled by the plan (ranges.effects: {{{}}}) and no other",
                    names(sampled)
                ),
            ));
        }
        Ok(())
    }

    /// Checks design and material; errors name `cases[index]`.
    fn validate(&self, index: usize) -> Result<(), SnapshotError> {
        let at = |f: &str| format!("cases[{index}] (id {}).{f}", self.id);
        match self.design() {
            Ok(_) => {}
            Err(GeometryError::OutOfRange {
                field,
                value,
                expected,
            }) => {
                let name = if field == "wall_thickness" {
                    schema::WALL_THICKNESS.name
                } else {
                    field
                };
                return Err(SnapshotError::field(at(name), value, &expected));
            }
            Err(e @ GeometryError::NoCavity { .. }) => {
                return Err(SnapshotError::field(
                    at(schema::WALL_THICKNESS.name),
                    self.wall_thickness_mm,
                    &format!("a thickness that leaves a cavity ({e})"),
                ));
            }
        }
        match Ogden2::new(self.mu1_mpa, self.alpha1, self.mu2_mpa, self.alpha2) {
            Ok(_) => Ok(()),
            Err(MaterialError::Inadmissible {
                field,
                value,
                expected,
            }) => Err(SnapshotError::field(at(&field), value, &expected)),
            Err(e) => Err(SnapshotError::field(at("material"), "?", &e.to_string())),
        }
    }
}

/// `K` points of a maximin Latin hypercube in `[0, 1]^dims`.
pub(crate) fn unit_lhs(k: usize, dims: usize, seed: u64) -> Array2<f64> {
    let limits = Array2::from_shape_fn((dims, 2), |(_, j)| j as f64);
    let kind = if k < 3 {
        LhsKind::Classic
    } else {
        LhsKind::Optimized
    };
    Lhs::new_with_rng(&limits, Xoshiro256Plus::seed_from_u64(seed))
        .kind(kind)
        .sample(k)
}

impl Plan {
    /// The domain a surrogate trained on all cases of this plan accepts: the box its cases
    /// span in the regression's coordinates ([`Domain::of_cases`], as the surrogate builds
    /// its own), reaching the plan's nominal end wherever the cases come within one stratum
    /// of it ([`Domain::with_plan_ends`]), as the model file states it
    /// ([`Self::stated_domain`]), so the two agree on every query.
    pub fn sampled_domain(&self) -> Domain {
        self.cases_domain()
            .with_plan_ends(&self.ranges.domain(&[0.0]), self.cases.len())
    }

    /// What a model trained on this plan's cases states of its domain
    /// ([`PlanDomain`]): `sampled`, the box of its training cases
    /// ([`crate::rom::Surrogate::sampled_domain`]), with the plan's nominal ends where the
    /// cases come within one stratum of them; `label` names the plan (its file), to which the
    /// plan's hash is added.
    pub fn stated_domain(&self, sampled: &Domain, label: &str) -> PlanDomain {
        PlanDomain {
            plan: format!("{label} (plan {})", self.hash()),
            plan_cases: self.cases.len(),
            ranges: sampled
                .with_plan_ends(&self.ranges.domain(&[0.0]), self.cases.len())
                .stated_ranges(),
        }
    }

    /// Whether this plan holds a case of id `case_id` (`case_000012`) with the design and
    /// material `inputs` (a snapshot set's case, checked before the plan states its domain).
    pub fn holds(&self, case_id: &str, inputs: &CaseInputs) -> bool {
        self.cases.iter().any(|c| {
            case_name(c.id) == case_id
                && c.n_bellows as u32 == inputs.n_bellows
                && c.wall_thickness_mm == inputs.wall_thickness_mm
                && [c.mu1_mpa, c.alpha1, c.mu2_mpa, c.alpha2]
                    == [inputs.mu1_mpa, inputs.alpha1, inputs.mu2_mpa, inputs.alpha2]
        })
    }

    /// The box the cases span ([`Domain::of_cases`]).
    fn cases_domain(&self) -> Domain {
        let cases: Vec<CaseInputs> = self
            .cases
            .iter()
            .map(|c| CaseInputs {
                n_bellows: c.n_bellows as u32,
                wall_thickness_mm: c.wall_thickness_mm,
                mu1_mpa: c.mu1_mpa,
                alpha1: c.alpha1,
                mu2_mpa: c.mu2_mpa,
                alpha2: c.alpha2,
            })
            .collect();
        Domain::of_cases(&cases, &self.settings.pressures_bar)
    }

    /// The literature Ogden sets and the material inputs of each outside
    /// [`Self::sampled_domain`] (an empty list: inside).
    ///
    /// # Errors
    /// If the shipped literature file cannot be read.
    pub fn literature_in_sampled_domain(
        &self,
    ) -> Result<Vec<(String, Vec<DomainViolation>)>, MaterialError> {
        let domain = self.sampled_domain();
        let (n, t, p) = (
            domain.n_bellows.first().copied().unwrap_or(0),
            domain.ranges[1].map_or(0.0, |r| r[0]),
            domain.ranges[2].map_or(0.0, |r| r[0]),
        );
        Ok(literature_sets()?
            .into_iter()
            .filter_map(|(name, law)| match law {
                MaterialLaw::Ogden(o) => {
                    let q = o.params();
                    let set = [q.mu[0], q.alpha[0], q.mu[1], q.alpha[1]];
                    let v = domain.violations(&Query::new(n, t, p, set));
                    Some((name, v))
                }
                _ => None,
            })
            .collect())
    }

    /// Samples a plan of `n_cases` cases (see the [module docs](self)).
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] for a bad range, setting, or `n_cases = 0`.
    pub fn generate(
        n_cases: usize,
        seed: u64,
        ranges: Ranges,
        settings: PlanSettings,
    ) -> Result<Self, SnapshotError> {
        ranges.validate()?;
        settings.validate()?;
        if n_cases == 0 {
            return Err(SnapshotError::field("cases", 0, "at least 1 case"));
        }
        let sampled = ranges.sampled_effects()?;
        let dims = 6 + sampled.len();
        let u = unit_lhs(n_cases, dims, seed);
        let mut order: Vec<usize> = (0..n_cases).collect();
        order.sort_by(|&a, &b| u[[a, 0]].total_cmp(&u[[b, 0]]).then(a.cmp(&b)));
        let mut stratum = vec![0; n_cases];
        let m = ranges.n_bellows.len();
        for (rank, &i) in order.iter().enumerate() {
            stratum[i] = rank * m / n_cases;
        }
        let cases = (0..n_cases)
            .map(|i| {
                let n = ranges.n_bellows[stratum[i]];
                let x = [u[[i, 1]], u[[i, 2]], u[[i, 3]], u[[i, 4]], u[[i, 5]]];
                let v: Vec<f64> = (6..dims).map(|d| u[[i, d]]).collect();
                ranges
                    .case_at(i, n, x, &sampled, &v)
                    .map_err(|e| SnapshotError::field("ranges.effects", &e, "values in range"))
            })
            .collect::<Result<_, _>>()?;
        let sampler = if sampled.is_empty() {
            SAMPLER.to_owned()
        } else {
            let names: Vec<&str> = sampled.iter().map(|(e, _)| e.name()).collect();
            format!(
                "egobox-doe 0.35 Lhs(Optimized: maximin ESE) on [0,1]^{dims} (N, T, mu0, s, alpha1, \
                 alpha2, {}), Xoshiro256Plus::seed_from_u64(seed); N stratified by rank",
                names.join(", ")
            )
        };
        let plan = Self {
            format_version: FORMAT_VERSION,
            seed,
            sampler,
            ranges,
            settings,
            cases,
        };
        plan.validate()?;
        Ok(plan)
    }

    /// Checks version, ranges, settings and every case (ids unique).
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SnapshotError> {
        if self.format_version != FORMAT_VERSION {
            return Err(SnapshotError::field(
                "format_version",
                self.format_version,
                &format!("{FORMAT_VERSION}"),
            ));
        }
        self.ranges.validate()?;
        self.settings.validate()?;
        let sampled: Vec<Effect> = self
            .ranges
            .sampled_effects()?
            .into_iter()
            .map(|(e, _)| e)
            .collect();
        if let Some(e) = sampled
            .iter()
            .find(|e| self.settings.effects.iter().any(|(f, _)| f == **e))
        {
            return Err(SnapshotError::field(
                "settings.effects",
                e.name(),
                "an effect that ranges.effects does not sample (an effect is fixed or sampled, \
                 not both)",
            ));
        }
        if self.cases.is_empty() {
            return Err(SnapshotError::field("cases", "[]", "at least 1 case"));
        }
        let mut seen = std::collections::HashSet::new();
        for (i, c) in self.cases.iter().enumerate() {
            if !seen.insert(c.id) {
                return Err(SnapshotError::field(
                    format!("cases[{i}].id"),
                    c.id,
                    "an id not used by an earlier case",
                ));
            }
            c.validate(i)?;
            c.validate_effects(i, &sampled)?;
        }
        Ok(())
    }

    /// Parses and validates plan JSON; `source` names it in errors.
    ///
    /// # Errors
    /// [`SnapshotError::PlanSyntax`] for invalid JSON, an unknown or missing field (the
    /// message names it, with line and column); [`SnapshotError::PlanField`] for a bad value.
    pub fn from_json(text: &str, source: &str) -> Result<Self, SnapshotError> {
        let syntax = |e: serde_json::Error| SnapshotError::PlanSyntax {
            path: source.to_owned(),
            message: e.to_string(),
        };
        let probe: VersionProbe = serde_json::from_str(text).map_err(syntax)?;
        let expected = serde_json::Value::from(FORMAT_VERSION);
        match probe.format_version {
            Some(v) if v == expected => {}
            Some(v) => {
                return Err(SnapshotError::field(
                    "format_version",
                    v,
                    &format!("{FORMAT_VERSION} (the plan format this program reads)"),
                ))
            }
            None => {
                return Err(SnapshotError::field(
                    "format_version",
                    "missing",
                    &FORMAT_VERSION.to_string(),
                ))
            }
        }
        let plan: Plan = serde_json::from_str(text).map_err(syntax)?;
        plan.validate()?;
        Ok(plan)
    }

    /// Reads and validates a plan file.
    ///
    /// # Errors
    /// I/O errors and those of [`Plan::from_json`].
    pub fn read(path: &Path) -> Result<Self, SnapshotError> {
        let text = std::fs::read_to_string(path).map_err(|e| SnapshotError::io(path, e))?;
        Self::from_json(&text, &path.display().to_string())
    }

    /// Canonical compact JSON (the hashed form).
    pub fn canonical_json(&self) -> String {
        // ok: plain numbers, strings and vectors; no map with non-string keys
        serde_json::to_string(self).expect("a plan always serialises")
    }

    /// Pretty JSON (what `snapshots plan` writes).
    pub fn pretty_json(&self) -> String {
        // ok: as above
        serde_json::to_string_pretty(self).expect("a plan always serialises")
    }

    /// The plan hash: CRC-32 of [`Plan::canonical_json`], 8 lowercase hex digits.
    pub fn hash(&self) -> String {
        format!("{:08x}", crc32fast::hash(self.canonical_json().as_bytes()))
    }

    /// A plan of `k` of this plan's cases (same ids and inputs) with other mesh settings: the
    /// high-fidelity subset of a multi-fidelity training set, whose cases pair one to one with
    /// the low-fidelity ones.
    ///
    /// Cases are picked greedily for the largest distance to those already picked (maximin) in
    /// the unit box of `(N, T, ln μ0, s, α1, α2)` over the plan's ranges, taking the values of
    /// `N` in turn; the first is the case nearest the centre. Deterministic: ties go to the
    /// smaller id.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] for `k = 0` or `k` larger than the plan, or bad settings.
    pub fn subset(&self, k: usize, mesh: MeshOptions) -> Result<Self, SnapshotError> {
        if k == 0 || k > self.cases.len() {
            return Err(SnapshotError::field(
                "cases",
                k,
                &format!("1 ..= {} (the cases of the plan)", self.cases.len()),
            ));
        }
        let r = &self.ranges;
        let coords: Vec<[f64; 6]> = self.cases.iter().map(|c| r.unit_coordinates(c)).collect();
        let dist2 = |a: &[f64; 6], b: &[f64; 6]| -> f64 {
            a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
        };
        // smallest squared distance of each case to the picked ones (centre before the first)
        let mut nearest: Vec<f64> = coords.iter().map(|c| -dist2(c, &[0.5; 6])).collect();
        let mut picked = vec![false; self.cases.len()];
        let mut chosen = Vec::with_capacity(k);
        let mut turn = 0;
        while chosen.len() < k {
            let n = r.n_bellows[turn % r.n_bellows.len()];
            turn += 1;
            let best = (0..self.cases.len())
                .filter(|&i| !picked[i] && self.cases[i].n_bellows == n)
                .max_by(|&a, &b| {
                    nearest[a]
                        .total_cmp(&nearest[b])
                        .then(self.cases[b].id.cmp(&self.cases[a].id))
                });
            let Some(i) = best else {
                continue;
            };
            picked[i] = true;
            chosen.push(i);
            for (j, c) in coords.iter().enumerate() {
                let d = dist2(c, &coords[i]);
                nearest[j] = if chosen.len() == 1 {
                    d
                } else {
                    nearest[j].min(d)
                };
            }
        }
        chosen.sort_by_key(|&i| self.cases[i].id);
        let plan = Self {
            format_version: FORMAT_VERSION,
            seed: self.seed,
            sampler: format!(
                "subset of plan {} ({} cases): greedy maximin in the unit box of (N, T, ln mu0, s, \
                 alpha1, alpha2), N in turn; parent sampler: {}",
                self.hash(),
                self.cases.len(),
                self.sampler
            ),
            ranges: self.ranges.clone(),
            settings: PlanSettings {
                mesh,
                ..self.settings.clone()
            },
            cases: chosen.iter().map(|&i| self.cases[i].clone()).collect(),
        };
        plan.validate()?;
        Ok(plan)
    }

    /// The effects of the plan's snapshot columns: the fixed and the sampled ones, in the
    /// library's order (empty for a plan without effects).
    pub fn effect_columns(&self) -> Vec<Effect> {
        let mut all: Vec<Effect> = self.settings.effects.iter().map(|(e, _)| e).collect();
        if let Some(c) = self.cases.first() {
            all.extend(c.effects.iter().map(|(e, _)| e));
        }
        all.sort();
        all.dedup();
        all
    }

    /// The cases of `shard`, in plan order (see [`Shard`]).
    pub fn shard_cases(&self, shard: Shard) -> Vec<&PlannedCase> {
        self.cases
            .iter()
            .enumerate()
            .filter(|(i, _)| shard.owns(*i))
            .map(|(_, c)| c)
            .collect()
    }
}

/// The `case_id` of a plan case.
pub fn case_name(id: usize) -> String {
    format!("case_{id:06}")
}
