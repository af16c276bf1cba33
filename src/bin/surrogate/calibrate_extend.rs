//! `surrogate calibrate --extend-box K`: the box extension's flags checked, the rounds run by
//! the library, its report written beside the FE in `<out>/extend/`.
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::calibrate::extend::{extend_box, BoxExtension, ExtendEvent, ExtendSettings};
use surrogate::calibrate::refine::TrainingSet;
use surrogate::calibrate::summary::summary_markdown_extended;
use surrogate::calibrate::{CalibrateError, CalibrationSettings};
use surrogate::rom::Surrogate;

use crate::calibrate::{
    inputs, run_fe, show_fe_progress, training_set, write_outputs, CalibrateArgs, Inputs,
};
use crate::files::write_file;

/// The extension's settings from the flags, checked against the model before any FE; a bad
/// value is named by its flag.
pub fn settings(
    a: &CalibrateArgs,
    model: &Surrogate,
    training: &TrainingSet,
    calibration: CalibrationSettings,
) -> Result<ExtendSettings> {
    anyhow::ensure!(
        a.refine == 0,
        "--extend-box {} with --refine {}: one at a time (the refinement of an extended model \
         needs its training set, which the extension does not write as one file)",
        a.extend_box,
        a.refine
    );
    let defaults = ExtendSettings::default();
    let s = ExtendSettings {
        max_rounds: a.extend_box,
        step: a.extend_step,
        cases_per_round: a.extend_cases,
        seed: a.extend_seed,
        train: defaults.train.clone().like(&model.training),
        calibration,
        threads: a.threads,
        ..defaults
    };
    let mut n: Vec<u32> = training
        .snapshots
        .rows
        .iter()
        .map(|r| r.inputs.n_bellows)
        .collect();
    n.sort_unstable();
    n.dedup();
    s.validate(n.len()).map_err(named)?;
    Ok(s)
}

/// A settings error named by its flag.
fn named(e: CalibrateError) -> anyhow::Error {
    let CalibrateError::Input {
        field,
        value,
        expected,
    } = &e
    else {
        return e.into();
    };
    let flag = match field.as_str() {
        "max_rounds" => "--extend-box",
        "step" => "--extend-step",
        "cases_per_round" => "--extend-cases",
        "threads" => "--threads",
        _ => return e.into(),
    };
    anyhow::anyhow!("{flag} {value}: expected {expected}")
}

/// `surrogate calibrate --extend-box K`: runs the extension, then the usual outputs for the
/// last calibration (with its FE check when `--verify-fe` asks for one) and the extension's
/// `extension.json` and `extension.md` in `<out>/extend/`.
pub fn run(args: CalibrateArgs) -> Result<()> {
    let a = &args;
    let Inputs {
        model,
        model_file,
        rec,
        settings: calibration,
        mesh: verify,
    } = inputs(a)?;
    let (model, rec) = (&model, &rec);
    let training = training_set(a, model)?;
    let settings = settings(a, model, &training, calibration)?;
    let dir = a.out.join("extend");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    eprintln!(
        "box extension: up to {} rounds of {} cases where the optimum presses the box (FE and \
         models in {}; a rerun resumes)",
        settings.max_rounds,
        settings.cases_per_round,
        dir.display()
    );
    let bar = ProgressBar::hidden();
    bar.set_style(ProgressStyle::with_template(
        "{spinner} round {msg} FE cases [{bar:30}] {pos}/{len}, {elapsed_precise}, eta {eta}",
    )?);
    let runner = crate::calibrate::runner(a);
    let mut e = extend_box(
        model,
        &training,
        rec,
        &settings,
        runner.as_ref(),
        &dir,
        &|ev| show_event(&bar, ev),
    )?;
    let mut cal = e
        .last
        .take()
        .context("the box extension returned no calibration")?;
    cal.inputs.insert(0, model_file);
    let last = match e.rounds.last() {
        Some(r) => surrogate::rom::Surrogate::load(&r.model)?,
        None => model.clone(),
    };
    let fe = match verify {
        Some(level) => {
            let cache = a
                .fe_cache
                .clone()
                .unwrap_or_else(|| a.out.join(format!("fe_{}_ramps", level.name())));
            Some(run_fe(&last, rec, &cal.best.rounded(4), level, &cache)?)
        }
        None => None,
    };
    let mut written = write_outputs(&a.out, &cal, fe.as_ref())?;
    let summary = summary_markdown_extended(&cal, fe.as_ref(), Some(&e));
    let p = a.out.join("summary.md");
    write_file(&p, summary.as_bytes())?;
    written.extend(write_extension(&dir, &e)?);
    print!("{summary}");
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Writes `extension.json` and `extension.md` (the summary's section) into `dir`.
fn write_extension(dir: &Path, e: &BoxExtension) -> Result<Vec<PathBuf>> {
    let p = dir.join("extension.json");
    write_file(&p, serde_json::to_string_pretty(e)?.as_bytes())?;
    let q = dir.join("extension.md");
    write_file(&q, e.summary_markdown().as_bytes())?;
    Ok(vec![p, q])
}

/// An extension event on stderr: stages and rounds as lines, FE cases on the progress bar.
fn show_event(bar: &ProgressBar, ev: ExtendEvent) {
    match ev {
        ExtendEvent::Stage(s) => bar.suspend(|| eprintln!("{s}")),
        ExtendEvent::Fe { round, progress } => {
            show_fe_progress(bar, &round, &progress);
        }
        ExtendEvent::Round(r) => bar.suspend(|| {
            eprintln!(
                "round {}: {} cases ({} failed); refit χ² {:.1}, on {}",
                r.round,
                r.cases,
                r.failed.len(),
                r.refit.chi2,
                if r.refit.active_bounds.is_empty() {
                    "no bound".to_string()
                } else {
                    r.refit.active_bounds.join("; ")
                }
            )
        }),
    }
}
