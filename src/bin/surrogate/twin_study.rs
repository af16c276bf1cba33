//! `surrogate twin-study`: the diagnoser's blind study ([`surrogate::diagnose::study`]).
use anyhow::{Context, Result};
use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::{ParamSpace, Recordings};
use surrogate::diagnose::study::{
    make_twins, null_approximation_error, ramps_to_run, run_diagnoses, study_markdown, Diagnoser,
    StudyDirs, StudyPlan,
};

use crate::args::TwinStudyArgs;
use crate::files::{given_or_announced, load_model, mesh_reference, write_file};

/// The diagnosing surrogate of the study without `--model`, in the repository.
const DEFAULT_MODEL: &str = "models/actuator_coarse.json";
/// The FE sensitivities of the study without `--sensitivities`, in the repository.
const DEFAULT_SENSITIVITIES: &str =
    "fe_reference/sensitivities/ogden002_coarse/baseline_sensitivities.json";
/// The study's directory without `--out`, in the repository (its committed results).
const DEFAULT_OUT: &str = "fe_reference/diagnosis/blind";

/// Runs the subcommand.
pub fn run(a: TwinStudyArgs) -> Result<()> {
    let (twins, diagnoses) = match a.stage.as_str() {
        "twins" => (true, false),
        "diagnose" => (false, true),
        "all" => (true, true),
        other => anyhow::bail!("--stage {other}: expected twins, diagnose or all"),
    };
    let (model_path, _) = given_or_announced("model", a.model.as_deref(), DEFAULT_MODEL);
    let model = load_model(&model_path)?;
    let (noise_dir, _) = given_or_announced("noise-from", a.noise_from.as_deref(), "training_data");
    let noise_from = Recordings::read_dir(&noise_dir)
        .with_context(|| format!("reading the noise source {}", noise_dir.display()))?;
    let (out, _) = given_or_announced("out", a.out.as_deref(), DEFAULT_OUT);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let plan_path = a.plan.clone().unwrap_or_else(|| out.join("plan.json"));
    let plan = if plan_path.exists() {
        StudyPlan::read(&plan_path)?
    } else {
        let p = StudyPlan::standard(&ParamSpace::training_domain(&model)?, a.draw_seed)?;
        p.write(&plan_path)?;
        eprintln!("wrote the standard plan to {}", plan_path.display());
        p
    };
    let plan = plan
        .only(&a.groups)
        .with_context(|| format!("--groups of {}", plan_path.display()))?;
    let markers = match a.markers.as_deref() {
        None => plan.markers,
        Some("yes") => true,
        Some("no") => false,
        Some(other) => anyhow::bail!("--markers {other}: expected yes or no"),
    };
    let dirs = StudyDirs::under(&out);
    eprintln!(
        "{} groups × {} seeds = {} twins; FE cached in {} (a rerun resumes)",
        plan.groups.len(),
        plan.seeds.len(),
        plan.twins().len(),
        dirs.cache.display()
    );
    if twins {
        let to_run = ramps_to_run(&plan, &noise_from, &dirs)?;
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
        make_twins(&plan, &noise_from, &dirs, &|line| eprintln!("{line}"))?;
    }
    if diagnoses {
        let (sens_path, _) = given_or_announced(
            "sensitivities",
            a.sensitivities.as_deref(),
            DEFAULT_SENSITIVITIES,
        );
        let sens = SweepSensitivities::read(&sens_path)
            .with_context(|| format!("--sensitivities {}", sens_path.display()))?;
        let reference = mesh_reference(&a.mesh_reference, &model_path)?;
        let approximation = match a.approximation_error.as_str() {
            "none" => None,
            "nulls" => {
                let e = null_approximation_error(
                    &plan,
                    &noise_from,
                    &dirs,
                    &model,
                    &model_path.display().to_string(),
                )?;
                let p = out.join("approximation_error.json");
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
                Some(e)
            }
            other => anyhow::bail!("--approximation-error {other}: expected nulls or none"),
        };
        let by = Diagnoser {
            model: &model,
            sens: &sens,
            mesh_reference: reference.as_ref().map(|(r, n)| (r, n.as_str())),
            markers,
            approximation: approximation.as_ref(),
        };
        let results = run_diagnoses(&plan, &noise_from, &dirs, &by, &|line| eprintln!("{line}"))?;
        let stem = format!(
            "{}{}",
            match (markers == plan.markers, markers) {
                (true, _) => "results",
                (false, true) => "results_markers",
                (false, false) => "results_no_markers",
            },
            if reference.is_some() { "_mesh" } else { "" },
        );
        let stem = if approximation.is_some() {
            stem
        } else {
            format!("{stem}_no_approx")
        };
        let p = out.join(format!("{stem}.json"));
        write_file(&p, serde_json::to_string_pretty(&results)?.as_bytes())?;
        let md = study_markdown(&plan, &results);
        let q = out.join(format!("{stem}.md"));
        write_file(&q, md.as_bytes())?;
        print!("{md}");
        eprintln!("wrote {} and {}", p.display(), q.display());
    }
    Ok(())
}
