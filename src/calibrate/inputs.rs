//! The files a calibration or a diagnosis read: what each one is, where it was read, its
//! checksum, and whether it was a documented default rather than a file the user named.
//!
//! Every report lists them ([`markdown`] for the summaries, the `inputs` field of the JSON
//! reports), so that no result rests on a file its reader cannot name.

use std::path::Path;

use serde::{Deserialize, Serialize};

/// One file read.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputFile {
    /// What it is: `bending`, `force`, `markers` (recordings), `model`, `sensitivities`, ….
    pub role: String,
    /// Where it was read: as the user gave it, or the resolved default.
    pub path: String,
    /// `crc32:xxxxxxxx` of its bytes.
    pub checksum: String,
    /// Its size (bytes).
    pub bytes: u64,
    /// Rows read (recordings only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rows: Option<usize>,
    /// A documented default, not a file the user named.
    pub default: bool,
    /// Columns in another unit, converted on reading (`pressure_kpa → pressure_bar × 0.01`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub converted: Vec<String>,
}

/// `crc32:xxxxxxxx` of `bytes` (the checksum the model files carry too).
pub fn checksum(bytes: &[u8]) -> String {
    format!("crc32:{:08x}", crc32fast::hash(bytes))
}

impl InputFile {
    /// The record of `bytes`, read from `path` in the role `role` (named by the user).
    pub fn of_bytes(role: &str, path: &str, bytes: &[u8]) -> Self {
        InputFile {
            role: role.to_string(),
            path: path.to_string(),
            checksum: checksum(bytes),
            bytes: bytes.len() as u64,
            rows: None,
            default: false,
            converted: Vec::new(),
        }
    }

    /// Reads `path` to record it.
    ///
    /// # Errors
    /// The I/O error of reading it.
    pub fn read(role: &str, path: &Path) -> std::io::Result<Self> {
        let bytes = std::fs::read(path)?;
        Ok(Self::of_bytes(role, &path.display().to_string(), &bytes))
    }

    /// The same file, marked as a documented default.
    pub fn as_default(mut self) -> Self {
        self.default = true;
        self
    }

    /// `named` or `default`.
    pub fn origin(&self) -> &'static str {
        if self.default {
            "default"
        } else {
            "named"
        }
    }
}

/// The summaries' section listing `files`: a table of role, path, checksum, rows and origin,
/// then each conversion of a column in another unit.
pub fn markdown(files: &[InputFile]) -> String {
    use std::fmt::Write;
    let mut s = String::from("## Inputs\n\n");
    if files.is_empty() {
        s.push_str("No file was read.\n");
        return s;
    }
    s.push_str("| input | file | checksum | rows | |\n|---|---|---|---|---|\n");
    for f in files {
        let _ = writeln!(
            s,
            "| {} | `{}` | {} | {} | {} |",
            f.role,
            f.path,
            f.checksum,
            f.rows.map_or(String::new(), |r| r.to_string()),
            f.origin()
        );
    }
    if files.iter().any(|f| f.default) {
        s.push_str(
            "\n`default`: not named on the command line; the documented default of the \
             repository was read.\n",
        );
    }
    for f in files {
        for c in &f.converted {
            let _ = writeln!(s, "\n{}: column {c}.", f.role);
        }
    }
    s
}
