//! Box extension: where the calibrated optimum presses a bound of the surrogate's training box,
//! the box is moved out there, FE cases fill the new slab, the surrogate is retrained and the
//! material refitted, round after round, until the optimum lies inside or the bounds it presses
//! are at their physical limits.
//!
//! ```text
//!   model M₀, its training set S₀, box B₀ (the span of its cases) ──► calibrate ──► θ₀
//!   after each calibration θ_{k−1}:
//!     no bound of M_{k−1}'s box active at θ_{k−1}                     ──► stop: Inside
//!     only bounds of coordinates the recordings do not determine
//!       (profile open on both sides) active                           ──► stop: Undetermined
//!     each other active bound (coordinate i, side ±) of B_{k−1}:
//!       b ← b ± step · width_i(B_{k−1}),  clipped at its physical limit
//!     every active bound already at its physical limit                 ──► stop: PhysicalLimit
//!     k − 1 = max_rounds                                               ──► stop: MaxRounds
//!   round k:
//!     B_k = B_{k−1} with the bounds moved;  the slabs B_k − B_{k−1}
//!     cases_per_round cases over the slabs (a Latin hypercube each, N stratified),
//!     the training plan's FE settings, run as a snapshot plan in extend_k/ (resumable)
//!       failed cases are reported and left out; all failed                 ──► error
//!     S_k = S_{k−1} + the round's cases ──► retrain M_k (model_extend_k.json) ──► calibrate ──► θ_k
//! ```
//!
//! Widths and steps are in the sampling coordinates `(ln μ0, s, α₁, α₂)`
//! ([`crate::calibrate::params`]): a step of 0.5 widens a pressed coordinate's range by half
//! (the pressed end of `μ0` moves by the factor `(hi/lo)^0.5`), and the cases are sampled as a
//! snapshot plan samples them (`μ0` log-uniform). The box a round extends is the nominal one, `B₀` moved by the rounds before;
//! the box the calibrator moves in is the retrained surrogate's, the span of its cases, which
//! comes within one stratum of `B_k`. A bound is *at its physical limit* when the nominal box
//! reaches it ([`PhysicalLimits`]: `μ0` 0.01–100 MPa, `s` 0.001–0.999, `|αᵢ|` 0.001–20, each
//! with its reasoning, each a setting).
//!
//! ## The new cases
//!
//! `B_k − B_{k−1}` is cut into disjoint boxes, coordinate by coordinate
//! ([`MaterialBox::slabs`]); each gets at least one case per value of `N` (when there are
//! enough), the rest of `cases_per_round` by volume. Each slab is sampled by the plan sampler
//! ([`crate::snapshots::plan::Plan::generate`]: maximin Latin hypercube, `N` stratified by
//! rank over the training set's values, `T` over the training plan's range capped per `N`,
//! any sampled effect over its range) with the seed `seed + 100·k + t`, so a round's plan and
//! its hash are reproducible; the FE settings (mesh, pressures, solver, contact, gravity, bulk
//! ratio, geometry preset, fixed effects) are the training plan's, so the cases are training
//! cases of the same fidelity and built as the rest. Ids are `10000·k + 5000 + j`: the upper
//! half of round `k`'s block, whose lower half the refinement's rounds use
//! ([`crate::calibrate::refine`]), apart from the training plan's (checked before any FE).
//! Each round's directory is a snapshot shard directory: an interrupted extension resumes
//! where it stopped, reading back every finished case.
//!
//! ## A multi-fidelity model
//!
//! A model corrected by a high-fidelity set ([`crate::rom::fidelity`]) is extended on both
//! meshes, as the refinement refines it: every round's cases run on the low-fidelity mesh
//! (`extend_k/`), and a maximin subset of them, as large a share as the training set's
//! high-fidelity subset (at least one case per `N`), on the high-fidelity mesh
//! (`extend_k_high/`, same ids); the correction and the surrogate are retrained as
//! `surrogate train --high-fidelity` does. Without the high-fidelity cases the correction would
//! extrapolate into the slab, where the box is extended because nothing is known.
//!
//! ## What the stops mean
//!
//! An active bound is one the optimum sits on with the gradient of `χ²` pushing outwards
//! ([`crate::calibrate::optimise`]). Along a direction the recordings do not determine (the
//! calibration's profiles say which), that gradient is small and its sign arbitrary, and the
//! extension follows it to the physical limit; the rounds' table and the profiles of the last
//! calibration show such a walk, and `max_rounds` caps its cost.
//!
//! By concern:
//! - `limits`: how far the box may ever reach ([`PhysicalLimits`]);
//! - `material_box`: the box, its pressed bounds moved, its slabs ([`MaterialBox`],
//!   [`PressedBound`]);
//! - `plan`: a round's cases ([`extension_plan`], [`high_fidelity_plan`]);
//! - `settings`: the settings of an extension ([`ExtendSettings`]);
//! - `run`: the rounds, until a stop ([`extend_box`], [`ExtendEvent`]);
//! - `report`: what the rounds found ([`BoxExtension`], [`ExtendRound`], [`ExtendStop`]).
//!
//! ```no_run
//! use std::path::Path;
//! use surrogate::calibrate::extend::{extend_box, ExtendSettings};
//! use surrogate::calibrate::refine::TrainingSet;
//! use surrogate::calibrate::Recordings;
//! use surrogate::rom::Surrogate;
//! use surrogate::snapshots::fe_runner::fe_runner;
//!
//! let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json"))?;
//! let training = TrainingSet::of_model(&model, Path::new("."))?;
//! let rec = Recordings::shipped()?;
//! let dir = Path::new("calibration/extend");
//! let e = extend_box(&model, &training, &rec, &ExtendSettings::default(), &fe_runner, dir, &|_| {})?;
//! print!("{}", e.summary_markdown());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod limits;
mod material_box;
mod plan;
mod report;
mod run;
mod settings;

pub use limits::PhysicalLimits;
pub use material_box::{MaterialBox, PressedBound};
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub use material_box::allocate;
pub use plan::{extension_case_id, extension_plan, high_fidelity_cases, high_fidelity_plan};
pub use report::{BoxExtension, ExtendRound, ExtendStop, FailedCase, Optimum, FORMAT, VERSION};
pub use run::{extend_box, ExtendEvent};
pub use settings::{ExtendSettings, MAX_CASES_PER_ROUND};
