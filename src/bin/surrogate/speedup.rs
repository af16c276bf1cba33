//! `surrogate predict --bench-fe MESH --bench-out F.json`: the surrogate's speed-up over the
//! full FE model, both timed in the same run on the same machine.
//!
//! The FE side is one bending ramp of the query's design and material (gravity and contact on,
//! default solver settings, the model's pressure grid up to its last pressure): what a user
//! of the FE model pays for the responses that the surrogate returns. The surrogate side is
//! `predict_into` (all 22 outputs) and `predict_scalars_into` (tip, angle, force) at the same
//! pressures, repeated until at least half a second has passed.
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use surrogate::case::Query;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{simulate_with_progress, Case, ContactSettings, Mode};
use surrogate::fe::solver::SolverSettings;
use surrogate::rom::batch::material_params;
use surrogate::rom::Surrogate;

use crate::args::PredictArgs;

#[derive(Serialize)]
struct Speedup {
    model: String,
    n: u32,
    t_mm: f64,
    material: String,
    mesh: &'static str,
    threads: usize,
    pressures_bar: Vec<f64>,
    fe_dofs: usize,
    fe_ramp_wall_s: f64,
    fe_newton_iterations: usize,
    surrogate_all_outputs_ns_per_query: f64,
    surrogate_tip_angle_force_ns_per_query: f64,
    surrogate_ramp_us: f64,
    speedup_per_ramp: f64,
    speedup_per_query: f64,
    /// Largest |FE − surrogate| over the ramp (mm) for the tip; a sanity check, not the
    /// model's accuracy (that is its stored cross-validation).
    max_tip_difference_mm: f64,
}

/// Runs the benchmark and writes the JSON summary.
pub fn run(model: &Surrogate, a: &PredictArgs, mesh: &str, out: &Path) -> Result<()> {
    let level: MeshLevel = mesh.parse().map_err(anyhow::Error::msg)?;
    let (n, t) = (a.n.unwrap_or_default(), a.t.unwrap_or_default());
    let spec = a.material.clone().unwrap_or_default();
    let m = material_params(&spec)?;
    let pressures: Vec<f64> = model.pressures.clone();
    let queries: Vec<Query> = pressures.iter().map(|&p| Query::new(n, t, p, m)).collect();
    for q in &queries {
        model.check_query(q)?;
    }
    let mut fe_pressures = pressures.clone();
    if fe_pressures.first().is_some_and(|&p| p > 0.0) {
        fe_pressures.insert(0, 0.0);
    }
    let case = Case {
        design: DesignParams::new(n as usize, t).validate()?,
        material: Material::from_spec(&spec, DEFAULT_BULK_RATIO)?,
        pressures_bar: fe_pressures,
        gravity: true,
        mesh: MeshOptions::level(level),
        solver: SolverSettings::default(),
        mode: Mode::Bending,
        contact: ContactSettings::default(),
        effects: surrogate::fe::effects::Effects::default(),
    };
    eprintln!(
        "FE ramp: N = {n}, T = {t} mm, {spec}, {} mesh, 0 → {} bar ({} steps)",
        level.name(),
        pressures.last().copied().unwrap_or_default(),
        case.pressures_bar.len()
    );
    let bar = ProgressBar::new(case.pressures_bar.len() as u64 + 1);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} FE ramp [{bar:30}] {pos}/{len} load steps, {elapsed_precise}",
    )?);
    let t0 = Instant::now();
    let fe = simulate_with_progress(&case, |i, _| bar.set_position(i as u64))?;
    let fe_wall = t0.elapsed().as_secs_f64();
    bar.finish_and_clear();

    let mut pred = model.new_prediction();
    let time_per_query = |scalars: bool, pred: &mut surrogate::rom::Prediction| -> Result<f64> {
        let mut reps = 0usize;
        let start = Instant::now();
        while start.elapsed().as_secs_f64() < 0.5 {
            for q in &queries {
                if scalars {
                    model.predict_scalars_into(black_box(q), pred)?;
                } else {
                    model.predict_into(black_box(q), pred)?;
                }
            }
            reps += 1;
        }
        Ok(start.elapsed().as_secs_f64() * 1e9 / (reps * queries.len()) as f64)
    };
    let all_ns = time_per_query(false, &mut pred)?;
    let scalar_ns = time_per_query(true, &mut pred)?;
    let mut max_diff = 0.0f64;
    for (q, s) in queries
        .iter()
        .zip(fe.steps.iter().rev().take(queries.len()).rev())
    {
        model.predict_into(q, &mut pred)?;
        let d = (pred.tip_uz_mm() - s.tip_uz_mm).hypot(pred.tip_uy_mm() - s.tip_uy_mm);
        max_diff = max_diff.max(d);
    }
    let ramp_us = all_ns * queries.len() as f64 * 1e-3;
    let result = Speedup {
        model: a.model.display().to_string(),
        n,
        t_mm: t,
        material: spec,
        mesh: level.name(),
        threads: rayon::current_num_threads(),
        pressures_bar: pressures,
        fe_dofs: fe.dofs,
        fe_ramp_wall_s: fe_wall,
        fe_newton_iterations: fe.steps.iter().map(|s| s.newton_iterations).sum(),
        surrogate_all_outputs_ns_per_query: all_ns,
        surrogate_tip_angle_force_ns_per_query: scalar_ns,
        surrogate_ramp_us: ramp_us,
        speedup_per_ramp: fe_wall / (ramp_us * 1e-6),
        speedup_per_query: fe_wall / (all_ns * 1e-9),
        max_tip_difference_mm: max_diff,
    };
    let text = serde_json::to_string_pretty(&result)?;
    crate::files::write_file(out, text.as_bytes())?;
    println!("{text}");
    Ok(())
}
