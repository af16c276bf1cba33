//! `surrogate demo`: the main job on the data shipped in the repository.
//!
//! Today: the full FE model of one experimental design (default N = 11, T = 2.0 mm) with the
//! literature Ogden 002 parameters over 0–3 bar, compared with the shipped experiments (tip
//! Uz, Uy, angle and the study's bending error BE) and with the shipped surrogate at the same
//! inputs (values and time per query), printed and plotted.
use std::path::Path;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use plotters::prelude::*;
use surrogate::calibrate::experiments::{bending_error, shipped_bending, BendingRecord};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{simulate_with_progress, Case, ContactSettings, Mode, StepResult};
use surrogate::fe::solver::SolverSettings;
use surrogate::rom::{Query, Surrogate};

use crate::args::DemoArgs;

/// Runs the subcommand.
pub fn run(a: DemoArgs) -> Result<()> {
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let case = Case {
        design: DesignParams::new(a.n, a.t).validate()?,
        material: Material::from_spec(&a.material, 1000.0)?,
        pressures_bar: vec![0.0, 1.0, 2.0, 3.0],
        gravity: true,
        mesh: MeshOptions::level(level),
        solver: SolverSettings::default(),
        mode: Mode::Bending,
        contact: ContactSettings::default(),
    };
    eprintln!(
        "FE model: N = {}, T = {} mm, {}, {} mesh, gravity on, pressure 0 → 3 bar",
        a.n,
        a.t,
        a.material,
        level.name()
    );
    let bar = ProgressBar::new(5);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} FE ramp [{bar:30}] {pos}/{len} load steps, {elapsed_precise}",
    )?);
    let response = simulate_with_progress(&case, |i, _| bar.set_position(i as u64))?;
    bar.finish_and_clear();
    let experiments: Vec<BendingRecord> = shipped_bending()?
        .into_iter()
        .filter(|r| r.n_bellows == a.n && (r.wall_thickness_mm - a.t).abs() < 1e-9)
        .collect();
    println!(
        "FE: {} dofs, {:.1} s wall time ({:.1} s factorisation)",
        response.dofs, response.wall_time_s, response.factor_time_s
    );
    println!("| P (bar) | Uz sim | Uz exp | Uy sim | Uy exp | angle sim | angle exp | BE (mm) |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut errors = Vec::new();
    for s in &response.steps {
        let exp = experiments
            .iter()
            .find(|r| (r.pressure_bar - s.pressure_bar).abs() < 1e-9);
        match exp {
            Some(e) => {
                let be = bending_error(e.tip_uz_mm, e.tip_uy_mm, s.tip_uz_mm, s.tip_uy_mm);
                errors.push(be);
                println!(
                    "| {:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} | {:.2} |",
                    s.pressure_bar,
                    s.tip_uz_mm,
                    e.tip_uz_mm,
                    s.tip_uy_mm,
                    e.tip_uy_mm,
                    s.angle_deg,
                    e.angle_deg,
                    be
                );
            }
            None => println!(
                "| {:.0} | {:.2} | – | {:.2} | – | {:.1} | – | – |",
                s.pressure_bar, s.tip_uz_mm, s.tip_uy_mm, s.angle_deg
            ),
        }
    }
    if !errors.is_empty() {
        println!(
            "mean tip bending error BE = {:.2} mm over {} pressures (literature parameters, with contact)",
            errors.iter().sum::<f64>() / errors.len() as f64,
            errors.len()
        );
    }
    let surrogate_tips = surrogate_comparison(&a, &case, &response.steps, &response.wall_time_s);
    std::fs::create_dir_all(&a.out_dir)
        .with_context(|| format!("creating {}", a.out_dir.display()))?;
    let svg = a.out_dir.join("demo_tip.svg");
    plot(&svg, &response.steps, &experiments, &surrogate_tips, 92.0)?;
    let json = a.out_dir.join("demo_response.json");
    std::fs::write(&json, serde_json::to_string_pretty(&response)?)?;
    println!("wrote {} and {}", svg.display(), json.display());
    Ok(())
}

/// The shipped surrogate at the FE's inputs: a table beside the FE values, the time per
/// query and the tips `(P, Uz, Uy)` for the plot. A model that cannot be used (missing file,
/// this design or material outside it) is reported and skipped: the FE comparison stands.
fn surrogate_comparison(
    a: &DemoArgs,
    case: &Case,
    steps: &[StepResult],
    fe_wall_s: &f64,
) -> Vec<(f64, f64, f64)> {
    let model = match Surrogate::load(&a.model) {
        Ok(m) => m,
        Err(e) => {
            println!("surrogate: skipped ({e})");
            return Vec::new();
        }
    };
    let Some(params) = case.material.ogden_params() else {
        println!(
            "surrogate: skipped ({} is not an Ogden material)",
            a.material
        );
        return Vec::new();
    };
    let query = |p: f64| Query::new(a.n as u32, a.t, p, params);
    if let Err(e) = model.check_query(&query(0.0)) {
        println!("surrogate: skipped ({e})");
        return Vec::new();
    }
    let mut pred = model.new_prediction();
    let mut tips = Vec::new();
    println!();
    let tip_rmse = model
        .validation
        .outputs
        .iter()
        .find(|o| o.name == "tip_uz_mm")
        .map_or(f64::NAN, |o| o.total.rmse);
    println!(
        "Surrogate {} ({} training cases from {}; held-out tip Uz RMSE {:.2} mm):",
        a.model.display(),
        model.training.n_cases,
        model.training.source,
        tip_rmse
    );
    println!(
        "| P (bar) | Uz FE | Uz surrogate | Uy FE | Uy surrogate | angle FE | angle surrogate |"
    );
    println!("|---|---|---|---|---|---|---|");
    for s in steps {
        if model
            .predict_into(&query(s.pressure_bar), &mut pred)
            .is_err()
        {
            continue;
        }
        let v = &pred.values;
        println!(
            "| {:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} |",
            s.pressure_bar, s.tip_uz_mm, v[18], s.tip_uy_mm, v[19], s.angle_deg, v[20]
        );
        tips.push((s.pressure_bar, v[18], v[19]));
    }
    let n = 20_000;
    let t = std::time::Instant::now();
    for i in 0..n {
        let q = query(3.0 * (i % 100) as f64 / 99.0);
        if model.predict_into(&q, &mut pred).is_err() {
            return tips;
        }
    }
    let per_query = t.elapsed().as_secs_f64() / n as f64;
    println!(
        "surrogate: {:.2} µs per query (all 22 outputs); the FE ramp above took {:.1} s",
        per_query * 1e6,
        fe_wall_s
    );
    tips
}

/// Deformed marker lines (simulated), measured tips and surrogate tips in the (z, y) plane.
fn plot(
    path: &Path,
    steps: &[StepResult],
    exp: &[BendingRecord],
    surrogate_tips: &[(f64, f64, f64)],
    lf: f64,
) -> Result<()> {
    let root = SVGBackend::new(path, (800, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Bottom-face markers: FE (lines), measured tip (crosses), surrogate tip (circles)",
            ("sans-serif", 20),
        )
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..lf + 5.0, -90.0..10.0)?;
    chart
        .configure_mesh()
        .x_desc("z (mm)")
        .y_desc("y (mm)")
        .draw()?;
    let colors = [BLACK, BLUE, GREEN, RED, MAGENTA];
    for (i, s) in steps.iter().enumerate() {
        let c = colors[i % colors.len()];
        let mut pts = vec![(0.0, 0.0)];
        pts.extend(
            s.markers
                .iter()
                .enumerate()
                .map(|(k, m)| ((k + 1) as f64 * lf / 9.0 - m[0], m[1])),
        );
        chart
            .draw_series(LineSeries::new(pts, c.stroke_width(2)))?
            .label(format!("FE {:.0} bar", s.pressure_bar))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
        if let Some(e) = exp
            .iter()
            .find(|r| (r.pressure_bar - s.pressure_bar).abs() < 1e-9)
        {
            chart.draw_series(std::iter::once(Cross::new(
                (lf - e.tip_uz_mm, e.tip_uy_mm),
                6,
                c.stroke_width(2),
            )))?;
        }
        if let Some(&(_, uz, uy)) = surrogate_tips
            .iter()
            .find(|t| (t.0 - s.pressure_bar).abs() < 1e-9)
        {
            chart.draw_series(std::iter::once(Circle::new(
                (lf - uz, uy),
                5,
                c.stroke_width(2),
            )))?;
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
