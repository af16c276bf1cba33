//! The ramp cache: one JSON file per ramp (design and mode, with or without sensitivities),
//! keyed by everything that defines the ramp, written atomically and read back only under the
//! same key; and the errors of a sweep.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::fe::geometry::DesignParams;
use crate::fe::sensitivity::{
    Parameter, Sensitivities, SENSITIVITY_FORMAT_VERSION, SENSITIVITY_METHOD,
};
use crate::fe::simulate::{Case, Mode, SimulateError, StepResult, FORCE_MODEL_REVISION};

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

/// A cached ramp: the key (everything that defines it) and its outcome.
#[derive(Serialize, Deserialize)]
struct CachedRamp {
    key: String,
    steps: Vec<StepResult>,
    error: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    sensitivities: Option<Sensitivities>,
}

/// What a cached ramp holds: its steps, the solver's message if it stopped, its
/// sensitivities if asked for.
pub(super) type RampOutcome = (Vec<StepResult>, String, Option<Sensitivities>);

/// Where one ramp of the baseline is cached, and its key.
pub(super) struct RampCache {
    pub(super) path: PathBuf,
    key: String,
}

impl RampCache {
    pub(super) fn at(dir: &Path, case: &Case, sensitivities: &[Parameter]) -> Self {
        let mode = match case.mode {
            Mode::Bending => "bending",
            Mode::Force => "force",
        };
        let p = case.design.params();
        let mut key = serde_json::json!({
            "code_version": env!("CARGO_PKG_VERSION"),
            "design": [p.n_bellows, p.wall_thickness],
            "material": case.material,
            "pressures_bar": case.pressures_bar,
            "gravity": case.gravity,
            "mesh": case.mesh,
            "solver": case.solver,
            "mode": mode,
            "contact": case.contact,
        });
        if case.mode == Mode::Force {
            key["plate_revision"] = FORCE_MODEL_REVISION.into();
        }
        // a design of another geometry than the historical one ([`Geometry`]) is keyed by
        // every dimension; the historical designs keep their key (and the committed caches)
        if *p != DesignParams::new(p.n_bellows, p.wall_thickness) {
            key["design_params"] = serde_json::to_value(p).unwrap_or_default();
        }
        // a neutral case keeps the key (and the cache) it had before effects existed
        if !case.effects.is_neutral() {
            key["effects"] = serde_json::to_value(&case.effects).unwrap_or_default();
        }
        // a ramp with sensitivities has its own file and key (a plain one keeps its own)
        let suffix = if sensitivities.is_empty() {
            String::new()
        } else {
            key["sensitivities"] = serde_json::to_value(sensitivities).unwrap_or_default();
            key["sensitivity_version"] = SENSITIVITY_FORMAT_VERSION.into();
            key["sensitivity_method"] = SENSITIVITY_METHOD.into();
            "_sensitivities".into()
        };
        let key = key.to_string();
        RampCache {
            path: dir.join(format!(
                "n{}_t{}_{mode}{suffix}.json",
                p.n_bellows, p.wall_thickness
            )),
            key,
        }
    }

    /// The cached outcome if the file exists, parses and carries the same key.
    pub(super) fn load(&self) -> Option<RampOutcome> {
        let text = std::fs::read_to_string(&self.path).ok()?;
        let c: CachedRamp = serde_json::from_str(&text).ok()?;
        (c.key == self.key).then_some((c.steps, c.error, c.sensitivities))
    }

    pub(super) fn store(&self, r: &RampOutcome) -> Result<(), BaselineError> {
        let c = CachedRamp {
            key: self.key.clone(),
            steps: r.0.clone(),
            error: r.1.clone(),
            sensitivities: r.2.clone(),
        };
        let text = serde_json::to_string(&c).map_err(|e| BaselineError::cache(&self.path, e))?;
        crate::io::write_atomic(&self.path, text.as_bytes())
            .map_err(|e| BaselineError::cache(&self.path, e))
    }
}
