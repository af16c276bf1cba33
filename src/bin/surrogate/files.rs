//! The files the subcommands share: the model they read and the outputs they write.
use std::path::Path;

use anyhow::{Context, Result};
use surrogate::rom::Surrogate;

/// Loads a model file; a missing one says where it was looked for and what to give instead.
pub fn load_model(path: &Path) -> Result<Surrogate> {
    Surrogate::load(path).map_err(|e| {
        if path.exists() {
            anyhow::Error::from(e)
        } else {
            anyhow::anyhow!(
                "{e}; give --model PATH (the shipped models are models/actuator.json and \
                 models/actuator_coarse.json in the repository: run from its root, or give \
                 the full path)"
            )
        }
    })
}

/// Writes `bytes` to a file atomically ([`surrogate::io::write_atomic`]), creating its
/// directory.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    surrogate::io::write_atomic(path, bytes).with_context(|| format!("writing {}", path.display()))
}
