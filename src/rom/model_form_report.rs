//! The model-form error from a calibration report: the residuals of its fitted
//! configurations, recomputed through a surrogate at the calibrated set
//! ([`from_calibration_report`], `surrogate model-form`). Apart from [`super::model_form`], which
//! the surrogate itself reads.

use std::path::Path;

use serde::Deserialize;

use super::model_form::{CalibrationSource, ModelFormError, Residual, SAME_MODEL_TOLERANCE};
use super::surrogate::Surrogate;
use super::{RomError, QUANTITY_NAMES, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::{OgdenSet, Query};

/// One configuration row of a calibration report (`calibration.configurations[]`).
#[derive(Debug, Deserialize)]
struct ReportRow {
    n_bellows: u32,
    wall_thickness_mm: f64,
    pressure_bar: f64,
    fitted: bool,
    uz_exp_mm: Option<f64>,
    uy_exp_mm: Option<f64>,
    angle_exp_deg: Option<f64>,
    force_exp_n: Option<f64>,
    uz_cal_mm: Option<f64>,
    uy_cal_mm: Option<f64>,
    angle_cal_deg: Option<f64>,
    force_cal_n: Option<f64>,
}

impl ReportRow {
    /// `(output, recorded, the report's prediction)` for each recorded output.
    fn recorded(&self) -> [(usize, Option<f64>, Option<f64>); 4] {
        [
            (Q_TIP_UZ, self.uz_exp_mm, self.uz_cal_mm),
            (Q_TIP_UY, self.uy_exp_mm, self.uy_cal_mm),
            (Q_ANGLE, self.angle_exp_deg, self.angle_cal_deg),
            (Q_FORCE, self.force_exp_n, self.force_cal_n),
        ]
    }
}

#[derive(Debug, Deserialize)]
struct ReportCalibration {
    model: String,
    objective: String,
    best: OgdenSet,
    configurations: Vec<ReportRow>,
}

#[derive(Debug, Deserialize)]
struct Report {
    calibration: ReportCalibration,
}

fn report_error(path: &str, field: &str, value: impl ToString, expected: &str) -> RomError {
    RomError::CalibrationReport {
        path: path.to_string(),
        field: field.to_string(),
        value: value.to_string(),
        expected: expected.to_string(),
    }
}

/// The model-form error of `model` from a calibration report (`report.json` of
/// `surrogate calibrate --out DIR`): the residuals of its fitted configurations, recomputed
/// through `model` at the calibrated set.
///
/// # Errors
/// [`RomError::Io`] for an unreadable file; [`RomError::CalibrationReport`] naming the field
/// for a report that is not JSON or lacks `calibration.best` or `calibration.configurations`,
/// for a configuration outside the model (an untrained N), or when the report's predictions
/// are not `model`'s (the report was made through another surrogate); as
/// [`ModelFormError::from_residuals`].
pub fn from_calibration_report(model: &Surrogate, path: &Path) -> Result<ModelFormError, RomError> {
    let shown = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| RomError::Io {
        path: shown.clone(),
        source,
    })?;
    let report: Report = serde_json::from_slice(&bytes).map_err(|e| {
        report_error(
            &shown,
            "calibration",
            e,
            "a calibration report (`report.json` of `surrogate calibrate --out DIR`) with \
             calibration.best and calibration.configurations",
        )
    })?;
    let cal = report.calibration;
    let material = cal.best;
    let mut pred = model.new_prediction();
    let mut residuals = Vec::new();
    let mut configurations = 0;
    for (i, row) in cal.configurations.iter().filter(|r| r.fitted).enumerate() {
        let field = |name: &str| format!("calibration.configurations[{i}].{name}");
        let q = Query::new(
            row.n_bellows,
            row.wall_thickness_mm,
            row.pressure_bar,
            material,
        );
        model.predict_into(&q, &mut pred).map_err(|e| {
            report_error(&shown, &field("n_bellows"), row.n_bellows, &e.to_string())
        })?;
        configurations += 1;
        for (o, recorded, reported) in row.recorded() {
            let Some(recorded) = recorded.filter(|v| v.is_finite()) else {
                continue;
            };
            let ours = pred.values[o];
            if let Some(theirs) = reported {
                if (ours - theirs).abs() > SAME_MODEL_TOLERANCE * theirs.abs().max(1.0) {
                    return Err(report_error(
                        &shown,
                        &field(QUANTITY_NAMES[o]),
                        format!(
                            "{theirs} (N = {}, T = {} mm, P = {} bar)",
                            row.n_bellows, row.wall_thickness_mm, row.pressure_bar
                        ),
                        &format!(
                            "this model's prediction {ours} at the calibrated set: the report \
                             names model {}; calibrate through this model first",
                            cal.model
                        ),
                    ));
                }
            }
            residuals.push(Residual {
                pressure_bar: row.pressure_bar,
                output: o,
                value: ours - recorded,
            });
        }
    }
    let source = CalibrationSource {
        report: shown,
        report_checksum: format!("crc32:{:08x}", crc32fast::hash(&bytes)),
        model: cal.model,
        objective: cal.objective,
        material,
        configurations,
    };
    ModelFormError::from_residuals(source, &residuals)
}
