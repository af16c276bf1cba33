//! `surrogate demo`: the main job on the data shipped in the repository.
//!
//! 1. The shipped surrogate (the identified geometry, every N from 7 to 15): its held-out
//!    accuracy.
//! 2. Calibration of one Ogden set to all 27 experimental configurations through it (tip,
//!    angle and blocked force, the identification's objective), with the identifiability
//!    analysis and the time per query, compared with the literature set and with the study's
//!    own figures (report and plots in `<out>/calibration/`). The study's per-configuration
//!    procedure is asked for and reported as skipped: its box around Ogden 002 lies outside
//!    the shipped model's domain.
//! 3. The committed FE verification of the calibrated set on the standard mesh (read from
//!    its ramp cache; nothing is recomputed), and the committed adaptive refinements of the
//!    models of the geometry as modelled.
//! 4. One design re-verified live by the full FE model on a mesh that finishes in a couple of
//!    minutes, beside the experiments and the surrogate of that mesh.
//! 5. Where the calibrated model still misses the experiments: the diagnoser's located
//!    residual, in words, and the effects of the library ranked by how much of it each
//!    explains, from the committed FE sensitivities at the calibrated material (report and
//!    plots in `<out>/diagnosis/`).
use std::path::Path;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use plotters::prelude::*;
use surrogate::calibrate::baseline::{SweepSensitivities, SweepSettings};
use surrogate::calibrate::experiments::{bending_error, shipped_bending, BendingRecord};
use surrogate::calibrate::refine::Refinement;
use surrogate::calibrate::verify::{cached_verification, fe_material, FeVerification};
use surrogate::calibrate::{calibrate, Calibration, CalibrationSettings, Recordings, Weights};
use surrogate::case::{OgdenSet, Query};
use surrogate::diagnose::locate::{locate, LocateSettings};
use surrogate::diagnose::name::NameSettings;
use surrogate::diagnose::refit::RefitSettings;
use surrogate::diagnose::Diagnosis;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{simulate_with_progress, Case, Mode, StepResult};
use surrogate::rom::Surrogate;
use surrogate::schema;

use crate::args::DemoArgs;
use crate::calibrate::{summary_text, write_outputs};
use crate::files::{given_or_announced, repository_file, DEFAULT_MODEL};

/// A committed adaptive refinement (`calibrate --refine`).
struct CommittedRefinement {
    /// What was refined against what.
    what: &'static str,
    /// Its rounds (the run's `refinement.json`), in the repository's `data/`.
    rounds: &'static str,
    /// The run's directory in the repository (its account `refinement.md`, its FE cases).
    run: &'static str,
}

/// The committed adaptive refinements (of the models of the geometry as modelled, before the
/// identification).
const REFINEMENTS: [CommittedRefinement; 2] = [
    CommittedRefinement {
        what: "the as-modelled coarse-mesh surrogate against coarse FE",
        rounds: "data/demo/refine_coarse.json",
        run: "fe_reference/calibration/refine_coarse",
    },
    CommittedRefinement {
        what: "the as-modelled multi-fidelity surrogate against standard-mesh FE",
        rounds: "data/demo/refine_standard.json",
        run: "fe_reference/calibration/refine_standard",
    },
];

/// The committed FE ramps of the calibrated set on the standard mesh, in the repository.
const FE_CACHE: &str = "data/demo/fe_standard_ramps";

/// The committed FE sensitivities of the effect library at the calibrated material, in the
/// repository.
const SENSITIVITIES: &str = surrogate::diagnose::setup::SHIPPED_SENSITIVITIES;

/// The calibration's objective: the identification's (tip, angle and blocked force).
const OBJECTIVE: &str = "tip,angle,force";

/// Runs the subcommand.
pub fn run(a: DemoArgs) -> Result<()> {
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    std::fs::create_dir_all(&a.out_dir)
        .with_context(|| format!("creating {}", a.out_dir.display()))?;
    let (model_path, _) = given_or_announced("model", a.model.as_deref(), DEFAULT_MODEL);
    let (fe_cache, _) = given_or_announced("fe-cache", a.fe_cache.as_deref(), FE_CACHE);
    // 1. the surrogate
    let model = Surrogate::load(&model_path)
        .with_context(|| format!("loading the surrogate {}", model_path.display()))?;
    println!("# 1. The surrogate\n");
    describe_model(&model, &model_path);
    // 2. calibration through it
    println!("\n# 2. Calibration to the shipped experiments, through the surrogate\n");
    let rec = Recordings::shipped()?;
    let settings = CalibrationSettings {
        weights: Weights::parse(OBJECTIVE)?,
        per_configuration: Some(0.1),
        ..CalibrationSettings::default()
    };
    let cal = calibrate(&model, &rec, &settings, &|stage| eprintln!("{stage}"))?;
    // 3. the committed standard-mesh FE verification
    let verified = cal.best.rounded(4);
    let fe = cached_verification(
        &model,
        &rec,
        &verified,
        MeshOptions::level(MeshLevel::Standard),
        &fe_cache,
    )?;
    let fe_complete = fe.incomplete < fe.rows.len();
    let cal_dir = a.out_dir.join("calibration");
    std::fs::create_dir_all(&cal_dir)?;
    let written = write_outputs(&cal_dir, &cal, fe_complete.then_some(&fe))?;
    print!("{}", summary_text(&cal, None));
    time_queries(&model, cal.best);
    println!("\n# 3. FE verification of the calibrated set (standard mesh, committed)\n");
    committed_fe(&fe, &cal, &fe_cache);
    println!("\nBefore the identification (models/as_modelled/):");
    for r in &REFINEMENTS {
        committed_refinement(r);
    }
    // 4. one design live
    println!(
        "\n# 4. One design re-verified live: N = {}, T = {} mm, {} mesh\n",
        a.n,
        a.t,
        level.name()
    );
    let material = if a.material == "calibrated" {
        fe_material(&verified)?
    } else {
        Material::from_spec(&a.material, DEFAULT_BULK_RATIO)?
    };
    live(&a, level, material, &cal, &model)?;
    // 5. where the calibrated model and the experiments still disagree
    println!("\n# 5. Where the calibrated model and the experiments disagree (diagnose: locate, name, refit)\n");
    let loc = locate(&cal, &model, &rec, &LocateSettings::default())?;
    let mut diagnosis = Diagnosis::new(&cal, &rec, loc);
    for f in &diagnosis.locate.findings {
        println!("- {}", f.text);
    }
    name_and_refit(&mut diagnosis, &model, &model_path)?;
    let diag_dir = a.out_dir.join("diagnosis");
    std::fs::create_dir_all(&diag_dir)?;
    let mut written = written;
    written.extend(crate::diagnose::write_outputs(&diag_dir, &diagnosis)?);
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Step 5's Name and Model stages on the committed FE sensitivities (coarse mesh, calibrated
/// material): the candidates, then the named effect (or the strongest plausible lead) refitted
/// with the material, each design left out in turn.
fn name_and_refit(diagnosis: &mut Diagnosis, model: &Surrogate, model_path: &Path) -> Result<()> {
    let sens_path = repository_file(SENSITIVITIES);
    match SweepSensitivities::read(&sens_path) {
        Ok(sens) => {
            println!(
                "\nWhich effect of the library explains it (FE sensitivities of {} ramps at the \
                 calibrated material, {} mesh, precomputed in {}):\n",
                sens.designs.len(),
                sens.mesh.level.name(),
                sens_path.display()
            );
            // the model's own mesh error, measured against the other shipped mesh, is a
            // candidate too
            let other = surrogate::diagnose::setup::other_shipped_model(model_path);
            if let Some((reference, name)) = other
                .map(|p| crate::files::load_mesh_reference(&p))
                .transpose()?
            {
                let me = diagnosis.mesh_error_with(model, &reference, &name)?;
                println!(
                    "The model's own mesh error: {name} differs from it by {:.2} σ rms at the \
                     calibrated material (candidate `{}`).\n",
                    me.rms_sigma, me.direction.name
                );
            }
            let n = diagnosis.name_with(&sens, model, &NameSettings::default())?;
            println!("{}", n.verdict);
            crate::diagnose::print_candidates(n, 5);
            // Model and show: the named effect, or else the strongest plausible lead, refitted
            // with the material and tried on designs the fit did not see
            let named = n.named().map(|c| c.effect.clone());
            let lead = named.clone().or_else(|| {
                n.candidates
                    .iter()
                    .find(|c| c.plausible && !c.model_error)
                    .map(|c| c.effect.clone())
            });
            if let Some(e) = lead {
                println!(
                    "\n{} {e}: material + {e} refitted through the surrogate (the effect \
                     linearised), each design left out in turn:\n",
                    if named.is_some() {
                        "The named effect"
                    } else {
                        "Nothing is named; the strongest plausible lead, tried anyway:"
                    }
                );
                let effect = surrogate::fe::effects::Effect::from_name(&e)?;
                let r = diagnosis.refit_with(&sens, model, &RefitSettings::new(vec![effect]))?;
                println!("{}", r.verdict);
            }
        }
        Err(e) => println!("\nThe Name stage is skipped: {e}"),
    }
    Ok(())
}

fn describe_model(model: &Surrogate, path: &Path) {
    let v = |name: &str| {
        model
            .validation
            .outputs
            .iter()
            .find(|o| o.name == name)
            .map_or(f64::NAN, |o| o.total.rmse)
    };
    println!(
        "{} ({} training cases; {}): held-out RMSE tip Uz {:.2} mm, tip Uy {:.2} mm, angle {:.2}°, force {:.3} N",
        path.display(),
        model.training.n_cases,
        model.training.source,
        v(schema::TIP_UZ.name),
        v(schema::TIP_UY.name),
        v(schema::ANGLE.name),
        v(schema::FORCE.name)
    );
}

/// The time per query of tip, angle and force at N = 11, T = 2 mm, 0 to 3 bar, with the
/// material `set` (the calibrated one: inside the model's domain by construction).
fn time_queries(model: &Surrogate, set: OgdenSet) {
    let mut pred = model.new_prediction();
    let n = 20_000;
    let t = std::time::Instant::now();
    for i in 0..n {
        let q = Query::new(11, 2.0, 3.0 * (i % 100) as f64 / 99.0, set);
        if let Err(e) = model.predict_scalars_into(&q, &mut pred) {
            println!("time per query: not measured ({e})");
            return;
        }
    }
    println!(
        "The surrogate answers tip, angle and force in {:.2} µs per query (N = 11, T = 2 mm, the calibrated set).",
        t.elapsed().as_secs_f64() / n as f64 * 1e6
    );
}

/// The committed FE ramps of the calibrated set, as far as they are computed.
fn committed_fe(v: &FeVerification, cal: &Calibration, cache: &Path) {
    let n = v.rows.len();
    let done = n - v.incomplete;
    if done == 0 {
        println!(
            "No committed FE ramp of the set {} in {} yet: `surrogate calibrate --objective tip,angle,force --per-configuration --verify-fe standard --fe-cache data/demo/fe_standard_ramps --out fe_reference/calibration/identified_standard` computes them (18 ramps, about 2 core-hours) and caches each one.",
            cal.best.rounded(4).spec(),
            cache.display()
        );
        return;
    }
    let s = &v.summary;
    println!(
        "{done} of {n} configurations have their FE ramps committed ({}).",
        cache.display()
    );
    println!(
        "| over those | mean BE (mm) | median BE (mm) | mean F error (N) |\n|---|---|---|---|"
    );
    let sel: Vec<_> = v.rows.iter().filter(|r| r.fe.error.is_empty()).collect();
    let mean = |f: &dyn Fn(&&surrogate::calibrate::verify::FeCheckRow) -> f64| {
        let x: Vec<f64> = sel.iter().map(f).filter(|x| x.is_finite()).collect();
        x.iter().sum::<f64>() / x.len().max(1) as f64
    };
    println!(
        "| FE, calibrated set | {:.2} | {:.2} | {:+.3} |",
        s.mean_be_mm, s.median_be_mm, s.mean_force_error_n
    );
    println!(
        "| surrogate, calibrated set | {:.2} | | {:+.3} |",
        mean(&|r| bending_error(r.fe.uz_exp_mm, r.fe.uy_exp_mm, r.uz_sur_mm, r.uy_sur_mm)),
        mean(&|r| r.force_sur_n - r.fe.force_exp_n)
    );
    println!(
        "Surrogate vs FE: mean |Δ| tip Uz {:.2} mm, tip Uy {:.2} mm, force {:.3} N; {} configurations outside the surrogate's 2σ band.",
        v.mean_abs_sur_fe[0], v.mean_abs_sur_fe[1], v.mean_abs_sur_fe[2], v.disagreements
    );
}

/// The rounds of a committed refinement, or how far it got.
fn committed_refinement(c: &CommittedRefinement) {
    let (what, rounds, dir) = (c.what, repository_file(c.rounds), repository_file(c.run));
    let Ok(text) = std::fs::read_to_string(&rounds) else {
        println!(
            "\nAdaptive refinement of {what}: not finished (`surrogate calibrate --refine 3 --out {}`, then its refinement.json to {}; its FE cases are committed in {}/refine/ as they finish, and a rerun resumes).",
            dir.display(),
            rounds.display(),
            dir.display()
        );
        return;
    };
    let Ok(r) = serde_json::from_str::<Refinement>(&text) else {
        println!(
            "\n{} is not a refinement report of this version",
            rounds.display()
        );
        return;
    };
    println!(
        "\nAdaptive refinement of {what} ({}/refinement.md):",
        dir.display()
    );
    for x in &r.rounds {
        let v = &x.verification;
        println!(
            "- round {}: {} training cases, set {}; FE mean BE {:.2} mm; surrogate − FE max |Δ| {:.2} / {:.2} mm, {:.3} N; {} of {} configurations beyond 2σ",
            x.round,
            x.model_cases,
            x.set.spec(),
            v.summary.mean_be_mm,
            v.max_abs_sur_fe[0],
            v.max_abs_sur_fe[1],
            v.max_abs_sur_fe[2],
            v.disagreements,
            v.rows.len()
        );
    }
    for sh in &r.shifts {
        println!(
            "- after round {}: the refit {} moves the recorded numbers by {:.2} σ rms, at most {:.2} σ",
            sh.round,
            sh.to.spec(),
            sh.rms_z,
            sh.max_abs_z
        );
    }
    println!("Stopped: {}.", r.stop.describe());
    if let Some(c) = &r.final_check {
        println!(
            "The retrained surrogate ({} cases) against that FE: max |Δ| {:.2} / {:.2} mm, {:.3} N; {} of {} configurations beyond 2σ.",
            r.last_model_cases,
            c.max_abs_sur_fe[0],
            c.max_abs_sur_fe[1],
            c.max_abs_sur_fe[2],
            c.disagreements,
            c.rows.len()
        );
    }
}

/// The live FE run of one design, beside the experiments and the surrogate of its mesh.
fn live(
    a: &DemoArgs,
    level: MeshLevel,
    material: Material,
    cal: &Calibration,
    model: &Surrogate,
) -> Result<()> {
    // built as the calibrating model's training cases were (geometry, fixed effects)
    let case = SweepSettings::new(material, MeshOptions::level(level))
        .built_as(model.training.built_with.as_ref())
        .case(a.n, a.t, vec![0.0, 1.0, 2.0, 3.0], Mode::Bending)?;
    eprintln!(
        "FE model: N = {}, T = {} mm, {}, {} mesh, gravity and contact on, 0 → 3 bar",
        a.n,
        a.t,
        if a.material == "calibrated" {
            format!("calibrated set {}", cal.best.rounded(4).spec())
        } else {
            a.material.clone()
        },
        level.name()
    );
    let bar = ProgressBar::new(4);
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
            "mean tip bending error BE = {:.2} mm over {} pressures ({} mesh; the coarse mesh is about 5 % stiffer than the standard one)",
            errors.iter().sum::<f64>() / errors.len() as f64,
            errors.len(),
            level.name()
        );
    }
    let surrogate_tips = surrogate_comparison(a, &case, &response.steps, &response.wall_time_s);
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
    let (live_model, _) = given_or_announced(
        "live-model",
        a.live_model.as_deref(),
        "models/actuator_coarse.json",
    );
    let model = match Surrogate::load(&live_model) {
        Ok(m) => m,
        Err(e) => {
            println!("surrogate: skipped ({e})");
            return Vec::new();
        }
    };
    let Some(params) = case.material.ogden_set() else {
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
        .find(|o| o.name == schema::TIP_UZ.name)
        .map_or(f64::NAN, |o| o.total.rmse);
    println!(
        "Surrogate {} ({} training cases from {}; held-out tip Uz RMSE {:.2} mm):",
        live_model.display(),
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
