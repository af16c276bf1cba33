//! A design loop through the surrogate: choose the number of bellows N and the wall thickness
//! T that reach a target bending angle and blocked force at 2 bar, with the material
//! calibrated to the shipped experiments.
//!
//! ```sh
//! cargo run --release --example optimise_design            # angle 40°, force 1.3 N
//! cargo run --release --example optimise_design -- 45 2.5  # angle 45°, force 2.5 N
//! ```
//!
//! For each trained N, the wall thickness is optimised by Gauss–Newton on
//! `((angle − a*)/1°)² + ((F − F*)/0.05 N)²` with the surrogate's analytic derivative in T
//! (clamped to the model's range of T), from a scan of 13 starting values.
//!
//! The pick is reported with its two errors: the surrogate's standard deviation (its error
//! against the FE model) and the model-form error the model file carries (how far the
//! calibrated model misses the recorded actuators, `surrogate::rom::model_form`), which is the
//! one to read as the prediction's accuracy.
use std::path::Path;

use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings};
use surrogate::case::Query;
use surrogate::rom::{Jacobian, Surrogate};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let target_angle = args.first().copied().unwrap_or(40.0);
    let target_force = args.get(1).copied().unwrap_or(1.3);
    let pressure = 2.0;

    let model = Surrogate::load(Path::new("models/actuator.json"))?;
    let cal = calibrate(
        &model,
        &Recordings::shipped()?,
        &CalibrationSettings::default(),
        &|_| {},
    )?;
    let material = cal.best.as_array();
    println!(
        "calibrated material: mu1 {:.4} MPa, alpha1 {:.3}, mu2 {:.3} MPa, alpha2 {:.3}",
        material[0], material[1], material[2], material[3]
    );
    println!("target at {pressure} bar: angle {target_angle}°, blocked force {target_force} N");

    let (t_min, t_max) = (model.inputs[1].min, model.inputs[1].max);
    let (s_angle, s_force) = (1.0, 0.05);
    let mut pred = model.new_prediction();
    let mut jac = Jacobian::default();
    let mut best: Option<(u32, f64, f64, f64, f64)> = None;
    for &n in &model.n_allowed {
        let mut best_n: Option<(f64, f64)> = None;
        for k in 0..13 {
            let mut t = t_min + (t_max - t_min) * k as f64 / 12.0;
            for _ in 0..30 {
                let q = Query::new(n, t, pressure, material);
                model.gradient_into(&q, &mut pred, &mut jac)?;
                let r = [
                    (pred.angle_deg() - target_angle) / s_angle,
                    (pred.force_n() - target_force) / s_force,
                ];
                let j = [
                    jac.angle().wall_thickness / s_angle,
                    jac.force().wall_thickness / s_force,
                ];
                let jtj = j[0] * j[0] + j[1] * j[1];
                if jtj <= 0.0 {
                    break;
                }
                let step = -(j[0] * r[0] + j[1] * r[1]) / jtj;
                let next = (t + step).clamp(t_min, t_max);
                if (next - t).abs() < 1e-9 {
                    break;
                }
                t = next;
            }
            let q = Query::new(n, t, pressure, material);
            model.predict_scalars_into(&q, &mut pred)?;
            let cost = ((pred.angle_deg() - target_angle) / s_angle).powi(2)
                + ((pred.force_n() - target_force) / s_force).powi(2);
            if best_n.is_none_or(|b| cost < b.1) {
                best_n = Some((t, cost));
            }
        }
        let (t, cost) = best_n.ok_or("no start")?;
        model.predict_scalars_into(&Query::new(n, t, pressure, material), &mut pred)?;
        println!(
            "N = {n:2}: T = {t:.3} mm -> angle {:.2}°, force {:.3} N (cost {cost:.2})",
            pred.angle_deg(),
            pred.force_n()
        );
        if best.is_none_or(|b| cost < b.4) {
            best = Some((n, t, pred.angle_deg(), pred.force_n(), cost));
        }
    }
    let (n, t, a, f, _) = best.ok_or("no design")?;
    println!(
        "best design: N = {n}, T = {t:.2} mm (angle {a:.2}°, force {f:.3} N at {pressure} bar)"
    );
    let q = Query::new(n, t, pressure, material);
    model.predict_with_std_into(&q, &mut pred)?;
    println!(
        "  surrogate vs FE (std): angle ±{:.2}°, force ±{:.3} N",
        pred.std_angle_deg(),
        pred.std_force_n()
    );
    match model.model_form_error(&q) {
        Some(e) => println!(
            "  {} at {pressure} bar: angle ±{:.2}°, force ±{:.3} N (rms; from {})",
            surrogate::rom::model_form::LABEL,
            e.angle_deg().unwrap_or(f64::NAN),
            e.force_n().unwrap_or(f64::NAN),
            model
                .model_form()
                .map_or("", |m| m.calibration.report.as_str())
        ),
        None => println!(
            "  {}: none in the model file; the accuracy against real actuators is not known",
            surrogate::rom::model_form::LABEL
        ),
    }
    Ok(())
}
