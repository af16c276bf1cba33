//! Model files: portable, versioned JSON with a checksum.
//!
//! ```text
//! {"format":"surrogate-rom","format_version":3,"checksum":"crc32:1a2b3c4d","model":{…},
//!  "model_form":{"checksum":"crc32:5e6f7a8b","content":{…}}}
//! ```
//! `model` is the serialised [`Surrogate`] (inputs with units and training bounds, scalers,
//! POD bases, regression weights, validation errors, provenance); each fitted regressor is one
//! entry of it under its name (`"gp": {…}, "poly": {…}`), read through a [`Registry`] (the
//! built-ins unless one is given: [`Surrogate::from_json_with`], [`Surrogate::load_with`]). The checksum is the CRC-32
//! of the exact text of `model`: the model's identity, which calibration reports quote.
//! `model_form` (version 3, optional) is the model-form error learned from a calibration
//! through that model ([`super::model_form`], `surrogate model-form`), with the CRC-32 of the
//! exact text of its `content`; it lies outside the model's checksum, so attaching it leaves
//! the model's identity as the calibration quoted it. Version 2 files (no `model_form`) are
//! still read, as models without a model-form error.
//!
//! Floats are written in shortest round-trip form and parsed exactly
//! (`serde_json/float_roundtrip`), so save → load gives a bit-identical model. Loading
//! rejects: unparsable JSON, another `format`, a `format_version` other than 2 or 3, a
//! checksum mismatch (of either part), a `model_form` in a version 2 file, and an internally
//! inconsistent model or model-form error, each with a message naming the problem.

use std::path::Path;

use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;

use super::model_form::ModelFormError;
use super::regression::{Registry, Regressors};
use super::surrogate::Surrogate;
use super::RomError;

/// Format name written in every model file.
pub const FORMAT_NAME: &str = "surrogate-rom";
/// Format version this build writes (and reads).
pub const FORMAT_VERSION: u32 = 3;
/// The earlier format version this build still reads: version 3 without `model_form`.
pub const FORMAT_VERSION_WITHOUT_MODEL_FORM: u32 = 2;

#[derive(Serialize)]
struct EnvelopeOut<'a> {
    format: &'a str,
    format_version: u32,
    checksum: String,
    model: &'a RawValue,
    #[serde(skip_serializing_if = "Option::is_none")]
    model_form: Option<Part<'a>>,
}

/// A checksummed part of the file beside the model.
#[derive(Serialize, Deserialize)]
struct Part<'a> {
    checksum: String,
    #[serde(borrow)]
    content: &'a RawValue,
}

#[derive(Deserialize)]
struct EnvelopeIn<'a> {
    format: String,
    format_version: u32,
    checksum: String,
    #[serde(borrow)]
    model: &'a RawValue,
    #[serde(borrow, default)]
    model_form: Option<Part<'a>>,
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
        let model_form = match &self.model_form {
            Some(m) => {
                Some(RawValue::from_string(serde_json::to_string(m).map_err(err)?).map_err(err)?)
            }
            None => None,
        };
        let env = EnvelopeOut {
            format: FORMAT_NAME,
            format_version: FORMAT_VERSION,
            checksum: checksum(raw.get()),
            model: &raw,
            model_form: model_form.as_deref().map(|content| Part {
                checksum: checksum(content.get()),
                content,
            }),
        };
        serde_json::to_string(&env).map_err(err)
    }

    /// The checksum (`crc32:…`) the model file of this model carries (of the model alone: a
    /// model-form error beside it has its own).
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

    /// Parses model file text (`path` is only used in messages), its regressors through the
    /// built-in registry.
    ///
    /// # Errors
    /// See the module docs.
    pub fn from_json(text: &str, path: &str) -> Result<Self, RomError> {
        Self::from_json_with(text, path, &Registry::builtin())
    }

    /// [`Self::from_json`], reading the regressors `registry` knows.
    ///
    /// # Errors
    /// See the module docs; a block whose regressor `registry` does not know is inconsistent.
    pub fn from_json_with(text: &str, path: &str, registry: &Registry) -> Result<Self, RomError> {
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
        if env.format_version != FORMAT_VERSION
            && env.format_version != FORMAT_VERSION_WITHOUT_MODEL_FORM
        {
            return Err(fail(format!("format version {} is not supported: this build reads versions {FORMAT_VERSION_WITHOUT_MODEL_FORM} and {FORMAT_VERSION} (retrain or convert the model)", env.format_version)));
        }
        let actual = checksum(env.model.get());
        if actual != env.checksum {
            return Err(fail(format!("checksum mismatch: file says {}, content gives {actual} (file modified or corrupt)", env.checksum)));
        }
        let mut model: Surrogate = serde_json::from_str(env.model.get()).map_err(|e| {
            fail(format!(
                "model content does not match format {}: {e}",
                env.format_version
            ))
        })?;
        model.regressors = Regressors::from_model_json(env.model.get(), registry).map_err(&fail)?;
        model
            .check_consistency()
            .map_err(|m| fail(format!("inconsistent model: {m}")))?;
        if let Some(part) = env.model_form {
            if env.format_version == FORMAT_VERSION_WITHOUT_MODEL_FORM {
                return Err(fail(format!("model_form in a format version {FORMAT_VERSION_WITHOUT_MODEL_FORM} file: expected version {FORMAT_VERSION} (a version 2 file has no model-form error)")));
            }
            let actual = checksum(part.content.get());
            if actual != part.checksum {
                return Err(fail(format!("model_form checksum mismatch: file says {}, content gives {actual} (file modified or corrupt)", part.checksum)));
            }
            let m: ModelFormError = serde_json::from_str(part.content.get())
                .map_err(|e| fail(format!("model_form content: {e}")))?;
            m.check()
                .map_err(|m| fail(format!("inconsistent model-form error: {m}")))?;
            model.model_form = Some(m);
        }
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

    /// Loads and verifies a model file (its regressors through the built-in registry).
    ///
    /// # Errors
    /// I/O, corrupt file, wrong format or version, checksum mismatch, inconsistent model.
    pub fn load(path: &Path) -> Result<Self, RomError> {
        Self::load_with(path, &Registry::builtin())
    }

    /// [`Self::load`], reading the regressors `registry` knows.
    ///
    /// # Errors
    /// As [`Self::load`].
    pub fn load_with(path: &Path, registry: &Registry) -> Result<Self, RomError> {
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
        Self::from_json_with(&text, &path.display().to_string(), registry)
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
