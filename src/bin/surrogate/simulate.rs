//! `surrogate simulate`: one design, one pressure ramp.
use std::io::Write;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{simulate_with_progress, Case};
use surrogate::fe::solver::SolverSettings;

use crate::args::SimulateArgs;

/// Parses a comma-separated pressure list.
pub fn parse_pressures(s: &str) -> Result<Vec<f64>> {
    s.split(',')
        .enumerate()
        .map(|(i, v)| {
            v.trim().parse::<f64>().with_context(|| {
                format!(
                    "--pressures: entry {} '{}' is not a number (expected e.g. 0,1,2,3)",
                    i + 1,
                    v.trim()
                )
            })
        })
        .collect()
}

fn build_case(a: &SimulateArgs, level: MeshLevel, pressures: Vec<f64>) -> Result<Case> {
    let design = DesignParams::new(a.n, a.t).validate()?;
    let material = Material::from_spec(&a.material, a.bulk_ratio)?;
    if let Some(h) = a.element_size {
        anyhow::ensure!(
            h.is_finite() && h > 0.05 && h <= 50.0,
            "--element-size {h}: expected a size in (0.05, 50] mm"
        );
    }
    Ok(Case {
        design,
        material,
        pressures_bar: pressures,
        gravity: !a.no_gravity,
        mesh: MeshOptions {
            level,
            element_size: a.element_size,
        },
        solver: SolverSettings {
            trace: std::env::var_os("SURROGATE_TRACE").is_some(),
            ..SolverSettings::default()
        },
    })
}

/// Runs the subcommand.
pub fn run(a: SimulateArgs) -> Result<()> {
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let pressures = parse_pressures(&a.pressures)?;
    let case = build_case(&a, level, pressures)?;
    let bar = ProgressBar::new(case.pressures_bar.len() as u64 + 1);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} simulate [{bar:30}] {pos}/{len} steps {elapsed_precise}",
    )?);
    let response = simulate_with_progress(&case, |i, _| bar.set_position(i as u64))?;
    bar.finish_and_clear();
    let json = serde_json::to_string_pretty(&response)?;
    match &a.out {
        Some(p) => std::fs::write(p, json).with_context(|| format!("writing {}", p.display()))?,
        None => writeln!(std::io::stdout(), "{json}")?,
    }
    Ok(())
}
