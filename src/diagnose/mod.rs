//! The discrepancy diagnoser: where the calibrated model misses the recordings, which
//! physics it leaves out, and what adding it gains on data the fit did not see.
//!
//! ```text
//!   (optional) the model's approximation error against a finer reference, sampled at
//!   several materials (approx_error): Recordings corrected by its mean, its covariance
//!   passed to name
//!                                                        │
//!   Recordings ──► calibrate (one material set) ──► Calibration (residuals at the optimum)
//!                                                        │
//!                                                        ▼
//!   locate:  residual table (output × design × pressure × marker), shares of χ²,
//!            structure over N, T, P (and along the actuator), sign patterns,
//!            findings in words, what the recordings lack          ──► Localisation
//!                                                        │
//!            (optional) the model's own mesh error, from a surrogate on another mesh
//!                                                        │          ──► MeshError (mesh_error)
//!                                                        ▼
//!   name:    material re-fit, every effect's FE signature past it (weighed by the
//!            approximation error's covariance), nested F tests under Holm, collinear
//!            pairs, the model's mesh error as a candidate        ──► Naming (name)
//!                                                        │
//!                                                        ▼
//!   model & show: material + effect(s) refitted, size and interval, every design held
//!            out, FE confirmation rounds                          ──► Refit (refit)
//! ```
//!
//! [`diagnose`] runs calibrate → locate and returns a [`Diagnosis`], the versioned report
//! (`format` / `version` fields); [`Diagnosis::mesh_error_with`], [`Diagnosis::name_with`] and
//! [`Diagnosis::refit_with`] run the later stages on it; [`locate()`] is the Locate stage on
//! its own. [`study`] is the blind study on twins. [`setup`] is how a diagnosis is set up (the
//! model, the FE sensitivities, the mesh reference, the approximation error) and its defaults
//! for real recordings and for the blind study.
//!
//! ## Locate: the residual table
//!
//! At the calibrated set `θ̂`, every recorded number `yᵢ` (tip Uz, tip Uy, angle, blocked
//! force, marker components) at its configuration `(N, T, P)` has the standardised residual
//!
//! ```text
//!   zᵢ = (ŷᵢ(θ̂) − yᵢ) / σᵢ,      σᵢ² = σ_meas,ᵢ² + σ_model,ᵢ²
//! ```
//!
//! with the calibrator's noise model ([`crate::calibrate::objective`]). The outputs the fit
//! used come from the [`Calibration`](crate::calibrate::Calibration) itself; the outputs its
//! objective left out (the blocked force under the default `tip` objective, say) are predicted
//! at `θ̂` through the same surrogate and standardised the same way, and flagged as not
//! fitted: they did not pull the material, so their residual is evidence the fit could not
//! hide. The diagnosis' `χ² = Σ zᵢ²` runs over every cell (each recorded number once,
//! unweighted); a cell's share is `zᵢ² / χ²`, and shares add up by output, design `(N, T)`,
//! `N`, `T`, `P` and marker.
//!
//! ## Locate: the statistics
//!
//! Every statement of the report rests on one of three tests, and all of them together form
//! one family whose significance is decided by Holm's step-down procedure at level `α`
//! ([`LocateSettings::alpha`], 0.05 by default): with the `m` p-values sorted, `p₍ₖ₎` is significant
//! while `p₍ⱼ₎ ≤ α / (m − j + 1)` for every `j ≤ k`.
//!
//! 1. **Misfit** of an output: under the noise model `Σ zᵢ² ~ χ²(n)` over its `n` cells
//!    (the 4 fitted parameters are not subtracted, which makes the test conservative).
//! 2. **Structure** of an output: the weighted least-squares fit of the residual to a small
//!    additive model (weights `1/σᵢ²`, i.e. ordinary least squares on `z`)
//!
//!    ```text
//!      zᵢ ≈ β₀ + β_T (Tᵢ − T̄) + β_N (Nᵢ − N̄) + β_P (Pᵢ − P̄) + β_PT (Pᵢ − P̄)(Tᵢ − T̄) [+ β_s (sᵢ − s̄)]
//!    ```
//!
//!    (`sᵢ = k/9`, the marker's position along the actuator, for marker outputs; the bars
//!    are means over the output's cells). Each coefficient gets its standard error
//!    `ŝ √[(XᵀX)⁻¹]ⱼⱼ` with `ŝ² = RSS / (n − p)`, and a two-sided Student-t test with `n − p`
//!    degrees of freedom: the scale is estimated from what the structure leaves, so a term
//!    is significant when it stands out of the unstructured scatter, however large the misfit
//!    is against the recordings' own σ. The fraction of the output's χ² a structure explains
//!    is `1 − RSS / Σ zᵢ²` (the constant counts as structure: a uniform offset is one).
//!    A regressor with one level on these recordings, or confounded with the others, is
//!    dropped and the report says so.
//! 3. **Group means**: for every output and every group of cells sharing a `T`, an `N`, a `P`,
//!    a design or a marker, `Z = Σ zᵢ / √n ~ N(0, 1)` under the noise model. A significant
//!    group with at least 80 % of its cells (and at least 3; all of them below 5) on the side
//!    of its mean is a sign pattern ("the tip bends too far for T = 1.6 mm at 8 of 9 cells");
//!    where two bending outputs (tip Uz, tip Uy, angle, markers) agree on a group it is said
//!    of the bending as a whole, and a design inside a T or N that says the same is not
//!    repeated.
//!
//! The findings are sentences built from these numbers only: each one names its test
//! statistic, and when no test is significant the report says that the residuals are
//! consistent with the recordings' scatter, or that they exceed it without a structure
//! over N, T and P.
//!
//! ## What the recordings lack
//!
//! [`Localisation::missing`] lists what the diagnosis could not use: no (or partial)
//! blocked-force recordings, no marker recordings (then nothing can be located along the
//! actuator), designs and pressures of the shipped experiments' plan (9 designs × 1, 2,
//! 3 bar) that are absent, rows outside the surrogate's domain and rows the calibration
//! excluded.
use thiserror::Error;

pub mod approx_error;
pub mod cells;
pub mod coverage;
pub mod discrimination;
pub mod findings;
pub mod groups;
pub mod locate;
pub mod measure_design;
pub mod measurements;
pub mod mesh_error;
pub mod name;
pub mod patterns;
pub mod refit;
pub mod report;
pub mod setup;
pub mod signature;
mod stages;
pub mod structure;
pub mod study;
pub mod summary;
pub mod sweep;
pub mod wording;

pub use locate::{locate, Localisation, LocateSettings};
pub use report::{diagnose, DiagnoseSettings, Diagnosis};

/// Errors of the diagnosis.
#[derive(Debug, Error)]
pub enum DiagnoseError {
    /// A bad setting or value.
    #[error("{field} = {value}: expected {expected}")]
    Input {
        /// What was given.
        field: String,
        /// Its value.
        value: String,
        /// What is allowed.
        expected: String,
    },
    /// FE sensitivities of another actuator than the model's: their sweep's geometry or fixed
    /// effects are not those the model's training cases were built with
    /// ([`sweep::check_built_as`]).
    #[error(
        "the FE sensitivities were computed with {what} {sweep}, the model's training cases \
         were built with {what} {model}: a sweep of another actuator than the model's \
         (`--sensitivities calibrated` computes one on the model's)"
    )]
    SweepBuiltOtherwise {
        /// `geometry` or `fixed effects`.
        what: &'static str,
        /// The sweep's, in words.
        sweep: String,
        /// The model's, in words.
        model: String,
    },
    /// The calibration, or a surrogate query made through it.
    #[error(transparent)]
    Calibrate(#[from] crate::calibrate::CalibrateError),
    /// A report that cannot be written or read as JSON.
    #[error("diagnosis report JSON: {0}")]
    Json(#[from] serde_json::Error),
}

impl DiagnoseError {
    pub(crate) fn input(field: &str, value: impl std::fmt::Display, expected: &str) -> Self {
        DiagnoseError::Input {
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }
}
