//! Design through the surrogate: the number of bellows `N` and the wall thickness `T` that
//! reach target outputs, and maps of the outputs over `(N, T, P)`.
//!
//! ## The objective
//!
//! A designer states targets `k = 1 … K`: an output `y_k` (tip Uz, tip Uy, bending angle or
//! blocked force), a pressure `P_k`, a value `v_k` and a tolerance `s_k > 0`, the scale of
//! that residual (1° for an angle, 0.05 N for a force). With the material `m` fixed, a design
//! `(N, T)` costs
//!
//! ```text
//!   Φ(N, T) = Σ_k r_k²,    r_k = (y_k(N, T, P_k, m) − v_k) / s_k
//! ```
//!
//! where `y_k` is the surrogate's prediction ([`Surrogate`]). `N` is discrete: [`search`]
//! minimises `Φ` in `T` for every `N` the model predicts inside the bounds, and picks the
//! `N` of least cost.
//!
//! ## The search in `T`
//!
//! For one `N`, `T` lies in `[T_lo, T_hi(N)]`: the designer's bounds, the model's range of
//! `T` ([`Surrogate::domain`]) and the largest wall that leaves a cavity with the geometry
//! the model was trained on ([`max_wall_thickness_in`]; [`TrainingInfo::built_with`], else
//! the geometry as modelled). Gauss–Newton on the scaled residuals with the surrogate's
//! analytic derivative `J_k = ∂r_k/∂T = (∂y_k/∂T)/s_k` ([`Surrogate::gradient_range_into`]),
//!
//! ```text
//!   ΔT = − Σ_k J_k r_k / Σ_k J_k²,    T ← clamp(T + λ ΔT, T_lo, T_hi(N)),
//! ```
//!
//! with `λ = 1, ½, ¼, …` until `Φ` does not grow, runs from every local minimum of `Φ` over
//! a scan of [`DesignSearch::starts`] values spread evenly over the interval (values only,
//! through the scalar fast path [`Surrogate::predict_scalars_into`]: one descent per basin the
//! scan sees, not one per start), and keeps the end point of least cost. It stops when the
//! step is below [`DesignSearch::step_tolerance_mm`], when it stands on a bound and the
//! descent points out of the interval, when no shortened step lowers `Φ`, when the
//! derivative vanishes, or after [`DesignSearch::max_iterations`] ([`Stop`]). An optimum on a
//! bound is reported with the bound and what sets it ([`BoundHit`]): a target no design
//! reaches drives `T` to the end that comes closest.
//!
//! The scan and the descents evaluate the surrogate into one
//! [`Prediction`](crate::rom::Prediction) and one [`Jacobian`](crate::rom::Jacobian), once per
//! distinct target pressure and trial wall, without allocating.
//!
//! ## Two errors of the pick
//!
//! The pick is reported with the surrogate's standard deviation at each target (its error
//! against the FE model, [`Surrogate::predict_with_std_into`]) and the model-form error the
//! model file carries (how far the calibrated model misses recorded actuators,
//! [`crate::rom::model_form`]); without one, the accuracy against real actuators is unknown
//! ([`Accuracy`]).
//!
//! ## Maps
//!
//! [`map`] evaluates outputs over a grid of `N`, `T` and `P` for figures, NaN where `T` is
//! beyond the buildable wall of `N`.
//!
//! ## Example
//!
//! ```
//! use surrogate::case::OgdenSet;
//! use surrogate::design::{search, DesignBounds, DesignSearch, Output, Target};
//! use surrogate::rom::Surrogate;
//!
//! let model = Surrogate::load(std::path::Path::new("models/actuator.json"))?;
//! // the set calibrated through the shipped model (`fe_reference/identification/shipped_surrogate/`)
//! let material = OgdenSet::from_array([0.2108, 18.1271, -1.2232, -1.9958]);
//! let targets = [
//!     Target::new(Output::AngleDeg, 2.0, 40.0, 1.0),
//!     Target::new(Output::ForceN, 2.0, 1.3, 0.05),
//! ];
//! let bounds = DesignBounds::of_model(&model);
//! let report = search(&model, material, &targets, &bounds, &DesignSearch::default())?;
//! for d in &report.designs {
//!     if let Some(c) = &d.best {
//!         println!("N = {}: T = {:.3} mm, cost {:.2}", d.n, c.t_mm, c.cost);
//!     }
//! }
//! let pick = &report.pick;
//! assert!(model.n_allowed.contains(&pick.n));
//! println!("pick: N = {}, T = {:.2} mm ({})", pick.n, pick.t_mm, report.accuracy);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`Surrogate`]: crate::rom::Surrogate
//! [`Surrogate::domain`]: crate::rom::Surrogate::domain
//! [`Surrogate::gradient_range_into`]: crate::rom::Surrogate::gradient_range_into
//! [`Surrogate::predict_scalars_into`]: crate::rom::Surrogate::predict_scalars_into
//! [`Surrogate::predict_with_std_into`]: crate::rom::Surrogate::predict_with_std_into
//! [`max_wall_thickness_in`]: crate::snapshots::plan::max_wall_thickness_in
//! [`TrainingInfo::built_with`]: crate::rom::provenance::TrainingInfo::built_with

mod map;
mod problem;
mod report;
mod search;
mod target;

pub use map::{map, DesignMap};
pub use report::{
    Accuracy, BoundHit, Candidate, DesignAtN, DesignReport, Evaluations, Pick, PickedOutput, Side,
    Stop, TLimit,
};
pub use search::search;
pub use target::{DesignBounds, DesignSearch, Output, Target};

use thiserror::Error;

use crate::rom::RomError;

/// Errors of the design search and maps.
#[derive(Debug, Error)]
pub enum DesignError {
    /// An invalid target, bound, setting, grid or material.
    #[error("{field} = {value}: expected {expected}")]
    Invalid {
        /// The field (`targets[0].p_bar`, `bounds.n`, `material`, …).
        field: String,
        /// The offending value.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// No `N` inside the bounds has a buildable wall inside the bounds of `T`.
    #[error("no buildable design: {0}")]
    NoBuildableDesign(String),
    /// The surrogate refused a query.
    #[error(transparent)]
    Rom(#[from] RomError),
}

impl DesignError {
    fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        expected: impl Into<String>,
    ) -> Self {
        DesignError::Invalid {
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}
