//! `surrogate twin-study`: the diagnoser's blind study ([`surrogate::diagnose::study`]).
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::{ParamSpace, Recordings};
use surrogate::diagnose::approx_error::ApproximationError;
use surrogate::diagnose::setup::{
    ApproximationSource, DiagnosisSetup, ResolvedFile, ResolvedSetup, Sensitivities,
};
use surrogate::diagnose::study::{
    close_loop, loop_markdown, make_twins, null_approximation_error, ramps_to_run, run_diagnoses,
    study_markdown, Diagnoser, LoopSettings, StudyDirs, StudyPlan,
};
use surrogate::rom::Surrogate;

use crate::args::TwinStudyArgs;
use crate::files::{
    announced, given_or_announced, load_mesh_reference, load_model, repository_root, write_file,
};

/// The study's directory without `--out`, in the repository (its committed results).
const DEFAULT_OUT: &str = "fe_reference/diagnosis/blind";

/// Runs the subcommand: the plan read (or the standard one written), then the stages asked
/// for: the twins made, the twins diagnosed and scored.
pub fn run(a: TwinStudyArgs) -> Result<()> {
    let (twins, diagnoses, closed_loop) = stages(&a.stage)?;
    if closed_loop {
        // refused before anything is read or written
        surrogate::diagnose::measure_design::PlanSettings::new(a.loop_k)
            .validate()
            .context("--loop-k")?;
    }
    let setup = a
        .setup
        .setup(DiagnosisSetup::blind_study())
        .resolve(repository_root())?;
    let model_path = announced("model", &setup.model).to_path_buf();
    let model = load_model(&model_path)?;
    let (noise_dir, _) = given_or_announced("noise-from", a.noise_from.as_deref(), "training_data");
    let noise_from = Recordings::read_dir(&noise_dir)
        .with_context(|| format!("reading the noise source {}", noise_dir.display()))?;
    let (out, _) = given_or_announced("out", a.out.as_deref(), DEFAULT_OUT);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let plan = study_plan(&a, &out, &model)?;
    let markers = match a.markers.as_deref() {
        None => plan.markers,
        Some("yes") => true,
        Some("no") => false,
        Some(other) => anyhow::bail!("--markers {other}: expected yes or no"),
    };
    let study = Study {
        dirs: StudyDirs::under(&out),
        plan,
        noise_from,
        out,
        model,
        model_path,
    };
    eprintln!(
        "{} groups × {} seeds = {} twins; FE cached in {} (a rerun resumes)",
        study.plan.groups.len(),
        study.plan.seeds.len(),
        study.plan.twins().len(),
        study.dirs.cache.display()
    );
    if twins {
        study.make_twins()?;
    }
    if diagnoses || closed_loop {
        study.diagnose(&a, &setup, markers, closed_loop)?;
    }
    Ok(())
}

/// The stages of `--stage`: (make the twins, diagnose them, close the loop).
fn stages(stage: &str) -> Result<(bool, bool, bool)> {
    Ok(match stage {
        "twins" => (true, false, false),
        "diagnose" => (false, true, false),
        "all" => (true, true, false),
        "loop" => (false, false, true),
        other => anyhow::bail!("--stage {other}: expected twins, diagnose, all or loop"),
    })
}

/// The study's plan (`--plan`, default `<out>/plan.json`; the standard plan written there
/// when there is none), restricted to `--groups`.
fn study_plan(a: &TwinStudyArgs, out: &Path, model: &Surrogate) -> Result<StudyPlan> {
    let plan_path = a.plan.clone().unwrap_or_else(|| out.join("plan.json"));
    let plan = if plan_path.exists() {
        StudyPlan::read(&plan_path)?
    } else {
        let p = StudyPlan::standard(&ParamSpace::training_domain(model)?, a.draw_seed)?;
        p.write(&plan_path)?;
        eprintln!("wrote the standard plan to {}", plan_path.display());
        p
    };
    plan.only(&a.groups)
        .with_context(|| format!("--groups of {}", plan_path.display()))
}

/// The study under way: its plan, the recordings whose scatter the noise copies, its
/// directories and the diagnosing surrogate.
struct Study {
    plan: StudyPlan,
    noise_from: Recordings,
    dirs: StudyDirs,
    out: PathBuf,
    model: Surrogate,
    model_path: PathBuf,
}

impl Study {
    /// The twins, their FE ramps run where the cache lacks them.
    fn make_twins(&self) -> Result<()> {
        let to_run = ramps_to_run(&self.plan, &self.noise_from, &self.dirs)?;
        eprintln!(
            "FE ramps to run: {}",
            if to_run.is_empty() {
                "none (every ramp is in the cache: only the noise is drawn)".to_string()
            } else {
                to_run
                    .iter()
                    .map(|(id, n)| format!("{id} {n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        );
        make_twins(&self.plan, &self.noise_from, &self.dirs, &|line| {
            eprintln!("{line}")
        })?;
        Ok(())
    }

    /// Every twin diagnosed without its key (with or without `markers`) and scored; the
    /// results written as JSON and Markdown, the Markdown printed.
    fn diagnose(
        &self,
        a: &TwinStudyArgs,
        setup: &ResolvedSetup,
        markers: bool,
        closed_loop: bool,
    ) -> Result<()> {
        // `none` and `calibrated` are refused by the setup's resolution
        let Sensitivities::File(f) = &setup.sensitivities else {
            anyhow::bail!("--sensitivities: the blind study needs a file");
        };
        let sens_path = announced("sensitivities", f);
        let sens = SweepSensitivities::read(sens_path)
            .with_context(|| format!("--sensitivities {}", sens_path.display()))?;
        let reference = match &setup.mesh_reference {
            Some(f) => Some(load_mesh_reference(&f.path)?),
            None => None,
        };
        let approximation = self.approximation(&setup.approximation_error)?;
        let by = Diagnoser {
            model: &self.model,
            sens: &sens,
            mesh_reference: reference.as_ref().map(|(r, n)| (r, n.as_str())),
            markers,
            approximation: approximation.as_ref(),
        };
        let stem = results_stem(
            markers,
            self.plan.markers,
            reference.is_some(),
            &setup.approximation_error,
        );
        if closed_loop {
            let settings = LoopSettings {
                k: a.loop_k,
                sequential: a.loop_sequential,
            };
            return self.close_loop(&by, &settings, &stem);
        }
        let results = run_diagnoses(&self.plan, &self.noise_from, &self.dirs, &by, &|line| {
            eprintln!("{line}")
        })?;
        let p = self.out.join(format!("{stem}.json"));
        write_file(&p, serde_json::to_string_pretty(&results)?.as_bytes())?;
        let md = study_markdown(&self.plan, &results);
        let q = self.out.join(format!("{stem}.md"));
        write_file(&q, md.as_bytes())?;
        print!("{md}");
        eprintln!("wrote {} and {}", p.display(), q.display());
        Ok(())
    }

    /// The closed loop (`--stage loop`): results written to `<stem with _loop>.json` and
    /// `.md`, the Markdown printed.
    fn close_loop(&self, by: &Diagnoser<'_>, settings: &LoopSettings, stem: &str) -> Result<()> {
        let results = close_loop(
            &self.plan,
            &self.noise_from,
            &self.dirs,
            by,
            settings,
            &|line| eprintln!("{line}"),
        )?;
        let to = if settings.sequential {
            "results_loop_sequential"
        } else {
            "results_loop"
        };
        let stem = stem.replacen("results", to, 1);
        let p = self.out.join(format!("{stem}.json"));
        write_file(&p, serde_json::to_string_pretty(&results)?.as_bytes())?;
        let md = loop_markdown(&results);
        let q = self.out.join(format!("{stem}.md"));
        write_file(&q, md.as_bytes())?;
        print!("{md}");
        eprintln!("wrote {} and {}", p.display(), q.display());
        Ok(())
    }

    /// The model's approximation error of `--approximation-error`: sampled on the null twins
    /// (`nulls`, written to `<out>/approximation_error.json`), read from a file, or none.
    fn approximation(
        &self,
        source: &ApproximationSource<ResolvedFile>,
    ) -> Result<Option<ApproximationError>> {
        match source {
            ApproximationSource::None => Ok(None),
            ApproximationSource::File(f) => {
                announced("approximation-error", f);
                let e = ApproximationError::read(&f.path)
                    .with_context(|| format!("--approximation-error {}", f.path.display()))?;
                e.check_model(&self.model)
                    .with_context(|| format!("--approximation-error {}", f.path.display()))?;
                eprintln!(
                    "approximation error: {} samples of {} against {}, read from {}",
                    e.samples.len(),
                    e.model,
                    e.reference,
                    f.path.display()
                );
                Ok(Some(e))
            }
            ApproximationSource::Nulls => {
                let e = null_approximation_error(
                    &self.plan,
                    &self.noise_from,
                    &self.dirs,
                    &self.model,
                    &repository_name(&self.model_path),
                )?;
                let p = self.out.join("approximation_error.json");
                e.write(&p)?;
                eprintln!(
                    "approximation error: {} samples ({}), written to {}",
                    e.samples.len(),
                    e.samples
                        .iter()
                        .map(|s| s.source.as_str())
                        .collect::<Vec<_>>()
                        .join(", "),
                    p.display()
                );
                Ok(Some(e))
            }
        }
    }
}

/// The results' file stem: `results`, with `_markers` or `_no_markers` when `markers`
/// differs from the plan's, `_mesh` with a mesh reference, `_no_approx` without an
/// approximation error, `_nulls` with the one sampled from the null twins.
fn results_stem(
    markers: bool,
    plan_markers: bool,
    mesh: bool,
    approximation: &ApproximationSource<ResolvedFile>,
) -> String {
    let stem = format!(
        "{}{}",
        match (markers == plan_markers, markers) {
            (true, _) => "results",
            (false, true) => "results_markers",
            (false, false) => "results_no_markers",
        },
        if mesh { "_mesh" } else { "" },
    );
    match approximation {
        ApproximationSource::File(_) => stem,
        ApproximationSource::Nulls => format!("{stem}_nulls"),
        ApproximationSource::None => format!("{stem}_no_approx"),
    }
}

/// `path` as the approximation error names its model: relative to the repository when it lies
/// in it (so a rerun with the defaults writes the committed file again, byte for byte), else as
/// given.
fn repository_name(path: &Path) -> String {
    path.strip_prefix(repository_root())
        .unwrap_or(path)
        .display()
        .to_string()
}
