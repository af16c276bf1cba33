//! A design loop through the surrogate: choose the number of bellows N and the wall thickness
//! T that reach a target bending angle and blocked force at 2 bar, with the material
//! calibrated to the shipped experiments, over every N from 7 to 15 the shipped model predicts.
//!
//! ```sh
//! cargo run --release --example optimise_design            # angle 40°, force 1.3 N
//! cargo run --release --example optimise_design -- 45 2.5  # angle 45°, force 2.5 N
//! ```
//!
//! `surrogate::design::search` minimises `((angle − a*)/1°)² + ((F − F*)/0.05 N)²` in T for
//! every N the model predicts (bounded Gauss–Newton with the surrogate's analytic derivative
//! in T, from 13 starts, T capped by the model's range and by the walls that leave a cavity).
//!
//! The pick is reported with its two errors: the surrogate's standard deviation (its error
//! against the FE model) and the model-form error the model file carries (how far the
//! calibrated model misses the recorded actuators, `surrogate::rom::model_form`), which is the
//! one to read as the prediction's accuracy.
use std::path::Path;

use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings, Weights};
use surrogate::design::{search, DesignBounds, DesignSearch, Output, Target};
use surrogate::rom::Surrogate;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let target_angle = args.first().copied().unwrap_or(40.0);
    let target_force = args.get(1).copied().unwrap_or(1.3);
    let pressure = 2.0;

    let model = Surrogate::load(Path::new("models/actuator.json"))?;
    // tip, angle and blocked force: the objective the model-form error was learned with
    let settings = CalibrationSettings {
        weights: Weights::parse("tip,angle,force")?,
        ..CalibrationSettings::default()
    };
    let cal = calibrate(&model, &Recordings::shipped()?, &settings, &|_| {})?;
    let material = cal.best;
    println!(
        "calibrated material: mu1 {:.4} MPa, alpha1 {:.3}, mu2 {:.3} MPa, alpha2 {:.3}",
        material.mu1_mpa, material.alpha1, material.mu2_mpa, material.alpha2
    );
    println!("target at {pressure} bar: angle {target_angle}°, blocked force {target_force} N");

    let targets = [
        Target::new(Output::AngleDeg, pressure, target_angle, 1.0),
        Target::new(Output::ForceN, pressure, target_force, 0.05),
    ];
    let bounds = DesignBounds::of_model(&model);
    let report = search(
        &model,
        material,
        &targets,
        &bounds,
        &DesignSearch::default(),
    )?;
    for d in &report.designs {
        let Some(c) = &d.best else {
            println!("N = {:2}: no buildable wall", d.n);
            continue;
        };
        println!(
            "N = {:2}: T = {:.3} mm -> angle {:.2}°, force {:.3} N (cost {:.2})",
            d.n, c.t_mm, c.predicted[0], c.predicted[1], c.cost
        );
    }
    let pick = &report.pick;
    let (angle, force) = (&pick.outputs[0], &pick.outputs[1]);
    println!(
        "best design: N = {}, T = {:.2} mm (angle {:.2}°, force {:.3} N at {pressure} bar)",
        pick.n, pick.t_mm, angle.predicted, force.predicted
    );
    println!(
        "  surrogate vs FE (std): angle ±{:.2}°, force ±{:.3} N",
        angle.surrogate_std, force.surrogate_std
    );
    match (angle.model_form, force.model_form) {
        (Some(a), Some(f)) => println!(
            "  {} at {pressure} bar: angle ±{a:.2}°, force ±{f:.3} N (rms)",
            report.accuracy
        ),
        _ => println!("  {}", report.accuracy),
    }
    Ok(())
}
