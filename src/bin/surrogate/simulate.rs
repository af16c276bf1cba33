//! `surrogate simulate`: one design, one pressure ramp (or `--bench`: the FE benchmark).
use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;
use surrogate::fe::sensitivity::{sensitivities_with, Parameter, Sensitivities};
use surrogate::fe::simulate::{
    simulate_with, ActuatorModel, Case, ContactSettings, Mode, Response, StepResult,
};
use surrogate::fe::solver::{MinimiseSettings, SolverKind, SolverSettings};
use surrogate::fe::vtk;

use crate::args::{ModeArg, SimulateArgs, SolverArg};

fn build_case(a: &SimulateArgs, level: MeshLevel, pressures: Vec<f64>) -> Result<Case> {
    let geometry = Geometry::from_name(&a.geometry).context("--geometry")?;
    let design = if geometry.is_as_modelled() {
        DesignParams::new(a.n, a.t).validate()?
    } else {
        geometry.design(a.n, a.t)?
    };
    let material = Material::from_spec(&a.material, a.bulk_ratio)?;
    anyhow::ensure!(
        a.max_increment.is_finite() && a.max_increment > 0.0 && a.max_increment <= 5.0,
        "--max-increment {}: expected a pressure increment in (0, 5] bar",
        a.max_increment
    );
    let case = Case {
        design,
        material,
        pressures_bar: pressures,
        gravity: !a.no_gravity,
        mesh: MeshOptions {
            level,
            element_size: a.refinement.element_size,
            wall_elements: a.refinement.wall_elements,
        },
        solver: SolverSettings {
            trace: std::env::var_os("SURROGATE_TRACE").is_some(),
            max_pressure_increment: a.max_increment * surrogate::fe::simulate::BAR,
            line_search: a.line_search,
            rtol: a.rtol,
            predictor: !a.no_predictor,
            grow_below_iterations: a.grow_below,
            augmented_updates: a.augmented,
            reuse_factor: !a.no_reuse_factor,
            kind: match a.solver {
                SolverArg::Newton => SolverKind::Newton,
                SolverArg::Minimise => SolverKind::Minimise(MinimiseSettings {
                    dhat_mm: a.barrier_dhat,
                    barrier_pressure: a.barrier_pressure,
                    ..MinimiseSettings::default()
                }),
            },
            ..SolverSettings::default()
        },
        mode: match a.mode {
            ModeArg::Bending => Mode::Bending,
            ModeArg::Force => Mode::Force,
        },
        contact: ContactSettings {
            enabled: !a.no_contact,
            stiffness: a.contact_stiffness,
            smoothing: a.contact_smoothing,
            closest_point: a.closest_point_contact,
        },
        effects: surrogate::fe::effects::Effects::parse(a.effect.iter().map(String::as_str))?,
    };
    case.validate().map_err(|e| match e {
        // name the command-line flag
        surrogate::fe::simulate::SimulateError::Setting(s) => {
            let flag = match s.field.as_str() {
                "mesh.element_size" => "--element-size",
                "mesh.wall_elements" => "--wall-elements",
                "solver.rtol" => "--rtol",
                "solver.augmented_updates" => "--augmented",
                "solver.kind.dhat_mm" => "--barrier-dhat",
                "solver.kind.barrier_pressure" => "--barrier-pressure",
                other => other,
            };
            anyhow::anyhow!("{flag} {}: expected {}", s.value, s.expected)
        }
        other => other.into(),
    })?;
    Ok(case)
}

fn run_case(case: &Case, vtk_dir: Option<&PathBuf>, label: &str) -> Result<Response> {
    Ok(run_case_with(case, vtk_dir, label, None)?.0)
}

/// A ramp with a progress bar and VTK output, and the sensitivities to `parameters` if
/// given.
fn run_case_with(
    case: &Case,
    vtk_dir: Option<&PathBuf>,
    label: &str,
    parameters: Option<&[Parameter]>,
) -> Result<(Response, Option<Sensitivities>)> {
    let bar = ProgressBar::new(case.pressures_bar.len() as u64 + 1);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} {msg} [{bar:30}] {pos}/{len} load steps, {elapsed_precise}",
    )?);
    bar.set_message(label.to_string());
    let mut written = Vec::new();
    let mut vtk_error = None;
    let total = case.pressures_bar.len();
    let mut done = 0usize;
    let on_result = |model: &ActuatorModel, result: &StepResult, u: &[f64]| {
        done += 1;
        // a line per converged step where the bar is not drawn (a log file, a pipe)
        if bar.is_hidden() {
            eprintln!(
                    "{label}: step {done}/{total}: {} bar, tip Uz {:.3} mm, Uy {:.3} mm, {} Newton iterations",
                    result.pressure_bar, result.tip_uz_mm, result.tip_uy_mm, result.newton_iterations
                );
        }
        if let Some(dir) = vtk_dir {
            match vtk::write_step(dir, written.len(), model, u) {
                Ok(p) => written.push((result.pressure_bar, p)),
                Err(e) => vtk_error = Some(e),
            }
        }
    };
    let progress = |i, _| bar.set_position(i as u64);
    let (response, sens) = match parameters {
        Some(p) => {
            let (r, s) = sensitivities_with(case, p, progress, on_result)?;
            (r, Some(s))
        }
        None => (simulate_with(case, progress, on_result)?, None),
    };
    bar.finish_and_clear();
    if let Some(e) = vtk_error {
        return Err(e).context("writing VTK output");
    }
    if let Some(dir) = vtk_dir {
        vtk::write_collection(dir, &written)
            .with_context(|| format!("writing {}", dir.display()))?;
        eprintln!(
            "wrote {} steps to {}/steps.pvd",
            written.len(),
            dir.display()
        );
    }
    Ok((response, sens))
}

/// Newton iterations and substeps to reach one output level of a benchmark ramp.
#[derive(Serialize)]
struct BenchLevel {
    pressure_bar: f64,
    newton_iterations: usize,
    substeps: usize,
}

#[derive(Serialize)]
struct BenchRow {
    mesh: &'static str,
    solver: &'static str,
    nodes: usize,
    elements: usize,
    dofs: usize,
    wall_time_s: f64,
    factor_time_s: f64,
    assembly_time_s: f64,
    factor_share: f64,
    newton_iterations: usize,
    substeps: usize,
    newton_per_substep: f64,
    tip_uz_mm_3bar: f64,
    tip_uy_mm_3bar: f64,
    factorizations: usize,
    /// Per output level (the first is the self-weight at 0 bar).
    levels: Vec<BenchLevel>,
    /// Blocked force at 3 bar (N), in force mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    force_n_3bar: Option<f64>,
}

fn write_output(out: Option<&PathBuf>, json: &str, what: &str) -> Result<()> {
    match out.filter(|p| p.as_os_str() != "-") {
        Some(p) => {
            crate::files::write_file(p, json.as_bytes())
                .with_context(|| format!("writing {}", p.display()))?;
            eprintln!("wrote {what} to {}", p.display());
        }
        None => writeln!(std::io::stdout(), "{json}")?,
    }
    Ok(())
}

/// Runs the subcommand.
pub fn run(a: SimulateArgs) -> Result<()> {
    if a.bench {
        return bench(&a);
    }
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let pressures = surrogate::fe::simulate::parse_pressures(&a.pressures)?;
    let case = build_case(&a, level, pressures)?;
    let parameters = match &a.sensitivities {
        Some(list) => Some(Parameter::parse_list(list).context("--sensitivities")?),
        None => None,
    };
    let (response, sens) = run_case_with(&case, a.vtk.as_ref(), "simulate", parameters.as_deref())?;
    if let Some(sens) = sens {
        let path = sensitivity_path(&a);
        crate::files::write_file(&path, serde_json::to_string_pretty(&sens)?.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        print_sensitivities(&sens);
        eprintln!(
            "wrote the sensitivities to {} (ramp {:.1} s, sensitivities {:.1} s: {:.0} % more)",
            path.display(),
            sens.cost.ramp_s,
            sens.cost.sensitivity_s,
            100.0 * sens.cost.overhead
        );
    }
    let what = format!(
        "{} steps ({:.1} s, {} dofs)",
        response.steps.len(),
        response.wall_time_s,
        response.dofs
    );
    write_output(
        a.out.as_ref(),
        &serde_json::to_string_pretty(&response)?,
        &what,
    )
}

/// Where `--sensitivities` writes: `--sensitivities-out`, or beside `--out` as
/// `<stem>_sensitivities.json`, or `sensitivities.json`.
fn sensitivity_path(a: &SimulateArgs) -> PathBuf {
    if let Some(p) = &a.sensitivities_out {
        return p.clone();
    }
    match a.out.as_ref().filter(|p| p.as_os_str() != "-") {
        Some(out) => {
            let stem = out
                .file_stem()
                .map_or("simulate".into(), |s| s.to_string_lossy());
            out.with_file_name(format!("{stem}_sensitivities.json"))
        }
        None => PathBuf::from("sensitivities.json"),
    }
}

/// The last step's derivatives of the tip, the angle and the force, one line per parameter.
fn print_sensitivities(s: &Sensitivities) {
    let Some(last) = s.steps.last() else { return };
    eprintln!(
        "derivatives at {} bar (per unit of the parameter):\n  {:<24} {:>8} {:>12} {:>12} {:>12}{}",
        last.pressure_bar,
        "parameter",
        "unit",
        "tip Uz mm",
        "tip Uy mm",
        "angle deg",
        if last.values.force_n.is_some() {
            "      force N"
        } else {
            ""
        }
    );
    for (p, d) in s.parameters.iter().zip(&last.derivatives) {
        eprintln!(
            "  {:<24} {:>8} {:>12.4e} {:>12.4e} {:>12.4e}{}",
            p.parameter.name(),
            p.unit,
            d.tip_uz_mm,
            d.tip_uy_mm,
            d.angle_deg,
            d.force_n.map_or(String::new(), |f| format!(" {f:>12.4e}"))
        );
    }
}

/// `--bench`: the full ramp 0 → 3 bar on each mesh level (or the one given with --mesh if it
/// is not the default), one JSON row per level.
fn bench(a: &SimulateArgs) -> Result<()> {
    let levels: Vec<MeshLevel> = if a.mesh == "all" {
        vec![MeshLevel::Coarse, MeshLevel::Standard, MeshLevel::Fine]
    } else {
        a.mesh
            .split(',')
            .map(|m| m.parse().map_err(anyhow::Error::msg))
            .collect::<Result<_>>()?
    };
    let mut rows = Vec::new();
    for level in levels {
        let case = build_case(a, level, vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0])?;
        let r = run_case(&case, None, level.name())?;
        let iters: usize = r.steps.iter().map(|s| s.newton_iterations).sum();
        let substeps: usize = r.steps.iter().map(|s| s.substeps).sum();
        let last = r.steps.last().context("no step")?;
        let row = BenchRow {
            mesh: level.name(),
            solver: match a.solver {
                SolverArg::Newton => "newton",
                SolverArg::Minimise => "minimise",
            },
            nodes: r.nodes,
            elements: r.elements,
            dofs: r.dofs,
            wall_time_s: r.wall_time_s,
            factor_time_s: r.factor_time_s,
            assembly_time_s: r.assembly_time_s,
            factor_share: r.factor_time_s / r.wall_time_s,
            newton_iterations: iters,
            substeps,
            newton_per_substep: iters as f64 / substeps.max(1) as f64,
            tip_uz_mm_3bar: last.tip_uz_mm,
            tip_uy_mm_3bar: last.tip_uy_mm,
            factorizations: r.factorizations,
            levels: r
                .steps
                .iter()
                .map(|s| BenchLevel {
                    pressure_bar: s.pressure_bar,
                    newton_iterations: s.newton_iterations,
                    substeps: s.substeps,
                })
                .collect(),
            force_n_3bar: last.force_n,
        };
        eprintln!(
            "{:>8}: {} dofs, {:.1} s ({:.0} % factorisation), {} Newton iterations in {} substeps",
            row.mesh,
            row.dofs,
            row.wall_time_s,
            100.0 * row.factor_share,
            row.newton_iterations,
            row.substeps
        );
        rows.push(row);
    }
    write_output(
        a.out.as_ref(),
        &serde_json::to_string_pretty(&rows)?,
        "the benchmark",
    )
}
