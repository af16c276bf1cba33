//! The experiments shipped in `training_data/`: bending (tip Uz, Uy, angle) and blocked force,
//! 27 (N, T, P) configurations each, and the study's tip bending error
//! `BE = sqrt((Uz_exp − Uz_sim)² + (Uy_exp − Uy_sim)²)` (mm).

use std::path::Path;

use serde::{Deserialize, Serialize};
use thiserror::Error;

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
    let mut out = Vec::new();
    for (i, rec) in rdr.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| record_error(name, line, "row", &e.to_string()))?;
        for (h, v) in headers.iter().zip(rec.iter()) {
            if columns.contains(&h) && !v.parse::<f64>().is_ok_and(f64::is_finite) {
                return Err(record_error(
                    name,
                    line,
                    h,
                    &format!("'{v}' is not a finite number"),
                ));
            }
        }
        let row: T = rec
            .deserialize(Some(&headers))
            .map_err(|e| record_error(name, line, "row", &e.to_string()))?;
        out.push(row);
    }
    Ok(out)
}

fn record_error(name: &str, line: usize, column: &str, reason: &str) -> ExperimentError {
    ExperimentError::Record {
        source_name: name.to_string(),
        line,
        column: column.to_string(),
        reason: reason.to_string(),
    }
}

const BENDING_COLUMNS: [&str; 7] = [
    "n_bellows",
    "wall_thickness_mm",
    "pressure_bar",
    "tip_uz_mm",
    "tip_uy_mm",
    "angle_deg",
    "angle_std_deg",
];
const FORCE_COLUMNS: [&str; 5] = [
    "n_bellows",
    "wall_thickness_mm",
    "pressure_bar",
    "force_n",
    "force_std_n",
];

/// The shipped bending experiments.
///
/// # Errors
/// Never for the shipped file (tested); kept fallible for uniformity.
pub fn shipped_bending() -> Result<Vec<BendingRecord>, ExperimentError> {
    parse(
        "training_data/bending_experiments.csv",
        BENDING_CSV,
        &BENDING_COLUMNS,
    )
}

/// The shipped blocked-force experiments.
///
/// # Errors
/// Never for the shipped file (tested).
pub fn shipped_force() -> Result<Vec<ForceRecord>, ExperimentError> {
    parse(
        "training_data/blocked_force_experiments.csv",
        FORCE_CSV,
        &FORCE_COLUMNS,
    )
}

/// Reads a bending-experiment CSV.
///
/// # Errors
/// I/O errors, missing columns, or a cell that is not a finite number (naming line and column).
pub fn read_bending(path: &Path) -> Result<Vec<BendingRecord>, ExperimentError> {
    let text = std::fs::read_to_string(path).map_err(|source| ExperimentError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse(&path.display().to_string(), &text, &BENDING_COLUMNS)
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
    fn bending_error_is_euclidean() {
        assert!((bending_error(3.0, 4.0, 0.0, 0.0) - 5.0).abs() < 1e-15);
    }
}
