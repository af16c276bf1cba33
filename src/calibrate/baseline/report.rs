//! The comparison with the recordings: one row per bending record (simulated and measured tip,
//! angle, blocked force, their errors) from the ramps of its design, and the table's summary,
//! over every configuration and over the reference study's nine.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::cache::BaselineError;
use super::ramps::{cached_ramps, run_ramps, SweepRamp};
use super::settings::{recorded_designs, SweepSettings};
use crate::calibrate::experiments::{bending_error, BendingRecord, ForceRecord};
use crate::fe::simulate::Mode;

/// One row of the baseline table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaselineRow {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Measured tip Uz (mm).
    pub uz_exp_mm: f64,
    /// Simulated tip Uz (mm).
    pub uz_sim_mm: f64,
    /// Measured tip Uy (mm).
    pub uy_exp_mm: f64,
    /// Simulated tip Uy (mm).
    pub uy_sim_mm: f64,
    /// Measured angle (deg).
    pub angle_exp_deg: f64,
    /// Simulated angle (deg).
    pub angle_sim_deg: f64,
    /// Tip bending error (mm).
    pub be_mm: f64,
    /// Measured blocked force (N).
    pub force_exp_n: f64,
    /// Simulated blocked force (N).
    pub force_sim_n: f64,
    /// `F_sim − F_exp` (N).
    pub force_error_n: f64,
    /// Solver message if a ramp stopped before this pressure (its values are then `NaN`);
    /// empty when absent from a table (tables written before the column existed).
    #[serde(default)]
    pub error: String,
}

/// Summary of a baseline table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaselineSummary {
    /// Configurations.
    pub configurations: usize,
    /// Configurations the FE did not reach (bending or force).
    pub failed: usize,
    /// Mean BE (mm).
    pub mean_be_mm: f64,
    /// Median BE (mm).
    pub median_be_mm: f64,
    /// Mean |F_sim − F_exp| (N).
    pub mean_abs_force_error_n: f64,
    /// Mean F_sim − F_exp (N): positive = over-prediction.
    pub mean_force_error_n: f64,
    /// Mean F_sim − F_exp (N) at the highest measured pressure (3 bar in the shipped data).
    pub mean_force_error_top_pressure_n: f64,
    /// The highest measured pressure (bar).
    pub top_pressure_bar: f64,
    /// Configurations of the reference study's nine found in the table (see
    /// [`in_paper_nine`]).
    #[serde(alias = "l9_configurations")]
    pub paper_nine_configurations: usize,
    /// Mean BE over the reference study's nine (mm).
    #[serde(alias = "l9_mean_be_mm")]
    pub paper_nine_mean_be_mm: f64,
    /// Median BE over the reference study's nine (mm).
    #[serde(alias = "l9_median_be_mm")]
    pub paper_nine_median_be_mm: f64,
}

/// Whether a configuration is one of the reference study's nine: the study compared its model
/// on nine of the 27 configurations in which T and P move together (T at its lowest level with
/// P at its lowest, the middle with the middle, the highest with the highest: T 1.6 mm at
/// 1 bar, 2.0 at 2 bar, 2.4 at 3 bar), for each N (its Fig. 8 and Table 8). With level
/// indices `j` of T and `k` of P in increasing order: `k = j`. `None` when a value is not one
/// of three levels.
pub fn in_paper_nine(
    levels_n: &[usize],
    levels_t: &[f64],
    levels_p: &[f64],
    n: usize,
    t: f64,
    p: f64,
) -> Option<bool> {
    if levels_n.len() != 3 || levels_t.len() != 3 || levels_p.len() != 3 {
        return None;
    }
    levels_n.iter().position(|&v| v == n)?;
    let j = levels_t.iter().position(|&v| (v - t).abs() < 1e-9)?;
    let k = levels_p.iter().position(|&v| (v - p).abs() < 1e-9)?;
    Some(k == j)
}

fn sorted_levels(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs the sweep for one material; `progress(done, total)` after every FE ramp. A ramp that
/// stops keeps the pressures it reached; the others get `NaN` values and the solver's message
/// in [`BaselineRow::error`].
///
/// # Errors
/// An invalid experimental design (N or T out of the model's range); a cache directory that
/// cannot be written.
pub fn run_baseline(
    settings: &SweepSettings,
    bending: &[BendingRecord],
    force: &[ForceRecord],
    cache: Option<&Path>,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<Vec<BaselineRow>, BaselineError> {
    let ramps = run_ramps(settings, &recorded_designs(bending), cache, progress)?;
    Ok(rows(&ramps, bending, force))
}

/// The rows of the ramps already in `cache`, without running any FE: a ramp that is not
/// cached gives `NaN` values and `not in the cache` in [`BaselineRow::error`] (a quick look
/// at a sweep that is still running, or at a committed one).
///
/// # Errors
/// An invalid experimental design.
pub fn cached_baseline(
    settings: &SweepSettings,
    bending: &[BendingRecord],
    force: &[ForceRecord],
    cache: &Path,
) -> Result<Vec<BaselineRow>, BaselineError> {
    let ramps = cached_ramps(settings, &recorded_designs(bending), cache)?;
    Ok(rows(&ramps, bending, force))
}

/// The baseline table: one row per bending record, from the ramps of its design.
fn rows(ramps: &[SweepRamp], bending: &[BendingRecord], force: &[ForceRecord]) -> Vec<BaselineRow> {
    let mut rows = Vec::new();
    for rec in bending {
        let find = |mode: Mode| {
            ramps
                .iter()
                .find(|r| {
                    r.mode == mode
                        && r.n_bellows == rec.n_bellows
                        && r.wall_thickness_mm == rec.wall_thickness_mm
                })
                .map(|r| (r.at(rec.pressure_bar), r.error.as_str()))
                .unwrap_or((None, "not run"))
        };
        let ((b, eb), (f, ef)) = (find(Mode::Bending), find(Mode::Force));
        let nan = f64::NAN;
        let (uz, uy, angle) =
            b.map_or((nan, nan, nan), |b| (b.tip_uz_mm, b.tip_uy_mm, b.angle_deg));
        let mut error = Vec::new();
        if b.is_none() {
            error.push(format!("bending: {eb}"));
        }
        if f.is_none() {
            error.push(format!("force: {ef}"));
        }
        let f_exp = force
            .iter()
            .find(|r| {
                r.n_bellows == rec.n_bellows
                    && r.wall_thickness_mm == rec.wall_thickness_mm
                    && r.pressure_bar == rec.pressure_bar
            })
            .map_or(f64::NAN, |r| r.force_n);
        let f_sim = f.and_then(|f| f.force_n).unwrap_or(f64::NAN);
        rows.push(BaselineRow {
            n_bellows: rec.n_bellows,
            wall_thickness_mm: rec.wall_thickness_mm,
            pressure_bar: rec.pressure_bar,
            uz_exp_mm: rec.tip_uz_mm,
            uz_sim_mm: uz,
            uy_exp_mm: rec.tip_uy_mm,
            uy_sim_mm: uy,
            angle_exp_deg: rec.angle_deg,
            angle_sim_deg: angle,
            be_mm: bending_error(rec.tip_uz_mm, rec.tip_uy_mm, uz, uy),
            force_exp_n: f_exp,
            force_sim_n: f_sim,
            force_error_n: f_sim - f_exp,
            error: error.join("; "),
        });
    }
    rows
}

/// Mean / median BE and force errors of a table, over the configurations the FE reached; the
/// same over the reference study's nine ([`in_paper_nine`]), and the force error at the top pressure.
pub fn summarize(rows: &[BaselineRow]) -> BaselineSummary {
    let mut be: Vec<f64> = rows
        .iter()
        .map(|r| r.be_mm)
        .filter(|v| v.is_finite())
        .collect();
    let fe: Vec<f64> = rows
        .iter()
        .map(|r| r.force_error_n)
        .filter(|v| v.is_finite())
        .collect();
    let levels_n: Vec<usize> = sorted_levels(rows.iter().map(|r| r.n_bellows as f64))
        .into_iter()
        .map(|v| v as usize)
        .collect();
    let levels_t = sorted_levels(rows.iter().map(|r| r.wall_thickness_mm));
    let levels_p = sorted_levels(rows.iter().map(|r| r.pressure_bar));
    let nine: Vec<&BaselineRow> = rows
        .iter()
        .filter(|r| {
            in_paper_nine(
                &levels_n,
                &levels_t,
                &levels_p,
                r.n_bellows,
                r.wall_thickness_mm,
                r.pressure_bar,
            ) == Some(true)
        })
        .collect();
    let mut nine_be: Vec<f64> = nine
        .iter()
        .map(|r| r.be_mm)
        .filter(|v| v.is_finite())
        .collect();
    let top = levels_p.last().copied().unwrap_or(f64::NAN);
    let fe_top: Vec<f64> = rows
        .iter()
        .filter(|r| (r.pressure_bar - top).abs() < 1e-9)
        .map(|r| r.force_error_n)
        .filter(|v| v.is_finite())
        .collect();
    BaselineSummary {
        configurations: rows.len(),
        failed: rows.iter().filter(|r| !r.error.is_empty()).count(),
        mean_be_mm: mean(&be),
        median_be_mm: median(&mut be),
        mean_abs_force_error_n: mean(&fe.iter().map(|v| v.abs()).collect::<Vec<_>>()),
        mean_force_error_n: mean(&fe),
        mean_force_error_top_pressure_n: mean(&fe_top),
        top_pressure_bar: top,
        paper_nine_configurations: nine.len(),
        paper_nine_mean_be_mm: mean(&nine_be),
        paper_nine_median_be_mm: median(&mut nine_be),
    }
}
