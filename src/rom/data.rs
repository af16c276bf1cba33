//! Snapshot CSV reader: validated rows, grouped into pressure ramps per case.
//!
//! ## Column rule
//!
//! The header must **start with** exactly these 31 columns ([`schema::SNAPSHOT_COLUMNS`]), in
//! this order:
//! `case_id, n_bellows, wall_thickness_mm, mu1_mpa, alpha1, mu2_mpa, alpha2, pressure_bar,
//! converged, tip_uz_mm, tip_uy_mm, angle_deg, force_n, m1_uz_mm, m1_uy_mm, …, m9_uz_mm, m9_uy_mm`.
//! Any columns *after* them (provenance: `newton_iterations`, `mesh`, `code_version`, `error`, …)
//! are ignored. A missing required column, or any other name at a required position (an extra
//! column in the middle shifts the rest), is an error naming the position, the name found and
//! the name expected. Rows with `converged = false` are skipped (and counted) before their
//! outputs are parsed.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use super::{RomError, N_MARKER_COMPONENTS, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::{CaseInputs, OgdenSet};
use crate::schema::{self, SNAPSHOT_COLUMN_NAMES};

/// One converged snapshot row.
#[derive(Debug, Clone)]
pub struct SnapshotRow {
    /// Case identifier.
    pub case_id: String,
    /// 1-based line in the source file.
    pub line: usize,
    /// Design and material.
    pub inputs: CaseInputs,
    /// Gauge pressure, bar.
    pub pressure_bar: f64,
    /// The 22 quantities in [`super::QUANTITY_NAMES`] order.
    pub values: [f64; 22],
}

/// Validated converged rows of a snapshot file.
#[derive(Debug, Clone)]
pub struct SnapshotSet {
    /// Name of the source (file path).
    pub source: String,
    /// Converged rows, in file order.
    pub rows: Vec<SnapshotRow>,
    /// Number of rows skipped because `converged = false`.
    pub skipped_unconverged: usize,
}

/// The pressure ramp of one case on the common grid.
#[derive(Debug, Clone)]
pub struct CaseRamp {
    /// Case identifier.
    pub case_id: String,
    /// Design and material.
    pub inputs: CaseInputs,
    /// For each grid pressure, the 22 quantities.
    pub values: Vec<[f64; 22]>,
}

/// A case whose ramp does not cover the whole grid (unconverged steps at its ends).
#[derive(Debug, Clone)]
pub struct PartialRamp {
    /// Case identifier.
    pub case_id: String,
    /// Design and material.
    pub inputs: CaseInputs,
    /// For each grid pressure, the 22 quantities when available.
    pub values: Vec<Option<[f64; 22]>>,
}

/// Cases on a common pressure grid, ready for training.
#[derive(Debug, Clone)]
pub struct CaseSet {
    /// Common pressure grid, bar (sorted).
    pub pressures: Vec<f64>,
    /// Complete cases.
    pub cases: Vec<CaseRamp>,
    /// Cases left out of the complete set, with the reason (ramp truncated at an end of the grid).
    pub dropped: Vec<(String, String)>,
    /// The truncated cases that still cover at least half of the grid (usable by gappy POD,
    /// see `TrainConfig::fill_truncated`).
    pub partial: Vec<PartialRamp>,
    /// Grid points filled by linear interpolation inside a case's own ramp.
    pub interpolated_points: usize,
    /// Rows at pressures that are not on the grid (ignored).
    pub off_grid_rows: usize,
}

/// Between the sources of appended sets in a set's (and so a model's) source:
/// `"a.csv + b.csv"` ([`SnapshotSet::append`]).
pub const SOURCE_SEPARATOR: &str = " + ";

impl SnapshotSet {
    /// Appends the rows of `other` (another set of the same actuator, such as the cases a
    /// box extension added): the source becomes `"<self> + <other>"`, the skipped rows add
    /// up.
    ///
    /// # Errors
    /// [`RomError::Csv`] naming the first case id that both sets hold: two sets that share a
    /// case would train on it twice.
    pub fn append(&mut self, other: SnapshotSet) -> Result<(), RomError> {
        let ids: std::collections::HashSet<&str> =
            self.rows.iter().map(|r| r.case_id.as_str()).collect();
        if let Some(r) = other.rows.iter().find(|r| ids.contains(r.case_id.as_str())) {
            return Err(RomError::Csv {
                source_name: other.source.clone(),
                message: format!(
                    "case `{}` is also in {}: expected sets with distinct cases",
                    r.case_id, self.source
                ),
            });
        }
        self.source = format!("{}{SOURCE_SEPARATOR}{}", self.source, other.source);
        self.rows.extend(other.rows);
        self.skipped_unconverged += other.skipped_unconverged;
        Ok(())
    }

    /// Reads and validates a snapshot CSV file.
    ///
    /// # Errors
    /// I/O, header (see the module's column rule) and cell errors naming line and column.
    pub fn read(path: &Path) -> Result<Self, RomError> {
        let file = std::fs::File::open(path).map_err(|source| RomError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_reader(file, &path.display().to_string())
    }

    /// Reads and validates snapshot CSV text from any reader.
    ///
    /// # Errors
    /// Header and cell errors naming line and column.
    pub fn from_reader<R: Read>(reader: R, source_name: &str) -> Result<Self, RomError> {
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(reader);
        let csv_err = |e: csv::Error| RomError::Csv {
            source_name: source_name.to_string(),
            message: e.to_string(),
        };
        let header = rdr.headers().map_err(csv_err)?.clone();
        check_header(&header, source_name)?;
        let mut set = SnapshotSet {
            source: source_name.to_string(),
            rows: Vec::new(),
            skipped_unconverged: 0,
        };
        for (i, rec) in rdr.records().enumerate() {
            let rec = rec.map_err(csv_err)?;
            let line = rec.position().map(|p| p.line() as usize).unwrap_or(i + 2);
            let cells = RowCells {
                rec: &rec,
                line,
                source_name,
            };
            if let Some(row) = parse_row(&cells)? {
                set.rows.push(row);
            } else {
                set.skipped_unconverged += 1;
            }
        }
        if set.rows.is_empty() {
            return Err(RomError::InsufficientData(format!(
                "{source_name}: no converged rows ({} skipped as unconverged)",
                set.skipped_unconverged
            )));
        }
        Ok(set)
    }

    /// Groups the rows into per-case ramps on the common pressure grid.
    ///
    /// The grid is the set of pressures present in at least half of the cases. A case missing a
    /// grid pressure inside its own range gets it by linear interpolation; a case whose ramp
    /// does not cover the grid's ends is dropped (listed in [`CaseSet::dropped`]).
    ///
    /// # Errors
    /// A case whose rows disagree on the design or material, or repeat a pressure.
    pub fn into_cases(self) -> Result<CaseSet, RomError> {
        let groups = group_by_case(&self)?;
        let grid = common_grid(&groups);
        if grid.len() < 2 {
            return Err(RomError::InsufficientData(format!(
                "{}: fewer than 2 common pressures",
                self.source
            )));
        }
        let mut out = CaseSet {
            pressures: grid.clone(),
            cases: Vec::new(),
            dropped: Vec::new(),
            partial: Vec::new(),
            interpolated_points: 0,
            off_grid_rows: 0,
        };
        for (id, rows) in groups {
            let on_grid: Vec<&SnapshotRow> = rows
                .iter()
                .copied()
                .filter(|r| grid.iter().any(|&g| same_pressure(g, r.pressure_bar)))
                .collect();
            out.off_grid_rows += rows.len() - on_grid.len();
            match ramp_on_grid(&on_grid, &grid) {
                Ok((values, filled)) => {
                    out.interpolated_points += filled;
                    out.cases.push(CaseRamp {
                        case_id: id,
                        inputs: rows[0].inputs,
                        values,
                    });
                }
                Err((values, reason)) => {
                    if 2 * values.iter().filter(|v| v.is_some()).count() >= grid.len() {
                        out.partial.push(PartialRamp {
                            case_id: id.clone(),
                            inputs: rows[0].inputs,
                            values,
                        });
                    }
                    out.dropped.push((id, reason));
                }
            }
        }
        Ok(out)
    }
}

struct RowCells<'a> {
    rec: &'a csv::StringRecord,
    line: usize,
    source_name: &'a str,
}

impl RowCells<'_> {
    fn text(&self, col: usize) -> Result<&str, RomError> {
        self.rec
            .get(col)
            .ok_or_else(|| self.err(col, "", "a value (row too short)"))
    }

    fn err(&self, col: usize, value: &str, expected: &str) -> RomError {
        RomError::Cell {
            source_name: self.source_name.to_string(),
            line: self.line,
            column: SNAPSHOT_COLUMN_NAMES[col].to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }

    fn float(&self, col: usize) -> Result<f64, RomError> {
        let t = self.text(col)?;
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(col, t, "a finite number")),
        }
    }

    fn positive(&self, col: usize) -> Result<f64, RomError> {
        let v = self.float(col)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(col, self.text(col)?, "a number > 0"))
        }
    }
}

fn check_header(header: &csv::StringRecord, source_name: &str) -> Result<(), RomError> {
    for (i, want) in SNAPSHOT_COLUMN_NAMES.iter().enumerate() {
        match header.get(i) {
            Some(got) if got == *want => {}
            Some(got) => {
                let message = if SNAPSHOT_COLUMN_NAMES.contains(&got) {
                    format!("column {} is `{got}`, expected `{want}` (required columns must come first, in contract order)", i + 1)
                } else {
                    format!("unknown column `{got}` at position {}, expected `{want}` (extra columns are allowed only after `{}`)", i + 1, SNAPSHOT_COLUMN_NAMES[SNAPSHOT_COLUMN_NAMES.len() - 1])
                };
                return Err(RomError::Header {
                    source_name: source_name.to_string(),
                    message,
                });
            }
            None => {
                return Err(RomError::Header {
                    source_name: source_name.to_string(),
                    message: format!("missing required column `{want}` (position {})", i + 1),
                })
            }
        }
    }
    Ok(())
}

/// An integer cell: `9`, or a number with no fractional part such as `9.0` or `9e0` (what
/// pandas and spreadsheets write for an integer column with a missing value elsewhere).
/// `None` for anything else (`9.5`, `-1`, text).
pub fn parse_count(text: &str) -> Option<u32> {
    let t = text.trim();
    if let Ok(n) = t.parse::<u32>() {
        return Some(n);
    }
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) => {
            Some(v as u32)
        }
        _ => None,
    }
}

fn parse_row(c: &RowCells<'_>) -> Result<Option<SnapshotRow>, RomError> {
    let case_id = c.text(0)?;
    if case_id.is_empty() {
        return Err(c.err(0, case_id, "a non-empty case identifier"));
    }
    let converged = match c.text(8)?.to_ascii_lowercase().as_str() {
        "true" => true,
        "false" => false,
        other => return Err(c.err(8, other, "true or false")),
    };
    if !converged {
        return Ok(None);
    }
    let n_text = c.text(1)?;
    let n_bellows = match parse_count(n_text) {
        Some(n) if n >= 1 => n,
        _ => return Err(c.err(1, n_text, "a positive integer (9 or 9.0)")),
    };
    let inputs = CaseInputs {
        n_bellows,
        wall_thickness_mm: c.positive(2)?,
        material: OgdenSet {
            mu1_mpa: c.float(3)?,
            alpha1: c.float(4)?,
            mu2_mpa: c.float(5)?,
            alpha2: c.float(6)?,
        },
    };
    let m = &inputs.material;
    if m.mu1_mpa * m.alpha1 <= 0.0 {
        return Err(c.err(4, c.text(4)?, "μ₁α₁ > 0 (admissible Ogden term)"));
    }
    if m.mu2_mpa * m.alpha2 <= 0.0 {
        return Err(c.err(6, c.text(6)?, "μ₂α₂ > 0 (admissible Ogden term)"));
    }
    let pressure_bar = c.float(7)?;
    if pressure_bar < 0.0 {
        return Err(c.err(7, c.text(7)?, "a gauge pressure ≥ 0"));
    }
    let mut values = [0.0; 22];
    for (q, col) in [(Q_TIP_UZ, 9), (Q_TIP_UY, 10), (Q_ANGLE, 11), (Q_FORCE, 12)] {
        values[q] = c.float(col)?;
    }
    for k in 0..N_MARKER_COMPONENTS {
        values[k] = c.float(13 + k)?;
    }
    Ok(Some(SnapshotRow {
        case_id: case_id.to_string(),
        line: c.line,
        inputs,
        pressure_bar,
        values,
    }))
}

fn same_pressure(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs())
}

type Groups<'a> = Vec<(String, Vec<&'a SnapshotRow>)>;

fn group_by_case(set: &SnapshotSet) -> Result<Groups<'_>, RomError> {
    let mut index: HashMap<&str, usize> = HashMap::new();
    let mut groups: Groups<'_> = Vec::new();
    for row in &set.rows {
        let g = *index.entry(row.case_id.as_str()).or_insert_with(|| {
            groups.push((row.case_id.clone(), Vec::new()));
            groups.len() - 1
        });
        let rows = &mut groups[g].1;
        if let Some(first) = rows.first() {
            if first.inputs != row.inputs {
                return Err(RomError::Cell {
                    source_name: set.source.clone(),
                    line: row.line,
                    column: schema::CASE_ID.name.into(),
                    value: row.case_id.clone(),
                    expected: format!(
                        "the same design and material as line {} of this case",
                        first.line
                    ),
                });
            }
            if rows
                .iter()
                .any(|r| same_pressure(r.pressure_bar, row.pressure_bar))
            {
                return Err(RomError::Cell {
                    source_name: set.source.clone(),
                    line: row.line,
                    column: schema::PRESSURE.name.into(),
                    value: row.pressure_bar.to_string(),
                    expected: format!("a pressure not already given for case {}", row.case_id),
                });
            }
        }
        rows.push(row);
    }
    for (_, rows) in groups.iter_mut() {
        rows.sort_by(|a, b| a.pressure_bar.total_cmp(&b.pressure_bar));
    }
    Ok(groups)
}

fn common_grid(groups: &Groups<'_>) -> Vec<f64> {
    let mut counts: Vec<(f64, usize)> = Vec::new();
    for (_, rows) in groups {
        for r in rows {
            match counts
                .iter_mut()
                .find(|(p, _)| same_pressure(*p, r.pressure_bar))
            {
                Some(c) => c.1 += 1,
                None => counts.push((r.pressure_bar, 1)),
            }
        }
    }
    let mut grid: Vec<f64> = counts
        .into_iter()
        .filter(|&(_, c)| 2 * c >= groups.len())
        .map(|(p, _)| p)
        .collect();
    grid.sort_by(f64::total_cmp);
    grid
}

type Ramp = (Vec<[f64; 22]>, usize);
type Partial = (Vec<Option<[f64; 22]>>, String);

/// The case's ramp on the grid: interior gaps interpolated linearly; on failure (grid points
/// outside the case's converged range), the partial ramp and the reason.
fn ramp_on_grid(rows: &[&SnapshotRow], grid: &[f64]) -> Result<Ramp, Partial> {
    let mut values = Vec::with_capacity(grid.len());
    let mut filled = 0;
    let mut missing = Vec::new();
    for &p in grid {
        if let Some(r) = rows.iter().find(|r| same_pressure(r.pressure_bar, p)) {
            values.push(Some(r.values));
            continue;
        }
        let lo = rows.iter().rev().find(|r| r.pressure_bar < p);
        let hi = rows.iter().find(|r| r.pressure_bar > p);
        match (lo, hi) {
            (Some(a), Some(b)) => {
                let w = (p - a.pressure_bar) / (b.pressure_bar - a.pressure_bar);
                let mut v = [0.0; 22];
                for q in 0..22 {
                    v[q] = (1.0 - w) * a.values[q] + w * b.values[q];
                }
                values.push(Some(v));
                filled += 1;
            }
            _ => {
                values.push(None);
                missing.push(p.to_string());
            }
        }
    }
    if missing.is_empty() {
        Ok((values.into_iter().flatten().collect(), filled))
    } else {
        let reason = format!(
            "no converged result at {} bar (ramp truncated)",
            missing.join(", ")
        );
        Err((values, reason))
    }
}
