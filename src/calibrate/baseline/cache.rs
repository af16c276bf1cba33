//! The errors of a sweep; its ramp cache is the FE runner's ([`crate::fe::runner::cache`]:
//! one JSON file per ramp, keyed by everything that defines it, written atomically and read
//! back only under the same key).

use std::path::Path;

use thiserror::Error;

use crate::fe::runner::RampCacheError;
use crate::fe::simulate::SimulateError;

/// Errors of [`run_baseline`](super::run_baseline).
#[derive(Debug, Error)]
pub enum BaselineError {
    /// A design or solver setting error.
    #[error(transparent)]
    Simulate(#[from] SimulateError),
    /// The ramp cache could not be written.
    #[error("ramp cache {path}: {message}")]
    Cache {
        /// File or directory.
        path: String,
        /// What failed.
        message: String,
    },
}

impl BaselineError {
    pub(super) fn cache(path: &Path, e: impl std::fmt::Display) -> Self {
        BaselineError::Cache {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    }
}

impl From<RampCacheError> for BaselineError {
    fn from(e: RampCacheError) -> Self {
        BaselineError::Cache {
            path: e.path,
            message: e.message,
        }
    }
}
