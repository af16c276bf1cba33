//! Crate-wide error type: one variant per module error.

use thiserror::Error;

/// Every error the library can return.
#[derive(Debug, Error)]
pub enum Error {
    /// Invalid material parameters or an unknown material name.
    #[error(transparent)]
    Material(#[from] crate::fe::material::MaterialError),
    /// Reduced-order model: snapshot data, training, model files, queries.
    #[error(transparent)]
    Rom(#[from] crate::rom::RomError),
    /// Calibration of the material to recordings.
    #[error(transparent)]
    Calibrate(#[from] crate::calibrate::CalibrateError),
    /// Sampling plans, snapshot directories and merges.
    #[error(transparent)]
    Snapshots(#[from] crate::snapshots::SnapshotError),
    /// Input/output failure with the path involved.
    #[error("{path}: {source}")]
    Io {
        /// File or directory involved.
        path: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
