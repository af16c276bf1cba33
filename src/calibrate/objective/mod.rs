//! What the fit compares: recordings → selected, standardised observations → residuals and
//! their Jacobian through the surrogate.
//!
//! ## The objective
//!
//! Every recorded number `yᵢ` (tip Uz, tip Uy, angle, blocked force, marker components) at its
//! configuration `(N, T, P)` gives one residual
//!
//! ```text
//!   rᵢ(θ) = √wᵢ · (ŷᵢ(θ) − yᵢ) / σᵢ,      σᵢ² = σ_meas,ᵢ² + σ_model,ᵢ²,      χ²(θ) = Σ rᵢ²
//! ```
//!
//! with `ŷ` the surrogate's prediction, `wᵢ` the weight of the output's term ([`Weights`]) and
//! `σᵢ` its standard deviation.
//!
//! ## Noise model
//!
//! - **angle**: the recorded standard deviation (`angle_std_deg`, the scatter of the 3
//!   specimens × 3 repetitions about their mean; a single test's scatter, not the standard
//!   error of the mean, because specimen-to-specimen differences do not average out over
//!   three specimens).
//! - **tip Uz, Uy**: the files give no standard deviation for the tip. The tip lies on the
//!   deformed chord from the support, of length `r = √((L_f − Uz)² + Uy²)` (L_f = 92 mm); a
//!   scatter `σ_α` of the angle moves it by `r·σ_α` (radians) across the chord. That value is
//!   taken for both components (isotropic: the scatter along the chord is not recorded, and
//!   this bound is the larger one).
//! - **force**: the recorded `force_std_n`.
//! - **markers**: the recorded `std_mm` of each component.
//! - **model**: the surrogate's own held-out RMSE of the output (stored in the model file) is
//!   added in quadrature, so that the fit does not chase the surrogate's error.
//!
//! Tip and angle carry largely the same information (the angle follows from the tip): `all`
//! counts it twice, which doubles its weight relative to the force; choose weights to suit.
//!
//! By concern:
//! - `terms`: what is recorded and how much each term counts ([`Output`], [`Term`],
//!   [`Weights`]);
//! - `selection`: configurations, exclusions and the selection of rows ([`Config`],
//!   [`Recording`], [`Exclusion`], [`Selection`]);
//! - `recordings`: the recordings a calibration reads ([`Recordings`]);
//! - `observations`: the standardised observations, checked against the model's domain
//!   ([`Observation`], [`ObservationSet`]);
//! - `evaluator`: residuals and their Jacobian through the surrogate ([`Evaluator`]).

mod evaluator;
mod observations;
mod recordings;
mod selection;
mod terms;

pub use evaluator::Evaluator;
pub use observations::{Observation, ObservationSet};
pub use recordings::Recordings;
pub use selection::{Config, Exclusion, Recording, Selection};
pub use terms::{Output, Term, Weights};

/// Free length used to derive the tip's standard deviation (mm).
pub use super::units::FREE_LENGTH_MM;
