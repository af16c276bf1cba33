//! Fitting the material to the experiments, through the surrogate, verified by the FE model.
//!
//! ```text
//!   Recordings (bending, force, markers) ──► checks (inconsistent rows flagged)
//!        │ selection, exclusions, weights
//!        ▼
//!   ObservationSet ──► Evaluator: whitened residuals r(u), ∂r/∂u through the surrogate
//!        │
//!        ▼
//!   multistart bounded Levenberg–Marquardt in the training domain ──► best set + every end point
//!        │
//!        ├─► identifiability: Cov = ŝ²(JᵀJ)⁻¹, correlations, eigen-directions, profiles,
//!        │                    extra measurements that would determine what is left
//!        ├─► the study's procedure: per-configuration fits in ±10 % of Ogden 002, their spread
//!        ├─► FE verification at the optimum (the baseline sweep, cached and resumable)
//!        ├─► refinement: FE at the optimum as training cases, retrain, refit (refine)
//!        └─► box extension: where the optimum presses a bound, new cases beyond it, retrain,
//!            refit (extend)
//!
//!   twin: FE ramps with concealed effects (the same sweep) + noise ──► recordings in the
//!         experiments' format, the key apart
//! ```
//!
//! [`fit::calibrate`] runs the whole pipeline and returns a [`fit::Calibration`] report; each
//! stage is a public function a design loop can call on its own.
//!
//! ```no_run
//! use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings};
//! use surrogate::rom::Surrogate;
//!
//! let model = Surrogate::load(std::path::Path::new("models/actuator.json"))?;
//! let cal = calibrate(&model, &Recordings::shipped()?, &CalibrationSettings::default(), &|_| {})?;
//! println!("best set {:?}, mean BE {:.2} mm", cal.best, cal.calibrated.mean_be_mm);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
use thiserror::Error;

pub mod baseline;
pub mod checks;
pub mod coverage;
pub mod experiments;
pub mod extend;
pub mod fit;
pub mod identify;
pub mod inputs;
pub mod joint;
pub mod objective;
pub mod optimise;
pub mod params;
mod recording_csv;
pub mod refine;
pub mod study;
pub mod summary;
pub mod synthetic;
pub mod twin;
pub mod units;
pub mod verdict;
pub mod verify;

pub use fit::{calibrate, Calibration, CalibrationSettings};
pub use objective::{Recordings, Selection, Weights};
pub use params::{MaterialCoords, OgdenSet, ParamSpace};

/// Errors of the calibration.
#[derive(Debug, Error)]
pub enum CalibrateError {
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
    /// A recording that cannot be used, by file, line and column.
    #[error("{source_name}, line {line}, column {column}: {reason}")]
    Record {
        /// File.
        source_name: String,
        /// 1-based line (header = 1).
        line: usize,
        /// Column.
        column: String,
        /// What is wrong.
        reason: String,
    },
    /// Recordings outside the surrogate's domain, every row named.
    #[error(
        "{} recorded rows lie outside the surrogate's domain:\n  - {}\nexclude them to go on \
         without them: {excludes}",
        rows.len(),
        rows.join("\n  - ")
    )]
    OutsideDomain {
        /// Each row: file, line, column, value and the domain.
        rows: Vec<String>,
        /// The `--exclude` flags that leave them out.
        excludes: String,
    },
    /// Reading the experiment files.
    #[error(transparent)]
    Experiments(#[from] experiments::ExperimentError),
    /// A surrogate query.
    #[error(transparent)]
    Rom(#[from] crate::rom::RomError),
    /// The FE verification.
    #[error(transparent)]
    Baseline(#[from] baseline::BaselineError),
}

/// A case value the ground floor rejects (an inadmissible Ogden set) is a bad input of the
/// calibration: the same field, value and expectation.
impl From<crate::case::CaseError> for CalibrateError {
    fn from(e: crate::case::CaseError) -> Self {
        match e {
            crate::case::CaseError::Input {
                field,
                value,
                expected,
            } => CalibrateError::Input {
                field,
                value,
                expected,
            },
        }
    }
}

impl CalibrateError {
    pub(crate) fn input(field: &str, value: impl std::fmt::Display, expected: &str) -> Self {
        CalibrateError::Input {
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }
}
