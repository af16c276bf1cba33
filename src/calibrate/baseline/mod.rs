//! The literature baseline: the full FE model (with contact) against every experimental
//! configuration, for one material set.
//!
//! For each design (N, T) of the shipped experiments, one bending ramp and one blocked-force
//! ramp through 0 and the measured pressures; per (N, T, P) the simulated and measured tip
//! Uz, Uy, angle, the tip bending error `BE` and the force error `F_sim − F_exp`.
//!
//! The settings shared by every ramp ([`SweepSettings`]: material, geometry, mesh, contact,
//! effects, solver, gravity, sensitivities) travel together, so an effect of the library
//! ([`crate::fe::effects`]) reaches every case of the sweep. [`run_ramps`] is the sweep itself
//! (designs and pressures in, ramps out), for other users of the same cached ramps (twin
//! recordings, [`crate::calibrate::twin`]).
//!
//! The sweep runs on the FE campaign runner ([`crate::fe::runner`]). With a cache directory
//! every finished ramp is written there atomically (one JSON per design and mode, keyed by
//! everything that defines the ramp: [`crate::fe::runner::cache`]), and a later run with the
//! same settings takes it from there: a long standard-mesh sweep resumes after an
//! interruption. Neutral settings (no effect, the as-modelled geometry, no sensitivities) add
//! nothing to the key, so the caches committed under `fe_reference/` are read as they are
//! (tested).
//!
//! By concern:
//! - `settings`: the settings shared by every ramp and the designs of a sweep
//!   ([`SweepSettings`], [`SweepDesign`], [`recorded_designs`]);
//! - `cache`: the errors of a sweep ([`BaselineError`]; the cache itself is the runner's);
//! - `ramps`: the ramps of a sweep, run in parallel or read from the cache ([`run_ramps`],
//!   [`cached_ramps`], [`SweepRamp`]): the runner's cases, store and start;
//! - `sensitivities`: the file of a sweep's sensitivities ([`SweepSensitivities`]);
//! - `report`: the comparison with the recordings, row by row and summarised
//!   ([`run_baseline`], [`BaselineRow`], [`summarize`]).

mod cache;
mod ramps;
mod report;
mod sensitivities;
mod settings;

pub use cache::BaselineError;
pub use ramps::{cached_ramps, run_ramps, RampSource, SweepRamp};
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub use ramps::cost_order;
pub use report::{
    cached_baseline, in_paper_nine, run_baseline, summarize, BaselineRow, BaselineSummary,
};
pub use sensitivities::{
    DesignSensitivities, SweepSensitivities, SWEEP_SENSITIVITY_FORMAT, SWEEP_SENSITIVITY_VERSION,
};
pub use settings::{
    recorded_designs, SweepDesign, SweepSettings, SWEEP_MAX_PRESSURE_INCREMENT, SWEEP_RTOL,
};
