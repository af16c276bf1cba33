//! The experiments shipped in `training_data/`: bending (tip Uz, Uy, angle) and blocked force,
//! 27 (N, T, P) configurations each, and the study's tip bending error
//! `BE = sqrt((Uz_exp − Uz_sim)² + (Uy_exp − Uy_sim)²)` (mm). The columns of the experiment
//! files, with units and meanings: [`crate::schema`] (formats `bending`, `force`, `markers`).
//!
//! Every reader validates at the door: comma-separated text (a file separated by `;` or tabs
//! is named as such), exactly the format's columns in any order, each either as named or as
//! one of its columns in another unit (`pressure_kpa`, `force_mn`, …, converted on reading),
//! finite numbers, integer `N`, positive standard deviations, one row per configuration, and
//! values whose scale and sign are those of the format ([`super::units`]). Each failure is an
//! [`ExperimentError`] naming the file, the line and the column.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::inputs::InputFile;
pub use super::recording_csv::ExperimentError;
use super::recording_csv::{check_duplicates, parse, plausible, record_error, Key, Parsed};
use super::units::{self, Recorded, Row};
use crate::schema;

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

fn key(n: usize, t: f64, p: f64) -> Key {
    Key {
        n,
        t_mm: t,
        p_bar: p,
        marker: None,
    }
}

// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn bending_from(name: &str, text: &str) -> Result<Parsed<BendingRecord>, ExperimentError> {
    let parsed: Parsed<BendingRecord> = parse(name, text, &BENDING_COLUMNS)?;
    let keys: Vec<Key> = parsed
        .rows
        .iter()
        .map(|r| key(r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
        .collect();
    check_duplicates(name, &keys)?;
    let rows: Vec<Row> = (parsed.rows.iter().enumerate())
        .map(|(i, r)| Row {
            line: i + 2,
            pressure_bar: r.pressure_bar,
            wall_thickness_mm: r.wall_thickness_mm,
            recorded: Recorded::Bending {
                tip_uz_mm: r.tip_uz_mm,
                tip_uy_mm: r.tip_uy_mm,
                angle_deg: r.angle_deg,
                angle_std_deg: r.angle_std_deg,
            },
        })
        .collect();
    plausible(name, units::check(&rows, &parsed.written))?;
    Ok(parsed)
}

fn force_from(name: &str, text: &str) -> Result<Parsed<ForceRecord>, ExperimentError> {
    let parsed: Parsed<ForceRecord> = parse(name, text, &FORCE_COLUMNS)?;
    let keys: Vec<Key> = parsed
        .rows
        .iter()
        .map(|r| key(r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
        .collect();
    check_duplicates(name, &keys)?;
    let rows: Vec<Row> = (parsed.rows.iter().enumerate())
        .map(|(i, r)| Row {
            line: i + 2,
            pressure_bar: r.pressure_bar,
            wall_thickness_mm: r.wall_thickness_mm,
            recorded: Recorded::Force {
                force_n: r.force_n,
                force_std_n: r.force_std_n,
            },
        })
        .collect();
    plausible(name, units::check(&rows, &parsed.written))?;
    Ok(parsed)
}

fn markers_from(name: &str, text: &str) -> Result<Parsed<MarkerRecord>, ExperimentError> {
    let parsed: Parsed<MarkerRecord> = parse(name, text, &MARKER_COLUMNS)?;
    for (i, r) in parsed.rows.iter().enumerate() {
        if !(1..=9).contains(&r.marker) {
            return Err(record_error(
                name,
                i + 2,
                schema::MARKER.name,
                &format!("{} is not a marker number 1..9", r.marker),
            ));
        }
    }
    let keys: Vec<Key> = parsed
        .rows
        .iter()
        .map(|r| Key {
            marker: Some(r.marker),
            ..key(r.n_bellows, r.wall_thickness_mm, r.pressure_bar)
        })
        .collect();
    check_duplicates(name, &keys)?;
    let rows: Vec<Row> = (parsed.rows.iter().enumerate())
        .map(|(i, r)| Row {
            line: i + 2,
            pressure_bar: r.pressure_bar,
            wall_thickness_mm: r.wall_thickness_mm,
            recorded: Recorded::Marker {
                marker: r.marker,
                uz_mm: r.uz_mm,
                uy_mm: r.uy_mm,
                std_mm: r.std_mm,
            },
        })
        .collect();
    plausible(name, units::check(&rows, &parsed.written))?;
    Ok(parsed)
}

fn read_text(path: &Path) -> Result<String, ExperimentError> {
    std::fs::read_to_string(path).map_err(|source| ExperimentError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Where the shipped bending experiments are, in the repository.
pub const SHIPPED_BENDING: &str = "training_data/bending_experiments.csv";
/// Where the shipped blocked-force experiments are, in the repository.
pub const SHIPPED_FORCE: &str = "training_data/blocked_force_experiments.csv";

/// The shipped bending experiments.
///
/// # Errors
/// Never for the shipped file (tested); kept fallible for uniformity.
pub fn shipped_bending() -> Result<Vec<BendingRecord>, ExperimentError> {
    Ok(bending_from(SHIPPED_BENDING, BENDING_CSV)?.rows)
}

/// The shipped blocked-force experiments.
///
/// # Errors
/// Never for the shipped file (tested).
pub fn shipped_force() -> Result<Vec<ForceRecord>, ExperimentError> {
    Ok(force_from(SHIPPED_FORCE, FORCE_CSV)?.rows)
}

/// The shipped experiments as built into the program, each with its record as a default
/// input (checksum of the text built in, which is the repository's file).
///
/// # Errors
/// Never for the shipped files (tested).
pub fn shipped_files() -> Result<(Loaded<BendingRecord>, Loaded<ForceRecord>), ExperimentError> {
    let b = bending_from(SHIPPED_BENDING, BENDING_CSV)?;
    let f = force_from(SHIPPED_FORCE, FORCE_CSV)?;
    Ok((
        loaded("bending", SHIPPED_BENDING, BENDING_CSV, b, true),
        loaded("force", SHIPPED_FORCE, FORCE_CSV, f, true),
    ))
}

/// Whether `file` is one of the shipped experiment files (bending or blocked force), by its
/// checksum: a copy read from another folder is too, an edited one is not.
pub fn is_shipped(file: &InputFile) -> bool {
    let shipped = match file.role.as_str() {
        "bending" => BENDING_CSV,
        "force" => FORCE_CSV,
        _ => return false,
    };
    file.checksum == super::inputs::checksum(shipped.as_bytes())
}

/// Rows read from a recording file, and the file's record (path, checksum, rows, conversions).
#[derive(Clone, Debug)]
pub struct Loaded<T> {
    /// The rows, in the format's units.
    pub rows: Vec<T>,
    /// The file.
    pub file: InputFile,
}

fn loaded<T>(role: &str, path: &str, text: &str, p: Parsed<T>, default: bool) -> Loaded<T> {
    let mut file = InputFile::of_bytes(role, path, text.as_bytes());
    file.rows = Some(p.rows.len());
    file.converted = p.converted();
    file.default = default;
    Loaded { rows: p.rows, file }
}

/// Reads a bending-experiment CSV with its record as an input named by the user.
///
/// # Errors
/// As [`read_bending`].
pub fn load_bending(path: &Path) -> Result<Loaded<BendingRecord>, ExperimentError> {
    let (name, text) = (path.display().to_string(), read_text(path)?);
    let p = bending_from(&name, &text)?;
    Ok(loaded("bending", &name, &text, p, false))
}

/// Reads a blocked-force CSV with its record.
///
/// # Errors
/// As [`read_bending`].
pub fn load_force(path: &Path) -> Result<Loaded<ForceRecord>, ExperimentError> {
    let (name, text) = (path.display().to_string(), read_text(path)?);
    let p = force_from(&name, &text)?;
    Ok(loaded("force", &name, &text, p, false))
}

/// Reads a marker-recording CSV with its record.
///
/// # Errors
/// As [`read_markers`].
pub fn load_markers(path: &Path) -> Result<Loaded<MarkerRecord>, ExperimentError> {
    let (name, text) = (path.display().to_string(), read_text(path)?);
    let p = markers_from(&name, &text)?;
    Ok(loaded("markers", &name, &text, p, false))
}

/// Reads a bending-experiment CSV: the columns of the shipped file (or, for a quantity, its
/// column in another unit: [`crate::schema::RECORDING_UNIT_COLUMNS`]).
///
/// # Errors
/// I/O errors; a file separated by `;` or tabs ([`ExperimentError::Separator`]); a missing
/// or unexpected column, a cell that is not a finite number, a non-positive standard
/// deviation, a duplicate configuration (naming line and column); values whose scale or sign
/// is not the format's ([`ExperimentError::Implausible`], every failing row).
pub fn read_bending(path: &Path) -> Result<Vec<BendingRecord>, ExperimentError> {
    Ok(load_bending(path)?.rows)
}

/// Reads a blocked-force CSV (the columns of the shipped file, or their other units).
///
/// # Errors
/// As [`read_bending`].
pub fn read_force(path: &Path) -> Result<Vec<ForceRecord>, ExperimentError> {
    Ok(load_force(path)?.rows)
}

/// Reads a marker-recording CSV (`n_bellows, wall_thickness_mm, pressure_bar, marker, uz_mm,
/// uy_mm, std_mm`, or their other units).
///
/// # Errors
/// As [`read_bending`]; a marker number outside 1..9.
pub fn read_markers(path: &Path) -> Result<Vec<MarkerRecord>, ExperimentError> {
    Ok(load_markers(path)?.rows)
}

/// Parses bending records from text (`name` is used in messages).
///
/// # Errors
/// As [`read_bending`].
pub fn parse_bending(name: &str, text: &str) -> Result<Vec<BendingRecord>, ExperimentError> {
    Ok(bending_from(name, text)?.rows)
}

/// Parses blocked-force records from text.
///
/// # Errors
/// As [`read_bending`].
pub fn parse_force(name: &str, text: &str) -> Result<Vec<ForceRecord>, ExperimentError> {
    Ok(force_from(name, text)?.rows)
}

/// Parses marker records from text.
///
/// # Errors
/// As [`read_markers`].
pub fn parse_markers(name: &str, text: &str) -> Result<Vec<MarkerRecord>, ExperimentError> {
    Ok(markers_from(name, text)?.rows)
}

/// The study's tip bending error (eq. 1), mm.
pub fn bending_error(uz_exp: f64, uy_exp: f64, uz_sim: f64, uy_sim: f64) -> f64 {
    ((uz_exp - uz_sim).powi(2) + (uy_exp - uy_sim).powi(2)).sqrt()
}
