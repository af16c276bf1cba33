//! Model files: portable, versioned JSON with a checksum.
//!
//! ```text
//! {"format":"surrogate-rom","format_version":2,"checksum":"crc32:1a2b3c4d","model":{…}}
//! ```
//! `model` is the serialised [`Surrogate`] (inputs with units and training bounds, scalers,
//! POD bases, regression weights, validation errors, provenance). The checksum is the CRC-32
//! of the exact text of `model`. Floats are written in shortest round-trip form and parsed
//! exactly (`serde_json/float_roundtrip`), so save → load gives a bit-identical model.
//! Loading rejects: unparsable JSON, another `format`, another `format_version`, a checksum
//! mismatch and an internally inconsistent model, each with a message naming the problem.

use std::path::Path;

use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;

use super::surrogate::Surrogate;
use super::RomError;

/// Format name written in every model file.
pub const FORMAT_NAME: &str = "surrogate-rom";
/// Format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 2;

#[derive(Serialize)]
struct EnvelopeOut<'a> {
    format: &'a str,
    format_version: u32,
    checksum: String,
    model: &'a RawValue,
}

#[derive(Deserialize)]
struct EnvelopeIn<'a> {
    format: String,
    format_version: u32,
    checksum: String,
    #[serde(borrow)]
    model: &'a RawValue,
}

fn checksum(text: &str) -> String {
    format!("crc32:{:08x}", crc32fast::hash(text.as_bytes()))
}

impl Surrogate {
    /// The model file text.
    ///
    /// # Errors
    /// Serialisation failure (non-finite numbers).
    pub fn to_json(&self) -> Result<String, RomError> {
        let err = |e: serde_json::Error| RomError::ModelFile {
            path: "<memory>".into(),
            message: e.to_string(),
        };
        let model = serde_json::to_string(self).map_err(err)?;
        let raw = RawValue::from_string(model).map_err(err)?;
        let env = EnvelopeOut {
            format: FORMAT_NAME,
            format_version: FORMAT_VERSION,
            checksum: checksum(raw.get()),
            model: &raw,
        };
        serde_json::to_string(&env).map_err(err)
    }

    /// The checksum (`crc32:…`) the model file of this model carries.
    ///
    /// # Errors
    /// Serialisation failure.
    pub fn checksum(&self) -> Result<String, RomError> {
        let model = serde_json::to_string(self).map_err(|e| RomError::ModelFile {
            path: "<memory>".into(),
            message: e.to_string(),
        })?;
        Ok(checksum(&model))
    }

    /// Parses model file text (`path` is only used in messages).
    ///
    /// # Errors
    /// See the module docs.
    pub fn from_json(text: &str, path: &str) -> Result<Self, RomError> {
        let fail = |message: String| RomError::ModelFile {
            path: path.to_string(),
            message,
        };
        let env: EnvelopeIn<'_> = serde_json::from_str(text).map_err(|e| {
            fail(format!(
                "not a valid model file (corrupt or truncated JSON): {e}"
            ))
        })?;
        if env.format != FORMAT_NAME {
            return Err(fail(format!(
                "format is {:?}, expected {FORMAT_NAME:?}",
                env.format
            )));
        }
        if env.format_version != FORMAT_VERSION {
            return Err(fail(format!("format version {} is not supported: this build reads version {FORMAT_VERSION} (retrain or convert the model)", env.format_version)));
        }
        let actual = checksum(env.model.get());
        if actual != env.checksum {
            return Err(fail(format!("checksum mismatch: file says {}, content gives {actual} (file modified or corrupt)", env.checksum)));
        }
        let model: Surrogate = serde_json::from_str(env.model.get()).map_err(|e| {
            fail(format!(
                "model content does not match format {FORMAT_VERSION}: {e}"
            ))
        })?;
        model
            .check_consistency()
            .map_err(|m| fail(format!("inconsistent model: {m}")))?;
        Ok(model)
    }

    /// Writes the model file atomically ([`crate::io::write_atomic`]: a reader never sees a
    /// half-written model), creating parent directories. An existing file is replaced;
    /// [`Self::save_new`] refuses to.
    ///
    /// # Errors
    /// I/O or serialisation failure.
    pub fn save(&self, path: &Path) -> Result<(), RomError> {
        let io = |source| RomError::Io {
            path: path.display().to_string(),
            source,
        };
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        if let Some(dir) = dir {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        crate::io::write_atomic(path, self.to_json()?.as_bytes()).map_err(io)
    }

    /// [`Self::save`], refusing to replace an existing file unless `overwrite`.
    ///
    /// # Errors
    /// [`RomError::ModelFile`] if `path` exists and `overwrite` is false; as [`Self::save`].
    pub fn save_new(&self, path: &Path, overwrite: bool) -> Result<(), RomError> {
        refuse_existing(path, overwrite)?;
        self.save(path)
    }

    /// Loads and verifies a model file.
    ///
    /// # Errors
    /// I/O, corrupt file, wrong format or version, checksum mismatch, inconsistent model.
    pub fn load(path: &Path) -> Result<Self, RomError> {
        let text = std::fs::read_to_string(path).map_err(|source| {
            if source.kind() == std::io::ErrorKind::NotFound {
                let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
                RomError::ModelFile {
                    path: path.display().to_string(),
                    message: format!(
                        "not found (looked for {}; a relative path starts from the current directory)",
                        abs.display()
                    ),
                }
            } else {
                RomError::Io {
                    path: path.display().to_string(),
                    source,
                }
            }
        })?;
        Self::from_json(&text, &path.display().to_string())
    }
}

/// An error if `path` exists and may not be replaced: checked before a long computation whose
/// result would go there.
///
/// # Errors
/// [`RomError::ModelFile`] naming the file.
pub fn refuse_existing(path: &Path, overwrite: bool) -> Result<(), RomError> {
    if !overwrite && path.exists() {
        return Err(RomError::ModelFile {
            path: path.display().to_string(),
            message: "exists: refusing to overwrite it (choose another path, or allow the \
                      overwrite explicitly)"
                .into(),
        });
    }
    Ok(())
}
