//! The CSV layer of the recording readers ([`super::experiments`]): the separator, the header
//! (each column as named or in another unit, [`crate::schema::RECORDING_UNIT_COLUMNS`]), finite
//! numbers, integers and positive standard deviations, one row per configuration, and the error
//! type that names the file, line and column of whatever fails.

use serde::Deserialize;
use thiserror::Error;

use super::units::{Suspicion, Written};
use crate::schema;

/// Errors reading experiment files.
#[derive(Debug, Error)]
pub enum ExperimentError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// A file whose header is one field holding another separator.
    #[error(
        "{source_name}, line 1: the header is one column, {header:?}: the file looks \
         {separator}-separated; the recordings are comma-separated (a spreadsheet's \
         \"CSV (comma delimited)\", with a decimal point)"
    )]
    Separator {
        /// File or source name.
        source_name: String,
        /// The header as read.
        header: String,
        /// The separator it holds (`;`, `tab`).
        separator: String,
    },
    /// Values whose scale or sign is not the format's: each column with every failing row.
    #[error(
        "{source_name}: values in another unit or with the other sign (nothing was read from \
         it):\n  - {}",
        problems.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n  - ")
    )]
    Implausible {
        /// File or source name.
        source_name: String,
        /// Each suspicious column, with its rows.
        problems: Vec<Suspicion>,
    },
    /// A malformed record.
    #[error("{source_name}, line {line}, column {column}: {reason}")]
    Record {
        /// File or source name.
        source_name: String,
        /// 1-based line.
        line: usize,
        /// Column name.
        column: String,
        /// What is wrong.
        reason: String,
    },
}

/// Rows of a recording and the columns converted from another unit.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub struct Parsed<T> {
    pub(super) rows: Vec<T>,
    pub(super) written: Written,
}

impl<T> Parsed<T> {
    /// The rows, in the format's units.
    // public for the tests in tests/calibrate/
    #[doc(hidden)]
    pub fn rows(&self) -> &[T] {
        &self.rows
    }

    /// The conversions, in words (`pressure_kpa → pressure_bar × 0.01`).
    // public for the tests in tests/calibrate/
    #[doc(hidden)]
    pub fn converted(&self) -> Vec<String> {
        self.written
            .renamed
            .iter()
            .map(|(c, w)| {
                let f = schema::RECORDING_UNIT_COLUMNS
                    .iter()
                    .find(|u| u.column.name == w)
                    .map_or(1.0, |u| u.to_canonical);
                format!("{w} → {c} × {f}")
            })
            .collect()
    }
}

/// Each column of the file as the format's column it stands for, with its factor.
fn map_header(
    name: &str,
    headers: &csv::StringRecord,
    columns: &[&str],
) -> Result<(Vec<(String, f64)>, Written), ExperimentError> {
    if headers.len() == 1 {
        let h = &headers[0];
        for (sep, word) in [(';', ";"), ('\t', "tab")] {
            if h.contains(sep) {
                return Err(ExperimentError::Separator {
                    source_name: name.to_string(),
                    header: h.to_string(),
                    separator: word.to_string(),
                });
            }
        }
    }
    let mut mapped = Vec::new();
    let mut written = Written::default();
    let mut unknown = Vec::new();
    for h in headers.iter() {
        if columns.contains(&h) {
            mapped.push((h.to_string(), 1.0));
        } else if let Some(u) = schema::RECORDING_UNIT_COLUMNS
            .iter()
            .find(|u| u.column.name == h && columns.contains(&u.canonical.name))
        {
            mapped.push((u.canonical.name.to_string(), u.to_canonical));
            written
                .renamed
                .push((u.canonical.name.to_string(), h.to_string()));
        } else {
            unknown.push(h);
            mapped.push((String::new(), f64::NAN));
        }
    }
    for c in columns {
        if !mapped.iter().any(|(m, _)| m == c) {
            let hint = if unknown.is_empty() {
                String::new()
            } else {
                format!(
                    " (the header has {}, which this format does not have: renamed?)",
                    unknown.join(", ")
                )
            };
            return Err(record_error(name, 1, c, &format!("missing column{hint}")));
        }
    }
    if let Some(h) = unknown.first() {
        let alternatives: Vec<&str> = schema::RECORDING_UNIT_COLUMNS
            .iter()
            .filter(|u| columns.contains(&u.canonical.name))
            .map(|u| u.column.name)
            .collect();
        return Err(record_error(
            name,
            1,
            h,
            &format!(
                "unexpected column (a unit or quantity this file format does not have); \
                 expected exactly {}, each either as named or in another unit ({})",
                columns.join(", "),
                alternatives.join(", ")
            ),
        ));
    }
    for (i, (m, _)) in mapped.iter().enumerate() {
        if let Some(j) = mapped[..i].iter().position(|(o, _)| o == m) {
            let both = if headers[i] == headers[j] {
                "column given twice".to_string()
            } else {
                format!(
                    "column given twice, as {} and as {}",
                    &headers[j], &headers[i]
                )
            };
            return Err(record_error(name, 1, m, &both));
        }
    }
    Ok((mapped, written))
}

pub(super) fn parse<T: for<'de> Deserialize<'de>>(
    name: &str,
    text: &str,
    columns: &[&str],
) -> Result<Parsed<T>, ExperimentError> {
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = rdr
        .headers()
        .map_err(|e| record_error(name, 1, "header", &e.to_string()))?
        .clone();
    let (mapped, written) = map_header(name, &headers, columns)?;
    let canonical: csv::StringRecord = mapped.iter().map(|(c, _)| c.as_str()).collect();
    let mut out = Vec::new();
    for (i, rec) in rdr.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| record_error(name, line, "row", &e.to_string()))?;
        let mut cleaned = csv::StringRecord::new();
        for ((h, (c, factor)), v) in headers.iter().zip(&mapped).zip(rec.iter()) {
            let x = match v.parse::<f64>() {
                Ok(x) if x.is_finite() => x * factor,
                _ => {
                    return Err(record_error(
                        name,
                        line,
                        h,
                        &format!("'{v}' is not a finite number"),
                    ))
                }
            };
            if INTEGER_COLUMNS.contains(&c.as_str()) {
                if x.fract() != 0.0 || x < 0.0 || x > u32::MAX as f64 {
                    return Err(record_error(
                        name,
                        line,
                        h,
                        &format!("'{v}' is not a non-negative integer"),
                    ));
                }
                // integers written as `9.0` (what pandas writes) are accepted
                cleaned.push_field(&format!("{}", x as u64));
                continue;
            }
            if STD_COLUMNS.contains(&c.as_str()) && x <= 0.0 {
                return Err(record_error(
                    name,
                    line,
                    h,
                    &format!("'{v}': a standard deviation must be > 0"),
                ));
            }
            if *factor == 1.0 {
                cleaned.push_field(v);
            } else {
                cleaned.push_field(&format!("{x:?}"));
            }
        }
        let row: T = cleaned
            .deserialize(Some(&canonical))
            .map_err(|e| record_error(name, line, "row", &e.to_string()))?;
        out.push(row);
    }
    if out.is_empty() {
        return Err(record_error(name, 2, "row", "no records"));
    }
    Ok(Parsed { rows: out, written })
}

/// The error of a file whose values fail the scale and sign checks, if any do.
pub(super) fn plausible(name: &str, problems: Vec<Suspicion>) -> Result<(), ExperimentError> {
    if problems.is_empty() {
        Ok(())
    } else {
        Err(ExperimentError::Implausible {
            source_name: name.to_string(),
            problems,
        })
    }
}

/// Columns holding integers.
const INTEGER_COLUMNS: [&str; 2] = [schema::N_BELLOWS.name, schema::MARKER.name];
/// Columns holding standard deviations (must be > 0).
const STD_COLUMNS: [&str; 3] = [
    schema::ANGLE_STD.name,
    schema::FORCE_STD.name,
    schema::MARKER_RECORDED_STD.name,
];

/// Rejects two records of the same configuration, naming both lines (header = line 1) and the
/// configuration in its units.
pub(super) fn check_duplicates(name: &str, keys: &[Key]) -> Result<(), ExperimentError> {
    for (i, k) in keys.iter().enumerate() {
        if let Some(j) = keys[..i].iter().position(|o| o.same(k)) {
            return Err(record_error(
                name,
                i + 2,
                "row",
                &format!(
                    "duplicate of line {} (same configuration: {})",
                    j + 2,
                    k.label()
                ),
            ));
        }
    }
    Ok(())
}

/// The configuration of a row, and its marker for marker recordings.
#[derive(Clone, Copy, Debug)]
pub(super) struct Key {
    pub(super) n: usize,
    pub(super) t_mm: f64,
    pub(super) p_bar: f64,
    pub(super) marker: Option<usize>,
}

impl Key {
    fn same(&self, o: &Key) -> bool {
        self.n == o.n && self.t_mm == o.t_mm && self.p_bar == o.p_bar && self.marker == o.marker
    }

    fn label(&self) -> String {
        let mut s = format!(
            "N = {}, T = {} mm, P = {} bar",
            self.n, self.t_mm, self.p_bar
        );
        if let Some(k) = self.marker {
            s.push_str(&format!(", marker {k}"));
        }
        s
    }
}

pub(super) fn record_error(name: &str, line: usize, column: &str, reason: &str) -> ExperimentError {
    ExperimentError::Record {
        source_name: name.to_string(),
        line,
        column: column.to_string(),
        reason: reason.to_string(),
    }
}
