//! Adaptive refinement: where the surrogate and the FE model disagree at the calibrated set,
//! the FE runs at that set become training cases, the surrogate is retrained and the material
//! refitted, round after round, until the two agree.
//!
//! ```text
//!   model M₀, its training set S₀ ──► calibrate ──► θ₀
//!   round k = 1, 2, …:
//!     FE ramps of every recorded design at θ_{k−1} (the training plan's settings and pressures,
//!     run as a snapshot plan: cached per case, resumable) ──► compare with M_{k−1} at θ_{k−1}
//!       agree (every |FE − surrogate| ≤ 2σ of the surrogate)      ──► stop: Agree
//!       k = max_rounds                                             ──► stop: MaxRounds
//!     S_k = S_{k−1} + the round's cases ──► retrain M_k ──► calibrate ──► θ_k
//!       θ_k = θ_{k−1} (as reported, 4 significant digits)          ──► stop: OptimumUnchanged
//!       M_k(θ_k) − M_k(θ_{k−1}) within noise on every recorded number ──► stop: PredictionsUnchanged
//! ```
//!
//! The last test is the one that ends a refinement whose data leave a direction of the
//! parameters undetermined: the refit then walks along that valley from round to round (another
//! split of the initial shear modulus between the two Ogden terms, say) while nothing the
//! recordings see changes. Through the retrained surrogate `M_k`, every recorded number
//! (tip, angle, force, markers: whatever the recordings hold, at the calibration's
//! configurations) is predicted at the refit `θ_k` and at the verified `θ_{k−1}`; when no
//! prediction moves by more than `data_tolerance` of its standard deviation (the calibrator's
//! noise model, [`super::objective`]), the two sets are the same answer to these recordings,
//! and the FE at `θ_{k−1}` (already run) verifies it ([`data_space_shift`]).
//!
//! The FE cases of a round are a [`Plan`] with the training plan's settings (mesh, pressures,
//! solver, contact, gravity, bulk ratio), so they are training cases of the same fidelity as the
//! rest; their ids are `10000·k + j` (the recorded designs in (N, T) order), apart from the
//! training plan's. Each round's directory is a snapshot shard directory
//! ([`crate::snapshots::run::run_shard`]): an interrupted refinement resumes where it stopped.
//!
//! A multi-fidelity model (a low-fidelity set corrected by a high-fidelity one,
//! [`crate::rom::fidelity`]) is refined on both of its meshes: every round runs each design on
//! the low-fidelity mesh (`round_k_low/`) and on the high-fidelity one (`round_k/`, the FE the
//! surrogate is compared with), the pair is added to both sets under one id, and the correction
//! and the surrogate are retrained as `surrogate train --high-fidelity` does.
//!
//! By concern:
//! - `settings`: the settings of a refinement ([`RefineSettings`]);
//! - `training`: the training set, the surrogate retrained on it and a round's plan run as a
//!   snapshot shard ([`TrainingSet`], [`HighFidelity`]; the box extension,
//!   [`super::extend`], retrains and runs its rounds through the same two functions);
//! - `cases`: the FE cases of a round and their rows against the experiments ([`round_plan`],
//!   [`case_at`], [`recorded_designs`], [`baseline_rows`]);
//! - `shift`: how far a refit moved in what the recordings see ([`data_space_shift`],
//!   [`DataSpaceShift`]);
//! - `run`: the rounds, until a stop ([`refine`], [`RefineEvent`]);
//! - `report`: what the rounds found ([`Refinement`], [`RefineRound`], [`RefineStop`]).
//!
//! [`Plan`]: crate::snapshots::plan::Plan

mod cases;
mod report;
mod run;
mod settings;
mod shift;
mod training;

pub use cases::{baseline_rows, case_at, recorded_designs, round_plan};
pub use report::{RefineRound, RefineStop, Refinement};
pub use run::{refine, RefineEvent};
pub use settings::RefineSettings;
pub use shift::{data_space_shift, DataSpaceShift};
pub(crate) use training::{run_round_plan, GrownSet, Refit};
pub use training::{HighFidelity, TrainingSet};
