//! Joint identification of the material and the dimensions the reference study leaves
//! unstated, straight on the FE model.
//!
//! ## Unknowns
//!
//! `θ` collects the chosen [`Unknown`]s: Ogden parameters (`mu1`, `alpha1`, `mu2`, `alpha2`),
//! the unstated dimensions of the actuator as one [`Geometry`](crate::fe::preset::Geometry) shared by every design
//! (`gap`, `base`, `duct`, `side_wall`, `free_length`, mm), and any effect of the library
//! (`plate_offset` for the force rig's printed square, `wall_bias_bellows`, `clamp_compliance`,
//! …). Each has bounds: the physical range of a dimension ([`crate::fe::preset`]), the range of
//! an effect, and for the material a sign-keeping box around the start
//! (`μᵢ ∈ [μᵢ⁰/5, 5μᵢ⁰]`, `|αᵢ| ∈ [0.5, 12]`).
//!
//! ## Objective
//!
//! The calibrator's noise model ([`super::objective`]) with a model-form floor: per recorded
//! configuration the tip `Uz`, `Uy` with `σ² = (r·σ_α)² + σ_tip²` (`r` the recorded chord,
//! `σ_α` the recorded angle scatter) and the blocked force with `σ² = σ_F² + σ_force²`
//! (`σ_F` its recorded scatter); `r(θ) = (y_FE(θ) − y)/σ`, `χ² = Σ r²`. The floor
//! ([`ModelSigma`], default 2 mm and 0.15 N, the scale of the accuracy wanted) says how far
//! the model may be trusted at best: without it, the forces' recorded scatter (0.03–0.09 N
//! against about 3 mm on a tip) makes the force about ten times heavier than the tips in `χ²`,
//! and the fit buys force with the force rig's plate while the tips stay where they are
//! (measured: `fe_reference/identification/README.md`).
//!
//! ## Method: FE-direct Levenberg–Marquardt
//!
//! Every evaluation of `θ` is one sweep of the FE model over the recorded designs (one bending
//! and one blocked-force ramp per design, [`super::baseline::run_ramps`]) with the direct
//! sensitivities of every output with respect to every unknown ([`crate::fe::sensitivity`]):
//! a dimension `d` of the geometry is differentiated through its bias effect at zero
//! (`∂/∂gap = ∂/∂gap_bias`, `∂/∂side_wall = ∂/∂wall_bias_side`, …). So one sweep gives `r`
//! and the Jacobian `J`, and the step solves
//!
//! ```text
//!   (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr
//! ```
//!
//! solved inside a box: every unknown has its own trust radius (a fraction of its range), so
//! the step is the damped Gauss–Newton step constrained to `|δᵢ| ≤ Δᵢ·rangeᵢ` and to the
//! bounds (a rectangular trust region, as in the "dogbox" method of Voglis and Lagaris). A
//! step is taken when the FE at `θ'` lowers `χ²` (gain ratio `ρ` of actual to linearly
//! predicted decrease `> 0`); `λ` follows Nielsen's rule (`λ·max(1/3, 1 − (2ρ − 1)³)` on
//! success, `λ·ν`, `ν ← 2ν` on failure); the radii of the unknowns the box held halve when the
//! step fails and double when it succeeds with `ρ > 0.5`. A sweep whose FE fails counts as a
//! failed step. It stops when `χ²` falls by less than a relative `1e-3` over an accepted step
//! the box did not hold, when `λ` exceeds `1e8`, or after the iteration budget
//! ([`JointStop`]).
//!
//! Every sweep is cached (sweep `k` in `sweep_k/` of the cache, one file per ramp keyed by
//! everything that defines it, the geometry's every dimension included), so an interrupted
//! identification rerun with the same settings replays the same sequence of steps from the
//! cache and resumes where it stopped.
//!
//! ## What the data determine
//!
//! At the optimum, `C = (JᵀJ)⁻¹` (residuals are already in units of σ) gives each unknown's
//! standard error and the correlations; an unknown on a bound is reported as such.
//!
//! ## Files
//!
//! - `correction`: the mesh correction, to fit on the coarse mesh what the standard one
//!   gives ([`MeshCorrection`]);
//! - `unknown`: the unknowns, a point of the identification, the bounds;
//! - `settings`: the settings, the model-form floor, how the iteration stops;
//! - `evaluation`: one FE sweep of a point turned into residuals, Jacobian and rows;
//! - `lm`: the bounded Levenberg–Marquardt and its box-constrained step;
//! - `held_out`: the held-out designs' prediction from the linearised refits;
//! - `identify`: [`identify`] and the report of its optimum;
//! - `report`: the report's types, its summary in words and its files.

mod correction;
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub mod evaluation;
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub mod held_out;
mod identify;
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub mod lm;
mod report;
mod settings;
mod unknown;

pub use correction::{CorrectionEntry, MeshCorrection};
pub use evaluation::in_paper_nine;
pub use identify::identify;
pub use report::{HeldOut, JointEstimate, JointReport, JointRow, JointSweep};
pub use settings::{JointSettings, JointStop, ModelSigma, MIN_GAIN_CHI2};
pub use unknown::{bounds, JointPoint, Unknown};
