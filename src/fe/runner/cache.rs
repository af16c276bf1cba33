//! The ramp cache: a directory of FE ramps, one JSON file per ramp (design and mode, with or
//! without sensitivities), keyed by everything that defines the ramp, written atomically and
//! read back only under the same key.
//!
//! The file of design `(N, T)` in `mode` is `n{N}_t{T}_{mode}.json`
//! (`n11_t2_force.json`), `…_{mode}_sensitivities.json` with sensitivities; it holds
//! `{"key": …, "steps": […], "error": "…", "sensitivities": …}`. The key is the JSON text of
//! the code version, design, material, pressures, gravity, mesh, solver, mode and contact
//! settings (and the force plate's revision in the blocked-force rig); a design of another
//! geometry than the historical one adds every dimension, effects that are not neutral add
//! themselves, sensitivities add their parameters and method. A neutral case keeps the key it
//! had before those existed, so caches written then are read as they are. A file that is
//! missing, damaged or of another key is not held: the ramp runs again and replaces it.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::batch::Store;
use super::ramp::{Ramp, RampCase};
use crate::fe::geometry::DesignParams;
use crate::fe::sensitivity::{
    Parameter, Sensitivities, SENSITIVITY_FORMAT_VERSION, SENSITIVITY_METHOD,
};
use crate::fe::simulate::{Case, Mode, StepResult, FORCE_MODEL_REVISION};

/// A ramp cache that cannot be written.
#[derive(Debug, thiserror::Error)]
#[error("ramp cache {path}: {message}")]
pub struct RampCacheError {
    /// File or directory.
    pub path: String,
    /// What failed.
    pub message: String,
}

impl RampCacheError {
    fn at(path: &Path, e: impl std::fmt::Display) -> Self {
        Self {
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

/// Where one ramp is cached, and its key.
#[derive(Clone, Debug)]
pub struct RampFile {
    /// The file.
    pub path: PathBuf,
    key: String,
}

impl RampFile {
    /// The file of `case` (with the sensitivities to `sensitivities`) in `dir`.
    pub fn at(dir: &Path, case: &Case, sensitivities: &[Parameter]) -> Self {
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
        RampFile {
            path: dir.join(format!(
                "n{}_t{}_{mode}{suffix}.json",
                p.n_bellows, p.wall_thickness
            )),
            key,
        }
    }

    /// The cached ramp if the file exists, parses and carries the same key (its steps, the
    /// solver's message if it stopped, its sensitivities; no solver account).
    pub fn load(&self) -> Option<Ramp> {
        let text = std::fs::read_to_string(&self.path).ok()?;
        let c: CachedRamp = serde_json::from_str(&text).ok()?;
        (c.key == self.key).then(|| Ramp {
            steps: c.steps,
            error: (!c.error.is_empty()).then_some(c.error),
            sensitivities: c.sensitivities,
            response: None,
        })
    }

    /// Writes `ramp` under this key, atomically.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn store(&self, ramp: &Ramp) -> Result<(), RampCacheError> {
        let c = CachedRamp {
            key: self.key.clone(),
            steps: ramp.steps.clone(),
            error: ramp.error.clone().unwrap_or_default(),
            sensitivities: ramp.sensitivities.clone(),
        };
        let text = serde_json::to_string(&c).map_err(|e| RampCacheError::at(&self.path, e))?;
        crate::io::write_atomic(&self.path, text.as_bytes())
            .map_err(|e| RampCacheError::at(&self.path, e))
    }
}

/// A ramp cache directory as a runner's store ([`Store`]).
#[derive(Clone, Debug)]
pub struct RampDir {
    dir: PathBuf,
}

impl RampDir {
    /// The cache in `dir`, to read (it need not exist: then it holds nothing).
    pub fn at(dir: &Path) -> Self {
        Self {
            dir: dir.to_path_buf(),
        }
    }

    /// The cache in `dir`, to read and write: the directory is created.
    ///
    /// # Errors
    /// The directory cannot be created.
    pub fn create(dir: &Path) -> Result<Self, RampCacheError> {
        std::fs::create_dir_all(dir).map_err(|e| RampCacheError::at(dir, e))?;
        Ok(Self::at(dir))
    }

    /// The file of `case`.
    pub fn file(&self, case: &RampCase) -> RampFile {
        RampFile::at(&self.dir, &case.case, &case.sensitivities)
    }
}

impl Store<RampCase> for RampDir {
    type Ramp = Ramp;
    type Held = Ramp;
    type Error = RampCacheError;

    fn held(&self, case: &RampCase) -> Result<Option<Ramp>, RampCacheError> {
        Ok(self.file(case).load())
    }

    fn keep(&self, case: &RampCase, ramp: &Ramp) -> Result<(), RampCacheError> {
        self.file(case).store(ramp)
    }
}
