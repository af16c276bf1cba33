//! How well a fit predicts the recordings: the tip bending error, the force error and `χ²`,
//! the noise level a perfect model would show, and a fit's summary.

use super::outcome::{FitSummary, Quality};
use super::problem::{Fitted, Problem};
use crate::calibrate::objective::Output;
use crate::diagnose::cells::Cell;
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;

/// The quality of `pred` against the recordings of `cells`.
pub(crate) fn quality(cells: &[Cell], pred: &[f64]) -> Quality {
    let z: Vec<f64> = cells
        .iter()
        .zip(pred)
        .map(|(c, p)| (p - c.recorded) / c.sigma)
        .collect();
    let mut be = Vec::new();
    let mut force = Vec::new();
    for (i, c) in cells.iter().enumerate() {
        match c.output {
            Output::TipUz => {
                if let Some(k) = cells.iter().position(|o| {
                    o.output == Output::TipUy
                        && o.n_bellows == c.n_bellows
                        && o.wall_thickness_mm == c.wall_thickness_mm
                        && o.pressure_bar == c.pressure_bar
                }) {
                    be.push((pred[i] - c.recorded).hypot(pred[k] - cells[k].recorded));
                }
            }
            Output::Force => force.push(pred[i] - c.recorded),
            _ => {}
        }
    }
    let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    let mut rms_z: Vec<(String, f64)> = Vec::new();
    for f in crate::diagnose::cells::Family::ALL {
        let zs: Vec<f64> = cells
            .iter()
            .zip(&z)
            .filter(|(c, _)| c.family == f)
            .map(|(_, v)| v * v)
            .collect();
        if let Some(m) = mean(&zs) {
            rms_z.push((f.label().to_string(), m.sqrt()));
        }
    }
    Quality {
        n_cells: cells.len(),
        chi2: z.iter().map(|v| v * v).sum(),
        mean_be_mm: mean(&be),
        mean_force_error_n: mean(&force),
        mean_abs_force_error_n: mean(&force.iter().map(|v| v.abs()).collect::<Vec<_>>()),
        rms_z,
    }
}

/// The mean tip BE of pure noise: `σ_tip √(π/2)` averaged over the configurations with tip
/// Uz and Uy.
pub(crate) fn noise_be(cells: &[Cell]) -> Option<f64> {
    let v: Vec<f64> = cells
        .iter()
        .filter(|c| c.output == Output::TipUz)
        .map(|c| c.sigma * std::f64::consts::FRAC_PI_2.sqrt())
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

pub(crate) fn summary(
    pb: &Problem<'_>,
    f: &Fitted,
    effects: &[Effect],
) -> Result<FitSummary, DiagnoseError> {
    let u = [f.x[0], f.x[1], f.x[2], f.x[3]];
    let names = pb.space.names();
    let mut active_bounds = Vec::new();
    for (i, &a) in f.active.iter().enumerate() {
        if !a {
            continue;
        }
        if i < 4 {
            let side = if f.x[i] <= 0.5 { "lower" } else { "upper" };
            active_bounds.push(format!(
                "{} at its {side} bound {}",
                names[i],
                pb.space.physical(i, f.x[i])
            ));
        } else {
            let e = effects[i - 4].info();
            active_bounds.push(format!(
                "{} at the end of its range ({})",
                e.name,
                pb.rows.value(i - 4, f.x[i])
            ));
        }
    }
    Ok(FitSummary {
        material: pb.space.ogden(&u)?,
        effects: (0..pb.k).map(|k| pb.rows.value(k, f.x[4 + k])).collect(),
        quality: quality(&pb.rows.cells, &pb.predictions(&f.x)?),
        iterations: f.iterations,
        stop: f.stop.to_string(),
        active_bounds,
    })
}
