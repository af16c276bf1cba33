//! `surrogate diagnose`: calibrate, then locate the residual ([`surrogate::diagnose`]); the
//! report as JSON and Markdown, and its figures.
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use surrogate::calibrate::baseline::{SweepSensitivities, SweepSettings};
use surrogate::calibrate::experiments::{BENDING_FILE, FORCE_FILE, MARKERS_FILE};
use surrogate::calibrate::inputs::InputFile;
use surrogate::calibrate::objective::Exclusion;
use surrogate::calibrate::{CalibrationSettings, Recordings, Selection, Weights};
use surrogate::diagnose::approx_error::ApproximationError;
use surrogate::diagnose::measure_design::{MeasurementPlan, PlanSettings};
use surrogate::diagnose::name::Naming;
use surrogate::diagnose::refit::{
    ranked_candidates, FeConfirmSettings, FeRankSettings, RefitSettings,
};
use surrogate::diagnose::report::Stage;
use surrogate::diagnose::setup::{
    ApproximationSource, DiagnosisSetup, ResolvedFile, ResolvedSetup, Sensitivities,
};
use surrogate::diagnose::summary::summary_markdown;
use surrogate::diagnose::sweep::sweep_at;
use surrogate::diagnose::{diagnose, DiagnoseSettings, Diagnosis, LocateSettings};
use surrogate::fe::effects::Effect;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::rom::Surrogate;

use crate::args::DiagnoseArgs;
use crate::diagnose_plots::write_plots;
use crate::files::{
    announced, given_or_default, input_file, load_mesh_reference, load_model, repository_root,
    write_file,
};

/// The validated settings of the run.
fn settings(a: &DiagnoseArgs) -> Result<DiagnoseSettings> {
    let exclude = a
        .exclude
        .iter()
        .map(|e| Exclusion::parse(e))
        .collect::<Result<Vec<_>, _>>()?;
    let locate = LocateSettings { alpha: a.alpha };
    locate.validate()?;
    Ok(DiagnoseSettings {
        calibration: CalibrationSettings {
            weights: Weights::parse(&a.objective)?,
            selection: Selection {
                exclude,
                ..Selection::default()
            },
            exclude_flagged: a.exclude_flagged,
            ..CalibrationSettings::default()
        },
        locate,
    })
}

/// The recordings of `dir`; a path that is not a directory says what was expected there.
/// `default`: the repository's `training_data/`, said on stderr and in the report.
fn recordings(dir: &Path, default: bool) -> Result<Recordings> {
    if !dir.is_dir() {
        anyhow::bail!(
            "--recordings {}: not a directory (expected a directory holding {BENDING_FILE} and, \
             where recorded, {FORCE_FILE} and {MARKERS_FILE}, like training_data/)",
            dir.display()
        );
    }
    let rec = Recordings::read_dir(dir)
        .with_context(|| format!("reading the recordings in {}", dir.display()))?;
    if default {
        for f in &rec.files {
            eprintln!("no --recordings: reading {} (the default)", f.path);
        }
        return Ok(rec.as_defaults());
    }
    Ok(rec)
}

/// The FE sensitivities of the setup's file (none for `calibrated` and `none`).
fn sensitivities(
    choice: &Sensitivities<ResolvedFile>,
) -> Result<Option<(SweepSensitivities, InputFile)>> {
    let Sensitivities::File(f) = choice else {
        return Ok(None);
    };
    let sens = SweepSensitivities::read(&f.path).with_context(|| {
        format!(
            "--sensitivities {}: expected the file `validate --sensitivities all` writes (or \
             calibrated, none)",
            f.path.display()
        )
    })?;
    let p = announced("sensitivities", f);
    Ok(Some((sens, input_file("sensitivities", p, f.default)?)))
}

/// Runs the subcommand: the inputs read and the flags checked before any work, then
/// calibrate and locate ([`diagnose`]), the mesh error, Name and Model and show where the
/// FE sensitivities allow them, the report written and its stages printed.
pub fn run(a: DiagnoseArgs) -> Result<()> {
    let s = settings(&a)?;
    let setup = a
        .setup
        .setup(DiagnosisSetup::recordings())
        .resolve(repository_root())?;
    let mut inputs = Inputs::read(&a, &setup)?;
    let choices = Choices::of(&a, &setup)?;
    let sens = match sensitivities(&setup.sensitivities)? {
        Some((sens, file)) => {
            inputs.files.push(file);
            Some(sens)
        }
        None => None,
    };
    let mut d = diagnose(&inputs.model, &inputs.rec, &s, &|stage| {
        eprintln!("{stage}")
    })?;
    d.inputs.splice(0..0, inputs.files.drain(..1));
    d.inputs.append(&mut inputs.files);
    let sens = match choices.sweep_at_calibrated {
        Some(mesh) => Some(sensitivities_at_calibrated(
            &a.out,
            &d,
            &inputs.rec,
            &inputs.model,
            mesh,
        )?),
        None => sens,
    };
    if let Some((reference, name)) = &inputs.reference {
        let me = d.mesh_error_with(&inputs.model, reference, name)?;
        eprintln!(
            "mesh error: {name} differs from --model by {:.2} σ rms at the calibrated material",
            me.rms_sigma
        );
    }
    let (sens, uncovered) = covering(&mut d, sens);
    let refit_asked = a.refit != "none" && a.refit != "auto";
    if let Some(sens) = &sens {
        d.name_and_plan(
            sens,
            &inputs.model,
            inputs.approximation.as_ref(),
            choices.plan.as_ref(),
            &|line| eprintln!("{line}"),
        )?;
        if a.rank_fe > 0 {
            rank_fe(&a, &mut d, sens, &inputs.model, choices.confirm)?;
        }
        model_and_show(&a, &mut d, sens, &inputs.model, choices.confirm)?;
    } else if refit_asked && !uncovered {
        anyhow::bail!(
            "--refit {}: needs the FE sensitivities (--sensitivities FILE, not none)",
            a.refit
        );
    }
    let written = write_outputs(&a.out, &d)?;
    print_stages(&d, uncovered);
    for p in written {
        println!("wrote {}", p.display());
    }
    if uncovered && refit_asked {
        anyhow::bail!(
            "--refit {}: not run, the FE sensitivities cover too few of the recorded cells (the \
             report names the others); {}",
            a.refit,
            surrogate::diagnose::sweep::COMPUTE_MISSING
        );
    }
    Ok(())
}

/// What the run reads before any work: the recordings (corrected by the mean of the
/// approximation error, when one is given), the model, the approximation error, the mesh
/// reference.
struct Inputs {
    rec: Recordings,
    model: Surrogate,
    approximation: Option<ApproximationError>,
    reference: Option<(Surrogate, String)>,
    /// The files read, for the report: the model first.
    files: Vec<InputFile>,
}

impl Inputs {
    fn read(a: &DiagnoseArgs, setup: &ResolvedSetup) -> Result<Self> {
        let (dir, default) = given_or_default(a.recordings.as_deref(), "training_data");
        let mut rec = recordings(&dir, default)?;
        let model_path = announced("model", &setup.model);
        let model = load_model(model_path)?;
        let mut files = vec![input_file("model", model_path, setup.model.default)?];
        let approximation = match &setup.approximation_error {
            ApproximationSource::File(f) => {
                let p = announced("approximation-error", f);
                let e = ApproximationError::read(p)
                    .with_context(|| format!("--approximation-error {}", p.display()))?;
                e.check_model(&model)
                    .with_context(|| format!("--approximation-error {}", p.display()))?;
                eprintln!(
                    "approximation error: {} samples of {} against {}; the recordings are \
                     corrected by its mean",
                    e.samples.len(),
                    e.model,
                    e.reference
                );
                rec = e.correct(&rec);
                files.push(input_file("approximation error", p, f.default)?);
                Some(e)
            }
            // `nulls` is refused by the setup's resolution
            ApproximationSource::None | ApproximationSource::Nulls => None,
        };
        // checked before any work: a bad value is named at once
        let reference = match &setup.mesh_reference {
            Some(f) => {
                let (m, name) = load_mesh_reference(&f.path)?;
                files.push(input_file("mesh reference", &f.path, f.default)?);
                Some((m, name))
            }
            None => None,
        };
        Ok(Inputs {
            rec,
            model,
            approximation,
            reference,
            files,
        })
    }
}

/// The flags of the later stages, checked before any work.
struct Choices {
    /// `--plan-measurements`.
    plan: Option<PlanSettings>,
    /// `--confirm-fe`.
    confirm: Option<MeshLevel>,
    /// `--sensitivities calibrated`: the sweep's mesh.
    sweep_at_calibrated: Option<MeshLevel>,
}

impl Choices {
    fn of(a: &DiagnoseArgs, setup: &ResolvedSetup) -> Result<Self> {
        refit_effects(&a.refit, None)?;
        let plan = plan_settings(a.plan_measurements)?;
        let confirm: Option<MeshLevel> = match a.confirm_fe.as_str() {
            "none" => None,
            other => Some(
                other
                    .parse()
                    .map_err(|e: String| anyhow::anyhow!("--confirm-fe {other}: {e} (or none)"))?,
            ),
        };
        // checked before any work: a sweep or a calibration is not run for nothing
        if a.rank_fe > 0 && confirm.is_none() {
            anyhow::bail!(
                "--rank-fe {}: needs the FE mesh to rank on, --confirm-fe coarse or standard",
                a.rank_fe
            );
        }
        if a.rank_fe == 1 {
            anyhow::bail!("--rank-fe 1: a ranking compares candidates; give 2 or more (0: off)");
        }
        let at_calibrated = setup.sensitivities == Sensitivities::Calibrated;
        let sweep_mesh: MeshLevel = a
            .sweep_mesh
            .parse()
            .map_err(|e: String| anyhow::anyhow!("--sweep-mesh {}: {e}", a.sweep_mesh))?;
        Ok(Choices {
            plan,
            confirm,
            sweep_at_calibrated: at_calibrated.then_some(sweep_mesh),
        })
    }
}

/// `--sensitivities calibrated`: the FE sweep at the material just calibrated, on `mesh`,
/// of the actuator `model`'s training cases were built as, cached in `<out>/fe_sensitivities`.
fn sensitivities_at_calibrated(
    out: &Path,
    d: &Diagnosis,
    rec: &Recordings,
    model: &Surrogate,
    mesh: MeshLevel,
) -> Result<SweepSensitivities> {
    let cache = out.join("fe_sensitivities");
    eprintln!(
        "FE sensitivities at the calibrated material ({}), {} mesh, ramps cached in {} (a \
         rerun resumes)",
        d.calibration.best.spec(),
        mesh.name(),
        cache.display()
    );
    Ok(sweep_at(
        &d.calibration.best,
        rec,
        MeshOptions::level(mesh),
        model.training.built_with.as_ref(),
        &cache,
        |k, n| eprintln!("FE ramp {k} of {n} done"),
    )?)
}

/// The sensitivities, unless they lack too many of the recorded cells (then the Locate stage
/// is reported, the cells without sensitivities named, and `true` says so).
fn covering(
    d: &mut Diagnosis,
    sens: Option<SweepSensitivities>,
) -> (Option<SweepSensitivities>, bool) {
    let uncovered = sens.as_ref().is_some_and(|sens| !d.cover(sens).enough());
    let sens = if uncovered { None } else { sens };
    if let Some(c) = d.sensitivity_coverage.as_ref().filter(|c| !c.complete()) {
        eprintln!("warning: {}", c.text());
    }
    (sens, uncovered)
}

/// Model and show with the effects `--refit` asks for (none: nothing), confirmed by the FE
/// model on the `confirm` mesh.
fn model_and_show(
    a: &DiagnoseArgs,
    d: &mut Diagnosis,
    sens: &SweepSensitivities,
    model: &Surrogate,
    confirm: Option<MeshLevel>,
) -> Result<()> {
    let Some(effects) = refit_effects(&a.refit, d.chosen())? else {
        return Ok(());
    };
    let rs = RefitSettings::new(effects);
    eprintln!(
        "model and show: material + {} through the surrogate, each design left out in turn",
        names(&rs.effects)
    );
    d.refit_with(sens, model, &rs)?;
    if let Some(level) = confirm {
        let fe = fe_settings(a, sens, model, level);
        let cache = &fe.cache;
        eprintln!(
            "FE confirmation on the {} mesh, ramps cached in {} (a rerun resumes)",
            level.name(),
            cache.display()
        );
        d.confirm_refit_with_fe(sens, model, &rs, &fe, &|k, n| {
            eprintln!("FE ramp {k} of {n} done")
        })?;
    }
    Ok(())
}

/// The FE settings of `--confirm-fe` and `--rank-fe` on `level`: the sweep's actuator,
/// cached in `--fe-cache` (default `<out>/fe_ramps`).
fn fe_settings(
    a: &DiagnoseArgs,
    sens: &SweepSensitivities,
    model: &Surrogate,
    level: MeshLevel,
) -> FeConfirmSettings {
    let cache = a.fe_cache.clone().unwrap_or_else(|| a.out.join("fe_ramps"));
    FeConfirmSettings::new(
        SweepSettings::new(sens.material.clone(), MeshOptions::level(level))
            .built_as(model.training.built_with.as_ref()),
        &cache,
    )
}

/// `--rank-fe K`: the Name stage's top K candidates ranked by FE-confirmed fits on the
/// `--confirm-fe` mesh.
fn rank_fe(
    a: &DiagnoseArgs,
    d: &mut Diagnosis,
    sens: &SweepSensitivities,
    model: &Surrogate,
    confirm: Option<MeshLevel>,
) -> Result<()> {
    let level = confirm.ok_or_else(|| {
        anyhow::anyhow!(
            "--rank-fe {}: needs the FE mesh to rank on, --confirm-fe coarse or standard",
            a.rank_fe
        )
    })?;
    let s = FeRankSettings {
        top: a.rank_fe,
        ..FeRankSettings::default()
    };
    // with fewer than 2 candidates there is nothing to rank: said, and the diagnosis is
    // written as without --rank-fe
    let picked = d.naming().map_or(0, |n| ranked_candidates(n, s.top).len());
    if picked < 2 {
        eprintln!(
            "FE ranking not run: {picked} candidate{} significant at a plausible size, at least \
             2 needed to rank",
            if picked == 1 { " is" } else { "s are" }
        );
        return Ok(());
    }
    let fe = fe_settings(a, sens, model, level);
    eprintln!(
        "FE ranking of the top {} candidates on the {} mesh, ramps cached in {} (a rerun \
         resumes)",
        s.top,
        level.name(),
        fe.cache.display()
    );
    let r = d.rank_with_fe(
        sens,
        model,
        &s,
        &fe,
        &|line| eprintln!("{line}"),
        &|k, n| eprintln!("FE ramp {k} of {n} done"),
    )?;
    eprintln!("{}", r.verdict);
    Ok(())
}

/// The findings, what the recordings lack, and the outcome of Name, the plan and Model and
/// show, on stdout.
fn print_stages(d: &Diagnosis, uncovered: bool) {
    println!("Findings:");
    for f in &d.locate.findings {
        println!("- {}", f.text);
    }
    if !d.locate.missing.is_empty() {
        println!("Not in the recordings:");
        for m in &d.locate.missing {
            println!("- {}", m.what);
        }
    }
    match d.naming() {
        None => match &d.name {
            Stage::NotRun { reason } if uncovered => {
                println!("Name (candidate physics): not run ({reason}).")
            }
            _ => println!("Name (candidate physics): not run (--sensitivities none)."),
        },
        Some(n) => print_naming(n, d.locate.consistent_with_scatter()),
    }
    if let Some(r) = &d.fe_ranking {
        println!("Name, ranked by FE: {}", r.verdict);
    }
    if let Some(p) = &d.measurement_plan {
        print_plan(p);
    }
    match d.refitted() {
        Some(r) => println!("Model and show: {}", r.verdict),
        None => {
            if let Stage::NotRun { reason } = &d.model_and_show {
                println!("Model and show: not run ({reason}).");
            }
        }
    }
}

/// The Name stage's verdict, its first candidates and the pairs it cannot tell apart; worded
/// as a hypothesis when Locate found the residuals consistent with the recorded scatter.
fn print_naming(n: &Naming, hypothesis: bool) {
    if hypothesis {
        println!(
            "Name (a hypothesis: Locate finds the residuals consistent with the recorded \
             scatter, so what is named may be the recordings' noise): {}",
            n.verdict
        );
    } else {
        println!("Name (candidate physics): {}", n.verdict);
    }
    print_candidates(n, 5);
    for p in &n.indistinguishable {
        println!(
            "- {} and {} cannot be told apart here ({}){}",
            p.a,
            p.b,
            p.why(),
            p.separated_by
                .as_ref()
                .map_or(String::new(), |s| format!("; {s}"))
        );
    }
}

/// Writes diagnosis.json, summary.md and the figures (each atomically).
pub fn write_outputs(dir: &Path, d: &Diagnosis) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut written = Vec::new();
    let p = dir.join("diagnosis.json");
    write_file(&p, d.to_json()?.as_bytes())?;
    written.push(p);
    let p = dir.join("summary.md");
    write_file(&p, summary_markdown(d).as_bytes())?;
    written.push(p);
    written.extend(write_plots(&d.locate, dir)?);
    Ok(written)
}

/// The settings of `--plan-measurements K` (none for 0).
fn plan_settings(k: usize) -> Result<Option<PlanSettings>> {
    if k == 0 {
        return Ok(None);
    }
    let s = PlanSettings::new(k);
    s.validate()
        .map_err(|e| anyhow::anyhow!("--plan-measurements {k}: {e} (or 0: no plan)"))?;
    Ok(Some(s))
}

/// The measurement plan, a line per item.
fn print_plan(p: &MeasurementPlan) {
    if p.items.is_empty() {
        println!("What to measure next: no plan ({}).", p.note);
        return;
    }
    println!(
        "What to measure next (to tell {} from {}; now {:.2} σ apart):",
        p.leader,
        p.rivals.join(", "),
        p.separation_sigma
    );
    for it in &p.items {
        println!(
            "- {} (σ = {:.3}): {:.2} σ apart, expected log Bayes factor {:.2} (+{:.2}); least \
             separated: {} at {:.2} σ",
            it.text(),
            it.measurement.sigma,
            it.separation_sigma,
            it.log_bayes_factor,
            it.gain,
            it.weakest,
            it.weakest_separation_sigma
        );
    }
}

/// The `top` candidates of the Name stage, a line each.
pub fn print_candidates(n: &Naming, top: usize) {
    for c in n.candidates.iter().take(top) {
        println!(
            "- {:<24} {} ± {:.4} {:<7} explains {:>5.1} % (p = {:.2e}{})",
            c.effect,
            c.size_text(4),
            c.std_error,
            c.unit,
            100.0 * c.explained,
            c.p_value,
            if c.significant { ", significant" } else { "" }
        );
    }
}

/// The effects `--refit` asks for: the named one (`auto`), none, or a list.
fn refit_effects(arg: &str, chosen: Option<&str>) -> Result<Option<Vec<Effect>>> {
    match arg.trim() {
        "none" => Ok(None),
        "auto" => Ok(chosen.map(Effect::from_name).transpose()?.map(|e| vec![e])),
        list => {
            let effects = list
                .split(',')
                .map(|n| Effect::from_name(n.trim()))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| anyhow::anyhow!("--refit {list}: {e} (or auto, none)"))?;
            Ok(Some(effects))
        }
    }
}

fn names(effects: &[Effect]) -> String {
    effects
        .iter()
        .map(|e| e.name())
        .collect::<Vec<_>>()
        .join(" + ")
}
