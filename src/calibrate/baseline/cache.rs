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

/// One ramp's cache file seen as the sweep saw it before the runner existed (steps, the
/// solver's message or "", sensitivities), for the tests of the committed caches' keys.
#[cfg(test)]
pub(super) struct RampCache {
    pub(super) path: std::path::PathBuf,
    file: crate::fe::runner::RampFile,
}

/// What a cached ramp holds: its steps, the solver's message if it stopped, its
/// sensitivities if asked for.
#[cfg(test)]
pub(super) type RampOutcome = (
    Vec<crate::fe::simulate::StepResult>,
    String,
    Option<crate::fe::sensitivity::Sensitivities>,
);

#[cfg(test)]
impl RampCache {
    pub(super) fn at(
        dir: &Path,
        case: &crate::fe::simulate::Case,
        sensitivities: &[crate::fe::sensitivity::Parameter],
    ) -> Self {
        let file = crate::fe::runner::RampFile::at(dir, case, sensitivities);
        Self {
            path: file.path.clone(),
            file,
        }
    }

    pub(super) fn load(&self) -> Option<RampOutcome> {
        let r = self.file.load()?;
        Some((r.steps, r.error.unwrap_or_default(), r.sensitivities))
    }

    pub(super) fn store(&self, r: &RampOutcome) -> Result<(), BaselineError> {
        let ramp = crate::fe::runner::Ramp {
            steps: r.0.clone(),
            error: (!r.1.is_empty()).then(|| r.1.clone()),
            sensitivities: r.2.clone(),
            response: None,
        };
        Ok(self.file.store(&ramp)?)
    }
}
