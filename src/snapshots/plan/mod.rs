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
//!
//! By concern:
//! - `ranges`: the sampling ranges, their checks and the map from the unit box to a case
//!   ([`Ranges`], [`max_wall_thickness`]);
//! - `settings`: the FE settings shared by every case ([`PlanSettings`]);
//! - `cases`: one case of a plan ([`PlannedCase`], [`case_name`]);
//! - `format`: the plan, its checks and its file: JSON, canonical form, hash ([`Plan`],
//!   [`FORMAT_VERSION`]);
//! - `sampling`: the Latin hypercube and the subset of a plan ([`Plan::generate`],
//!   [`Plan::subset`], [`SAMPLER`]);
//! - `domain`: the domain a surrogate trained on the plan accepts ([`Plan::sampled_domain`],
//!   [`Plan::stated_domain`]).

mod cases;
mod domain;
mod format;
mod ranges;
mod sampling;
mod settings;

pub use cases::{case_name, PlannedCase};
pub use format::{Plan, FORMAT_VERSION};
pub use ranges::{max_wall_thickness, max_wall_thickness_in, Ranges};
pub(crate) use sampling::unit_lhs;
pub use sampling::SAMPLER;
pub use settings::PlanSettings;
