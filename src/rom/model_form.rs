//! The model-form error: how far the calibrated model misses the recorded actuators.
//!
//! A prediction has two errors. The surrogate's standard deviation (`predict --std`,
//! [`super::Prediction::std`]) is its error against the FE model it was trained on, checked by
//! cross-validation. The FE model in turn misses the actuators that were built: after one
//! material is calibrated on the recordings ([`crate::calibrate`]), the residuals
//! `r = y_model(design, P, calibrated set) − y_recorded` keep a pattern no material removes
//! (on the shipped experiments: angle 8.9° rms, against the surrogate's 0.24°). That is the
//! *model-form error*, and it is what a designer should read as a prediction's accuracy for
//! actuators built and measured like the recorded ones.
//!
//! ## What is stored
//!
//! From the fitted configurations of a calibration report, per output `o` the calibration
//! recorded (tip Uz, tip Uy, angle, blocked force; the markers only if recorded, which the
//! calibration report's configuration table does not carry), with `r` recomputed through the
//! model the error is attached to (and checked against the report's own predictions):
//!
//! - `rms_o = √(mean r²)` over all residuals (mean bias included, not removed: a prediction is
//!   not corrected by it), and the mean `r̄_o`, reported;
//! - per recorded pressure level `P_j`, `rms_o(P_j)` over the designs recorded there, when at
//!   least [`MIN_LEVEL_RESIDUALS`] residuals support it;
//! - the reported error `e_o(P_j) = max(rms_o, rms_o(P_j))` (the global rms as a floor, so that
//!   a prediction at a recorded design is never given less than the calibration's rms
//!   residual), linear in `P` between levels and held at the nearer level outside them
//!   ([`surrogate_predict::model_form_at`], the same rule as exported models).
//!
//! ## Why pressure, and not N or T
//!
//! 27 configurations (9 designs × 3 pressures) do not support a surface in `(N, T, P)`. On the
//! shipped calibration each candidate dependence was scored by leaving each recorded design
//! out in turn and asking how likely its residuals are under the error learned from the other
//! eight (Gaussian, summed negative log-likelihood; lower is better), and how many of its
//! residuals lie within the error:
//!
//! | output | one rms | per pressure, floored | log-linear in (N, T, P), floored |
//! |---|---|---|---|
//! | tip Uz | 81.8, 21/27 | 80.1, 22/27 | 76.6, 22/27 |
//! | tip Uy | 69.3, 18/27 | 69.8, 19/27 | 71.9, 19/27 |
//! | angle | 76.8, 20/27 | 74.9, 22/27 | 75.2, 21/27 |
//! | force | −0.7, 16/27 | −1.3, 19/27 | −1.0, 20/27 |
//!
//! The growth with pressure (angle 4.4°, 8.7°, 11.8° rms at 1, 2, 3 bar) holds for every
//! design and is estimated from 9 residuals per level; a dependence on N and T (3 values each,
//! residuals correlated within a design) helps tip Uz but makes tip Uy worse held out, and its
//! four parameters per output would be fitted to 9 designs. So the error varies with pressure
//! only, floored by the global rms; with fewer residuals at a level than
//! [`MIN_LEVEL_RESIDUALS`], that level reports the global rms.

use serde::{Deserialize, Serialize};

use super::{RomError, QUANTITY_NAMES, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::OgdenSet;
use surrogate_predict::{marker_uy, marker_uz, model_form_at};

/// The label of the model-form error wherever it is printed.
pub const LABEL: &str = "model-form error (calibration residuals)";
/// The label of the surrogate's standard deviation (`--std`) beside it.
pub const STD_LABEL: &str = "surrogate vs FE";
/// Residuals an output needs for a model-form error (fewer: the output gets none).
pub const MIN_RESIDUALS: usize = 3;
/// Residuals a pressure level needs for its own rms (fewer: the level reports the global rms).
pub const MIN_LEVEL_RESIDUALS: usize = 5;
/// Largest relative difference between the report's predictions and the model's at the
/// calibrated set for the report to count as made through this model.
pub const SAME_MODEL_TOLERANCE: f64 = 1e-6;

/// The calibration a model-form error was learned from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CalibrationSource {
    /// The calibration report, as given to `surrogate model-form`.
    pub report: String,
    /// `crc32:…` of the report's bytes.
    pub report_checksum: String,
    /// The model the report names (`calibration.model`: checksum and provenance).
    pub model: String,
    /// The calibration's objective.
    pub objective: String,
    /// The calibrated Ogden set the residuals are taken at (in the file:
    /// `[μ₁ MPa, α₁, μ₂ MPa, α₂]`).
    #[serde(with = "crate::case::material::array")]
    pub material: OgdenSet,
    /// Fitted configurations (design and pressure) the residuals come from.
    pub configurations: usize,
}

/// The model-form error of one output ([module docs](self)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutputModelForm {
    /// The output (a column of [`QUANTITY_NAMES`]: `tip_uz_mm` …).
    pub name: String,
    /// Residuals.
    pub count: usize,
    /// Mean residual `predicted − recorded` (the bias; not removed from predictions).
    pub mean: f64,
    /// Root mean square residual over all levels: the floor.
    pub rms: f64,
    /// Residuals at each pressure level of [`ModelFormError::pressures`].
    pub level_count: Vec<usize>,
    /// Root mean square residual at each level (0 where none).
    pub level_rms: Vec<f64>,
    /// The reported error at each level: `max(rms, level_rms)` where the level has at least
    /// [`MIN_LEVEL_RESIDUALS`] residuals, else `rms`.
    pub at_levels: Vec<f64>,
}

/// The model-form error of a model, learned from a calibration ([module docs](self)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelFormError {
    /// What it was learned from.
    pub calibration: CalibrationSource,
    /// Recorded pressure levels, bar, increasing.
    pub pressures: Vec<f64>,
    /// Per output with enough residuals.
    pub outputs: Vec<OutputModelForm>,
}

/// One residual `predicted − recorded` of output `output` (an index among the 22) at a
/// recorded pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Residual {
    /// Recorded pressure, bar.
    pub pressure_bar: f64,
    /// Output index ([`super::Q_TIP_UZ`] …).
    pub output: usize,
    /// `predicted − recorded`, in the output's unit.
    pub value: f64,
}

/// The model-form error at one pressure, per output: `None` where the calibration recorded
/// nothing to learn it from (the markers of the shipped experiments).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelFormEstimate {
    /// The pressure, bar.
    pub pressure_bar: f64,
    /// Per output in [`QUANTITY_NAMES`] order, in the output's unit.
    pub values: [Option<f64>; 22],
}

impl ModelFormEstimate {
    /// Tip Uz, mm.
    pub fn tip_uz_mm(&self) -> Option<f64> {
        self.values[Q_TIP_UZ]
    }
    /// Tip Uy, mm.
    pub fn tip_uy_mm(&self) -> Option<f64> {
        self.values[Q_TIP_UY]
    }
    /// Bending angle, degrees.
    pub fn angle_deg(&self) -> Option<f64> {
        self.values[Q_ANGLE]
    }
    /// Blocked force, N.
    pub fn force_n(&self) -> Option<f64> {
        self.values[Q_FORCE]
    }
    /// Marker `k`'s `(Uz, Uy)`, mm, `k = 1 … 9`.
    ///
    /// # Panics
    /// `k` outside `1 … 9`.
    pub fn marker(&self, k: usize) -> (Option<f64>, Option<f64>) {
        (self.values[marker_uz(k)], self.values[marker_uy(k)])
    }
}

fn rms(v: impl Iterator<Item = f64>) -> (usize, f64) {
    let (n, s) = v.fold((0usize, 0.0), |(n, s), x| (n + 1, s + x * x));
    (n, if n == 0 { 0.0 } else { (s / n as f64).sqrt() })
}

/// Pressures closer than this (bar) are one level.
const LEVEL_MERGE_BAR: f64 = 1e-9;

impl ModelFormError {
    /// The model-form error of `residuals` ([module docs](self)).
    ///
    /// # Errors
    /// [`RomError::InvalidInput`]: a non-finite residual or pressure, an output index ≥ 22, or
    /// no output with [`MIN_RESIDUALS`] residuals.
    pub fn from_residuals(
        calibration: CalibrationSource,
        residuals: &[Residual],
    ) -> Result<Self, RomError> {
        for r in residuals {
            if r.output >= QUANTITY_NAMES.len() || !r.value.is_finite() {
                return Err(RomError::invalid(
                    "residual",
                    format!("{r:?}"),
                    "a finite residual of one of the 22 outputs",
                ));
            }
            if !r.pressure_bar.is_finite() {
                return Err(RomError::invalid(
                    "residual pressure_bar",
                    r.pressure_bar,
                    "a finite pressure",
                ));
            }
        }
        let mut pressures: Vec<f64> = residuals.iter().map(|r| r.pressure_bar).collect();
        pressures.sort_by(f64::total_cmp);
        pressures.dedup_by(|a, b| (*a - *b).abs() <= LEVEL_MERGE_BAR);
        let level = |p: f64| {
            pressures
                .iter()
                .position(|&l| (l - p).abs() <= LEVEL_MERGE_BAR)
        };
        let mut outputs = Vec::new();
        for (o, name) in QUANTITY_NAMES.iter().enumerate() {
            let of = |r: &&Residual| r.output == o;
            let (count, rms_o) = rms(residuals.iter().filter(of).map(|r| r.value));
            if count < MIN_RESIDUALS {
                continue;
            }
            let mean = residuals.iter().filter(of).map(|r| r.value).sum::<f64>() / count as f64;
            let (level_count, level_rms): (Vec<usize>, Vec<f64>) = (0..pressures.len())
                .map(|j| {
                    rms(residuals
                        .iter()
                        .filter(|r| r.output == o && level(r.pressure_bar) == Some(j))
                        .map(|r| r.value))
                })
                .unzip();
            let at_levels = level_count
                .iter()
                .zip(&level_rms)
                .map(|(&n, &e)| {
                    if n >= MIN_LEVEL_RESIDUALS {
                        e.max(rms_o)
                    } else {
                        rms_o
                    }
                })
                .collect();
            outputs.push(OutputModelForm {
                name: name.to_string(),
                count,
                mean,
                rms: rms_o,
                level_count,
                level_rms,
                at_levels,
            });
        }
        if outputs.is_empty() {
            return Err(RomError::invalid(
                "calibration residuals",
                format!("{} residuals", residuals.len()),
                &format!("at least {MIN_RESIDUALS} residuals of one output"),
            ));
        }
        Ok(ModelFormError {
            calibration,
            pressures,
            outputs,
        })
    }

    /// The error of output `q` (an index among the 22) at `p_bar`; `None` where nothing was
    /// learned for it, or for a non-finite pressure.
    pub fn error(&self, q: usize, p_bar: f64) -> Option<f64> {
        let name = QUANTITY_NAMES.get(q)?;
        let o = self.outputs.iter().find(|o| o.name == *name)?;
        model_form_at(&self.pressures, &o.at_levels, p_bar)
    }

    /// The error of every output at `p_bar`.
    pub fn at(&self, p_bar: f64) -> ModelFormEstimate {
        ModelFormEstimate {
            pressure_bar: p_bar,
            values: std::array::from_fn(|q| self.error(q, p_bar)),
        }
    }

    /// The tables of an exported model ([`surrogate_predict::ModelFormTables`]): the levels,
    /// the output indices and the errors output-major.
    pub fn tables(&self) -> (Vec<f64>, Vec<u8>, Vec<f64>) {
        let index = |name: &str| QUANTITY_NAMES.iter().position(|q| *q == name);
        let mut outputs = Vec::new();
        let mut values = Vec::new();
        for o in &self.outputs {
            if let Some(q) = index(&o.name) {
                outputs.push(q as u8);
                values.extend_from_slice(&o.at_levels);
            }
        }
        (self.pressures.clone(), outputs, values)
    }

    /// Internal consistency (a loaded model file): known outputs, increasing levels, tables
    /// of one length, finite non-negative errors, each at least its output's rms.
    ///
    /// # Errors
    /// A message naming the field, its value and what it should be.
    pub fn check(&self) -> Result<(), String> {
        let l = self.pressures.len();
        if l == 0
            || self.pressures.iter().any(|p| !p.is_finite())
            || self.pressures.windows(2).any(|w| w[0] >= w[1])
        {
            return Err(format!(
                "model_form.pressures = {:?}: expected at least one finite level, increasing",
                self.pressures
            ));
        }
        if self.outputs.is_empty() {
            return Err("model_form.outputs is empty: expected at least one output".into());
        }
        for o in &self.outputs {
            if !QUANTITY_NAMES.contains(&o.name.as_str()) {
                return Err(format!(
                    "model_form output name = {:?}: expected one of the 22 outputs",
                    o.name
                ));
            }
            if o.level_count.len() != l || o.level_rms.len() != l || o.at_levels.len() != l {
                return Err(format!(
                    "model_form output {}: {} counts, {} rms, {} errors: expected {l} each (one per level)",
                    o.name,
                    o.level_count.len(),
                    o.level_rms.len(),
                    o.at_levels.len()
                ));
            }
            let bad = |v: f64| !v.is_finite() || v < 0.0;
            if bad(o.rms) || o.level_rms.iter().any(|&v| bad(v)) || !o.mean.is_finite() {
                return Err(format!(
                    "model_form output {}: rms {} / level rms {:?} / mean {}: expected finite, rms ≥ 0",
                    o.name, o.rms, o.level_rms, o.mean
                ));
            }
            if let Some(e) = o.at_levels.iter().find(|&&e| bad(e) || e < o.rms) {
                return Err(format!(
                    "model_form output {}: error {e} at a level: expected finite and at least the output's rms {}",
                    o.name, o.rms
                ));
            }
        }
        Ok(())
    }

    /// The table of the error: one line per output (rms, bias, the error at each level).
    pub fn table(&self) -> String {
        let levels: Vec<String> = self.pressures.iter().map(|p| format!("{p} bar")).collect();
        let mut out = format!(
            "{LABEL}: calibrated model − recorded, {} configurations of {} (objective {}, model {})\n\
             output          n     rms    bias   at {}\n",
            self.calibration.configurations,
            self.calibration.report,
            self.calibration.objective,
            self.calibration.model,
            levels.join(", ")
        );
        for o in &self.outputs {
            let at: Vec<String> = o.at_levels.iter().map(|e| format!("{e:.4}")).collect();
            out.push_str(&format!(
                "{:<12} {:>4} {:>7.4} {:>7.4}   {}\n",
                o.name,
                o.count,
                o.rms,
                o.mean,
                at.join(", ")
            ));
        }
        out
    }
}
