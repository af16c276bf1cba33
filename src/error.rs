//! Crate-wide error type: one variant per module error a caller of the pipeline meets.
//!
//! Library functions return their module's error (`RomError`, `CalibrateError`, …), which
//! names what went wrong where. A program that chains stages (load a model, read recordings,
//! calibrate, simulate) can return [`Result`] and let `?` convert each of them:
//!
//! ```no_run
//! use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings};
//! use surrogate::fe::geometry::DesignParams;
//! use surrogate::rom::Surrogate;
//!
//! fn main() -> surrogate::Result<()> {
//!     let model = Surrogate::load(std::path::Path::new("models/actuator.json"))?; // RomError
//!     let recordings = Recordings::shipped()?; // CalibrateError
//!     let cal = calibrate(&model, &recordings, &CalibrationSettings::default(), &|_| {})?;
//!     let design = DesignParams::default().validate()?; // GeometryError
//!     println!("{:?}, N = {}", cal.best, design.params().n_bellows);
//!     Ok(())
//! }
//! ```

use thiserror::Error;

/// Every error the library's modules return, for callers that chain them.
#[derive(Debug, Error)]
pub enum Error {
    /// A case value that is not admissible (an Ogden set with `μᵢαᵢ ≤ 0`).
    #[error(transparent)]
    Case(#[from] crate::case::CaseError),
    /// An invalid actuator design.
    #[error(transparent)]
    Geometry(#[from] crate::fe::geometry::GeometryError),
    /// Invalid material parameters or an unknown material name.
    #[error(transparent)]
    Material(#[from] crate::fe::material::MaterialError),
    /// An effect setting: unknown name, value out of range, given twice.
    #[error(transparent)]
    Effect(#[from] crate::fe::effects::EffectError),
    /// An FE simulation: its case, or a solve that did not converge.
    #[error(transparent)]
    Simulate(#[from] crate::fe::simulate::SimulateError),
    /// Sampling plans, snapshot directories and merges.
    #[error(transparent)]
    Snapshots(#[from] crate::snapshots::SnapshotError),
    /// Reduced-order model: snapshot data, training, model files, queries.
    #[error(transparent)]
    Rom(#[from] crate::rom::RomError),
    /// Calibration of the material to recordings.
    #[error(transparent)]
    Calibrate(#[from] crate::calibrate::CalibrateError),
    /// Experiment files.
    #[error(transparent)]
    Experiments(#[from] crate::calibrate::experiments::ExperimentError),
    /// The FE baseline sweep against the experiments.
    #[error(transparent)]
    Baseline(#[from] crate::calibrate::baseline::BaselineError),
    /// Twin recordings.
    #[error(transparent)]
    Twin(#[from] crate::calibrate::twin::TwinError),
    /// The design search and maps.
    #[error(transparent)]
    Design(#[from] crate::design::DesignError),
    /// The discrepancy diagnosis.
    #[error(transparent)]
    Diagnose(#[from] crate::diagnose::DiagnoseError),
}

/// Result alias for callers of the library ([`enum@Error`]).
pub type Result<T, E = Error> = std::result::Result<T, E>;
