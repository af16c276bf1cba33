//! A mesh correction: identify on the coarse mesh what the standard mesh would give.
//!
//! The coarse mesh is about eight times cheaper per ramp than the standard one, but not the
//! same model: at the wall-law optimum of `fe_reference/identification/wall_law/` the standard
//! mesh bends 1–3 mm less at the tip, design by design. An identification on the coarse mesh
//! alone fits the coarse model, and its optimum then misses on the standard mesh by that
//! difference.
//!
//! The correction is the additive output correction of space mapping (Bandler et al., "Space
//! mapping: the state of the art", IEEE Trans. MTT 52 (2004), output space mapping): with
//! both meshes run once at a reference point `θ_c` (two `surrogate validate` tables),
//!
//! ```text
//!   y_corrected(θ) = y_coarse(θ) + (y_standard(θ_c) − y_coarse(θ_c))
//! ```
//!
//! per recorded configuration and output. It is exact at `θ_c`, and near it as far as the
//! meshes' difference does not change with `θ`; the Jacobian stays the coarse one. The
//! identification's optimum is then verified on the standard mesh, and if it moved far from
//! `θ_c`, the correction is taken again there.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::calibrate::baseline::BaselineRow;
use crate::calibrate::CalibrateError;

/// One configuration's correction: standard − coarse at the reference point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectionEntry {
    /// N.
    pub n_bellows: usize,
    /// T (mm).
    pub wall_thickness_mm: f64,
    /// P (bar).
    pub pressure_bar: f64,
    /// Added to the tip Uz (mm).
    pub uz_mm: f64,
    /// Added to the tip Uy (mm).
    pub uy_mm: f64,
    /// Added to the angle (deg).
    pub angle_deg: f64,
    /// Added to the blocked force (N).
    pub force_n: f64,
}

/// The mesh correction of an identification ([`super::JointSettings::correction`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshCorrection {
    /// Where the fine values came from (a file name).
    pub fine: String,
    /// Where the coarse values came from.
    pub coarse: String,
    /// One entry per configuration of the tables.
    pub entries: Vec<CorrectionEntry>,
}

impl MeshCorrection {
    /// The correction from two tables of the same configurations at the same point: `fine`
    /// (the standard mesh) and `coarse`, labelled for the report.
    ///
    /// # Errors
    /// [`CalibrateError::Input`] naming the configuration when a table lacks a configuration
    /// of the other or holds a value the FE did not reach (`NaN`).
    pub fn from_tables(
        fine: &[BaselineRow],
        coarse: &[BaselineRow],
        fine_label: &str,
        coarse_label: &str,
    ) -> Result<Self, CalibrateError> {
        let same = |a: &BaselineRow, b: &BaselineRow| {
            a.n_bellows == b.n_bellows
                && (a.wall_thickness_mm - b.wall_thickness_mm).abs() < 1e-9
                && (a.pressure_bar - b.pressure_bar).abs() < 1e-9
        };
        if fine.is_empty() {
            return Err(CalibrateError::input(
                "mesh correction",
                fine_label,
                "a table with at least one configuration",
            ));
        }
        for c in coarse {
            if !fine.iter().any(|f| same(f, c)) {
                return Err(CalibrateError::input(
                    "mesh correction",
                    fine_label,
                    &format!(
                        "a row for N = {}, T = {}, P = {} (it is in {coarse_label})",
                        c.n_bellows, c.wall_thickness_mm, c.pressure_bar
                    ),
                ));
            }
        }
        let mut entries = Vec::with_capacity(fine.len());
        for f in fine {
            let label = |file: &str| {
                format!(
                    "{file}: N = {}, T = {}, P = {}",
                    f.n_bellows, f.wall_thickness_mm, f.pressure_bar
                )
            };
            let c = coarse.iter().find(|c| same(f, c)).ok_or_else(|| {
                CalibrateError::input(
                    "mesh correction",
                    coarse_label,
                    &format!(
                        "a row for N = {}, T = {}, P = {} (it is in {fine_label})",
                        f.n_bellows, f.wall_thickness_mm, f.pressure_bar
                    ),
                )
            })?;
            for (row, file) in [(f, fine_label), (c, coarse_label)] {
                for (name, v) in [
                    ("uz_sim_mm", row.uz_sim_mm),
                    ("uy_sim_mm", row.uy_sim_mm),
                    ("angle_sim_deg", row.angle_sim_deg),
                    ("force_sim_n", row.force_sim_n),
                ] {
                    if !v.is_finite() {
                        return Err(CalibrateError::input(
                            name,
                            label(file),
                            "a finite FE value (this ramp did not reach it; rerun the table)",
                        ));
                    }
                }
            }
            entries.push(CorrectionEntry {
                n_bellows: f.n_bellows,
                wall_thickness_mm: f.wall_thickness_mm,
                pressure_bar: f.pressure_bar,
                uz_mm: f.uz_sim_mm - c.uz_sim_mm,
                uy_mm: f.uy_sim_mm - c.uy_sim_mm,
                angle_deg: f.angle_sim_deg - c.angle_sim_deg,
                force_n: f.force_sim_n - c.force_sim_n,
            });
        }
        Ok(MeshCorrection {
            fine: fine_label.to_string(),
            coarse: coarse_label.to_string(),
            entries,
        })
    }

    /// The correction from two `surrogate validate` tables (CSV) at the same point.
    ///
    /// # Errors
    /// An unreadable or malformed table (the file and the line), or the errors of
    /// [`from_tables`](Self::from_tables).
    pub fn read(fine: &Path, coarse: &Path) -> Result<Self, CalibrateError> {
        let f = read_table(fine)?;
        let c = read_table(coarse)?;
        Self::from_tables(
            &f,
            &c,
            &fine.display().to_string(),
            &coarse.display().to_string(),
        )
    }

    /// The correction of configuration `(n, t, p)`.
    pub fn at(&self, n: usize, t: f64, p: f64) -> Option<&CorrectionEntry> {
        self.entries.iter().find(|e| {
            e.n_bellows == n
                && (e.wall_thickness_mm - t).abs() < 1e-9
                && (e.pressure_bar - p).abs() < 1e-9
        })
    }

    /// Mean length of the tip correction over the entries (mm).
    pub fn mean_tip_mm(&self) -> f64 {
        let n = self.entries.len().max(1) as f64;
        self.entries
            .iter()
            .map(|e| e.uz_mm.hypot(e.uy_mm))
            .sum::<f64>()
            / n
    }

    /// Mean |force correction| over the entries (N).
    pub fn mean_abs_force_n(&self) -> f64 {
        let n = self.entries.len().max(1) as f64;
        self.entries.iter().map(|e| e.force_n.abs()).sum::<f64>() / n
    }
}

/// A `surrogate validate` table.
fn read_table(path: &Path) -> Result<Vec<BaselineRow>, CalibrateError> {
    let bad = |line: u64, why: String| {
        CalibrateError::input(
            "mesh correction table",
            format!("{}, line {line}", path.display()),
            &format!("a `surrogate validate` table ({why})"),
        )
    };
    let mut r = csv::Reader::from_path(path).map_err(|e| bad(0, e.to_string()))?;
    let mut out = Vec::new();
    for row in r.deserialize::<BaselineRow>() {
        let row = row.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            bad(line, e.to_string())
        })?;
        out.push(row);
    }
    Ok(out)
}
