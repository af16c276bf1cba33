//! The experiments shipped in `training_data/`: bending (tip Uz, Uy, angle) and blocked force,
//! 27 (N, T, P) configurations each, and the study's tip bending error
//! `BE = sqrt((Uz_exp − Uz_sim)² + (Uy_exp − Uy_sim)²)` (mm). The columns of the experiment
//! files, with units and meanings: [`crate::schema`] (formats `bending`, `force`, `markers`).

use std::path::Path;

use serde::{Deserialize, Serialize};
use thiserror::Error;

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

/// One bending configuration (means over specimens and repetitions).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BendingRecord {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Tip Uz (mm).
    pub tip_uz_mm: f64,
    /// Tip Uy (mm).
    pub tip_uy_mm: f64,
    /// Bending angle (deg).
    pub angle_deg: f64,
    /// Standard deviation of the angle (deg).
    pub angle_std_deg: f64,
}

/// One blocked-force configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ForceRecord {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Mean blocked force (N).
    pub force_n: f64,
    /// Its standard deviation (N).
    pub force_std_n: f64,
}

/// File name of bending recordings in a recordings directory (`training_data/`, a twin's).
pub const BENDING_FILE: &str = "bending_experiments.csv";
/// File name of blocked-force recordings in a recordings directory.
pub const FORCE_FILE: &str = "blocked_force_experiments.csv";
/// File name of marker recordings in a recordings directory (optional).
pub const MARKERS_FILE: &str = "marker_experiments.csv";

const BENDING_CSV: &str = include_str!("../../training_data/bending_experiments.csv");
const FORCE_CSV: &str = include_str!("../../training_data/blocked_force_experiments.csv");

fn parse<T: for<'de> Deserialize<'de>>(
    name: &str,
    text: &str,
    columns: &[&str],
) -> Result<Vec<T>, ExperimentError> {
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = rdr
        .headers()
        .map_err(|e| record_error(name, 1, "header", &e.to_string()))?
        .clone();
    for c in columns {
        if !headers.iter().any(|h| h == *c) {
            return Err(record_error(name, 1, c, "missing column"));
        }
    }
    for h in headers.iter() {
        if !columns.contains(&h) {
            return Err(record_error(
                name,
                1,
                h,
                &format!(
                    "unexpected column (a unit or quantity this file format does not have); \
                     expected exactly {}",
                    columns.join(", ")
                ),
            ));
        }
        if headers.iter().filter(|o| *o == h).count() > 1 {
            return Err(record_error(name, 1, h, "column given twice"));
        }
    }
    let mut out = Vec::new();
    for (i, rec) in rdr.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| record_error(name, line, "row", &e.to_string()))?;
        for (h, v) in headers.iter().zip(rec.iter()) {
            if !v.parse::<f64>().is_ok_and(f64::is_finite) {
                return Err(record_error(
                    name,
                    line,
                    h,
                    &format!("'{v}' is not a finite number"),
                ));
            }
            if INTEGER_COLUMNS.contains(&h) {
                let x: f64 = v.parse().unwrap_or(f64::NAN);
                if x.fract() != 0.0 || x < 0.0 {
                    return Err(record_error(
                        name,
                        line,
                        h,
                        &format!("'{v}' is not a non-negative integer"),
                    ));
                }
            }
            if STD_COLUMNS.contains(&h) {
                let x: f64 = v.parse().unwrap_or(f64::NAN);
                if x <= 0.0 {
                    return Err(record_error(
                        name,
                        line,
                        h,
                        &format!("'{v}': a standard deviation must be > 0"),
                    ));
                }
            }
        }
        // integers written as `9.0` (what pandas writes) are accepted
        let cleaned: csv::StringRecord = headers
            .iter()
            .zip(rec.iter())
            .map(|(h, v)| {
                if INTEGER_COLUMNS.contains(&h) {
                    format!("{}", v.parse::<f64>().unwrap_or(f64::NAN) as i64)
                } else {
                    v.to_string()
                }
            })
            .collect();
        let row: T = cleaned
            .deserialize(Some(&headers))
            .map_err(|e| record_error(name, line, "row", &e.to_string()))?;
        out.push(row);
    }
    if out.is_empty() {
        return Err(record_error(name, 2, "row", "no records"));
    }
    Ok(out)
}

/// Columns holding integers.
const INTEGER_COLUMNS: [&str; 2] = [schema::N_BELLOWS.name, schema::MARKER.name];
/// Columns holding standard deviations (must be > 0).
const STD_COLUMNS: [&str; 3] = [
    schema::ANGLE_STD.name,
    schema::FORCE_STD.name,
    schema::MARKER_RECORDED_STD.name,
];

/// Rejects two records of the same key, naming both lines (header = line 1).
fn check_duplicates<K: PartialEq + std::fmt::Debug>(
    name: &str,
    keys: &[K],
) -> Result<(), ExperimentError> {
    for (i, k) in keys.iter().enumerate() {
        if let Some(j) = keys[..i].iter().position(|o| o == k) {
            return Err(record_error(
                name,
                i + 2,
                "row",
                &format!("duplicate of line {} (same configuration {k:?})", j + 2),
            ));
        }
    }
    Ok(())
}

fn record_error(name: &str, line: usize, column: &str, reason: &str) -> ExperimentError {
    ExperimentError::Record {
        source_name: name.to_string(),
        line,
        column: column.to_string(),
        reason: reason.to_string(),
    }
}

const BENDING_COLUMNS: [&str; 7] = schema::names(&schema::BENDING_COLUMNS);
const FORCE_COLUMNS: [&str; 5] = schema::names(&schema::FORCE_COLUMNS);

/// Columns of a marker-recording file (optional: recordings that track points along the
/// actuator, in the convention of the tip columns).
const MARKER_COLUMNS: [&str; 7] = schema::names(&schema::MARKER_RECORDING_COLUMNS);

/// One recorded marker (bottom-face point `k = 1..9` at `z = k·Lf/9`; 9 is the tip).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MarkerRecord {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Marker number, 1..9.
    pub marker: usize,
    /// Uz = −Δz (mm).
    pub uz_mm: f64,
    /// Uy = Δy (mm).
    pub uy_mm: f64,
    /// Standard deviation of each component (mm).
    pub std_mm: f64,
}

fn key(n: usize, t: f64, p: f64) -> (usize, u64, u64) {
    (n, t.to_bits(), p.to_bits())
}

/// Parses `text` and rejects two records of the same configuration `(N, T, P)`.
fn parse_unique<T: for<'de> Deserialize<'de>>(
    name: &str,
    text: &str,
    columns: &[&str],
    config: impl Fn(&T) -> (usize, f64, f64),
) -> Result<Vec<T>, ExperimentError> {
    let rows: Vec<T> = parse(name, text, columns)?;
    let keys: Vec<_> = rows
        .iter()
        .map(|r| {
            let (n, t, p) = config(r);
            key(n, t, p)
        })
        .collect();
    check_duplicates(name, &keys)?;
    Ok(rows)
}

fn bending_from(name: &str, text: &str) -> Result<Vec<BendingRecord>, ExperimentError> {
    parse_unique(name, text, &BENDING_COLUMNS, |r: &BendingRecord| {
        (r.n_bellows, r.wall_thickness_mm, r.pressure_bar)
    })
}

fn force_from(name: &str, text: &str) -> Result<Vec<ForceRecord>, ExperimentError> {
    parse_unique(name, text, &FORCE_COLUMNS, |r: &ForceRecord| {
        (r.n_bellows, r.wall_thickness_mm, r.pressure_bar)
    })
}

fn markers_from(name: &str, text: &str) -> Result<Vec<MarkerRecord>, ExperimentError> {
    let rows: Vec<MarkerRecord> = parse(name, text, &MARKER_COLUMNS)?;
    for (i, r) in rows.iter().enumerate() {
        if !(1..=9).contains(&r.marker) {
            return Err(record_error(
                name,
                i + 2,
                schema::MARKER.name,
                &format!("{} is not a marker number 1..9", r.marker),
            ));
        }
    }
    let keys: Vec<_> = rows
        .iter()
        .map(|r| {
            (
                key(r.n_bellows, r.wall_thickness_mm, r.pressure_bar),
                r.marker,
            )
        })
        .collect();
    check_duplicates(name, &keys)?;
    Ok(rows)
}

fn read_text(path: &Path) -> Result<String, ExperimentError> {
    std::fs::read_to_string(path).map_err(|source| ExperimentError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// The shipped bending experiments.
///
/// # Errors
/// Never for the shipped file (tested); kept fallible for uniformity.
pub fn shipped_bending() -> Result<Vec<BendingRecord>, ExperimentError> {
    bending_from("training_data/bending_experiments.csv", BENDING_CSV)
}

/// The shipped blocked-force experiments.
///
/// # Errors
/// Never for the shipped file (tested).
pub fn shipped_force() -> Result<Vec<ForceRecord>, ExperimentError> {
    force_from("training_data/blocked_force_experiments.csv", FORCE_CSV)
}

/// Reads a bending-experiment CSV (columns exactly those of the shipped file).
///
/// # Errors
/// I/O errors, a missing or unexpected column, a cell that is not a finite number, a
/// non-positive standard deviation, a duplicate configuration (naming line and column).
pub fn read_bending(path: &Path) -> Result<Vec<BendingRecord>, ExperimentError> {
    bending_from(&path.display().to_string(), &read_text(path)?)
}

/// Reads a blocked-force CSV (columns exactly those of the shipped file).
///
/// # Errors
/// As [`read_bending`].
pub fn read_force(path: &Path) -> Result<Vec<ForceRecord>, ExperimentError> {
    force_from(&path.display().to_string(), &read_text(path)?)
}

/// Reads a marker-recording CSV (`n_bellows, wall_thickness_mm, pressure_bar, marker, uz_mm,
/// uy_mm, std_mm`).
///
/// # Errors
/// As [`read_bending`]; a marker number outside 1..9.
pub fn read_markers(path: &Path) -> Result<Vec<MarkerRecord>, ExperimentError> {
    markers_from(&path.display().to_string(), &read_text(path)?)
}

/// Parses bending records from text (`name` is used in messages).
///
/// # Errors
/// As [`read_bending`].
pub fn parse_bending(name: &str, text: &str) -> Result<Vec<BendingRecord>, ExperimentError> {
    bending_from(name, text)
}

/// Parses blocked-force records from text.
///
/// # Errors
/// As [`read_bending`].
pub fn parse_force(name: &str, text: &str) -> Result<Vec<ForceRecord>, ExperimentError> {
    force_from(name, text)
}

/// Parses marker records from text.
///
/// # Errors
/// As [`read_markers`].
pub fn parse_markers(name: &str, text: &str) -> Result<Vec<MarkerRecord>, ExperimentError> {
    markers_from(name, text)
}

/// The study's tip bending error (eq. 1), mm.
pub fn bending_error(uz_exp: f64, uy_exp: f64, uz_sim: f64, uy_sim: f64) -> f64 {
    ((uz_exp - uz_sim).powi(2) + (uy_exp - uy_sim).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_files_parse() {
        let b = shipped_bending().unwrap();
        assert_eq!(b.len(), 27);
        assert_eq!(b[0].n_bellows, 9);
        assert!((b[2].tip_uy_mm + 65.76).abs() < 1e-12);
        assert_eq!(shipped_force().unwrap().len(), 27);
    }

    #[test]
    fn malformed_rows_name_line_and_column() {
        let text = "n_bellows,wall_thickness_mm,pressure_bar,tip_uz_mm,tip_uy_mm,angle_deg,angle_std_deg\n9,1.6,1,abc,-35.9,23.57,1.95\n";
        let e = parse::<BendingRecord>("x.csv", text, &BENDING_COLUMNS).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.csv, line 2, column tip_uz_mm: 'abc' is not a finite number"
        );
        let e = parse::<BendingRecord>("x.csv", "n_bellows,pressure_bar\n9,1\n", &BENDING_COLUMNS)
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("column wall_thickness_mm: missing column"),
            "{e}"
        );
    }

    #[test]
    fn extra_columns_duplicates_and_bad_values_are_named() {
        let head = "n_bellows,wall_thickness_mm,pressure_bar,force_n,force_std_n";
        let e = parse_force(
            "f.csv",
            &format!("{head},force_lbf\n9,1.6,1,0.7,0.05,0.1\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("f.csv, line 1, column force_lbf: unexpected column"),
            "{e}"
        );
        let e = parse_force(
            "f.csv",
            &format!("{head}\n9,1.6,1,0.7,0.05\n9,1.6,2,1.7,0.05\n9.0,1.6,1,0.8,0.05\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("line 4, column row: duplicate of line 2"), "{e}");
        let e = parse_force("f.csv", &format!("{head}\n9,1.6,1,NaN,0.05\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 2, column force_n: 'NaN' is not a finite number"),
            "{e}"
        );
        let e = parse_force("f.csv", &format!("{head}\n9,1.6,1,0.7,0\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("column force_std_n"), "{e}");
        let e = parse_force("f.csv", &format!("{head}\n9.5,1.6,1,0.7,0.1\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("column n_bellows: '9.5' is not a non-negative integer"),
            "{e}"
        );
        let ok = parse_force("f.csv", &format!("{head}\n9.0,1.6,1,0.7,0.1\n")).unwrap();
        assert_eq!(ok[0].n_bellows, 9);
        let e = parse_force("f.csv", &format!("{head}\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no records"), "{e}");
        let m = "n_bellows,wall_thickness_mm,pressure_bar,marker,uz_mm,uy_mm,std_mm\n9,1.6,1,10,0,0,1\n";
        let e = parse_markers("m.csv", m).unwrap_err().to_string();
        assert!(
            e.contains("column marker: 10 is not a marker number"),
            "{e}"
        );
    }

    #[test]
    fn bending_error_is_euclidean() {
        assert!((bending_error(3.0, 4.0, 0.0, 0.0) - 5.0).abs() < 1e-15);
    }
}
