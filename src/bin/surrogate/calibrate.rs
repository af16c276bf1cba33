//! `surrogate calibrate`: one Ogden set for the recordings, through the surrogate; its
//! identifiability, the study's per-configuration procedure, and the FE verification.
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::calibrate::experiments::{SHIPPED_BENDING, SHIPPED_FORCE};
use surrogate::calibrate::fit::describe_exclusions;
use surrogate::calibrate::identify::IdentifySettings;
use surrogate::calibrate::inputs::{self, InputFile};
use surrogate::calibrate::objective::Exclusion;
use surrogate::calibrate::optimise::MultistartSettings;
use surrogate::calibrate::refine::{refine, RefineEvent, RefineSettings, TrainingSet};
use surrogate::calibrate::verdict;
use surrogate::calibrate::verify::{verify_fe, FeVerification};
use surrogate::calibrate::{
    calibrate, Calibration, CalibrationSettings, OgdenSet, Recordings, Selection, Weights,
};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::rom::Surrogate;

use crate::calibrate_plots::write_plots;
use crate::files::{
    given_or_default, input_file, load_model, repository_file, write_file, DEFAULT_MODEL,
};

/// `surrogate calibrate`.
#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Surrogate model file [default: models/actuator.json of the repository the program was
    /// built from, from any working directory].
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Bending recordings (columns of training_data/bending_experiments.csv, or their other
    /// units: src/schema.rs). Without --bending, --force and --markers the shipped
    /// experiments are read (training_data/ of the repository, both files, listed as
    /// defaults in the report); with any of them, only the files named are read.
    #[arg(long)]
    pub bending: Option<PathBuf>,
    /// Blocked-force recordings (columns of training_data/blocked_force_experiments.csv); not
    /// given with --bending: the force is not compared.
    #[arg(long)]
    pub force: Option<PathBuf>,
    /// Marker recordings (n_bellows, wall_thickness_mm, pressure_bar, marker, uz_mm, uy_mm,
    /// std_mm); needs --bending.
    #[arg(long)]
    pub markers: Option<PathBuf>,
    /// Objective: tip, angle, force, markers, all, or weights such as tip=1,force=0.5.
    #[arg(long, default_value = "tip")]
    pub objective: String,
    /// Leave out a configuration: N,T,P (both recordings), bending:N,T,P or force:N,T,P
    /// (repeatable; listed in the report).
    #[arg(long, allow_hyphen_values = true)]
    pub exclude: Vec<String>,
    /// Also leave out every row the data checks flag (listed in the report with the reason).
    #[arg(long)]
    pub exclude_flagged: bool,
    /// Latin-hypercube starts of the multistart fit (the literature set is one more).
    #[arg(long, default_value_t = 24)]
    pub starts: usize,
    /// Seed of the starts.
    #[arg(long, default_value_t = 2024)]
    pub seed: u64,
    /// Profile-likelihood grid points per parameter.
    #[arg(long, default_value_t = 24)]
    pub profile_points: usize,
    /// Literature set compared against (and used as a start).
    #[arg(long, default_value = "ogden_002")]
    pub literature: String,
    /// Also run the study's procedure: a fit per configuration inside ±`box` of the literature set.
    #[arg(long)]
    pub per_configuration: bool,
    /// Relative half-width of the per-configuration box.
    #[arg(long = "box", default_value_t = 0.1)]
    pub box_fraction: f64,
    /// Verify the optimum with the full FE model on this mesh (coarse, standard, fine; `none` to skip).
    #[arg(long, default_value = "none")]
    pub verify_fe: String,
    /// Cache of the FE ramps (default: `<out>/fe_<mesh>_ramps`); a rerun resumes from it.
    #[arg(long)]
    pub fe_cache: Option<PathBuf>,
    /// Adaptive refinement: up to this many rounds of FE at the calibrated set (every recorded
    /// design, on the training set's mesh), each added to the training set where surrogate and FE
    /// disagree, the surrogate retrained and the material refitted (0: off). Needs a model
    /// trained on one snapshot set (`--training`). FE cases are cached in `<out>/refine/`.
    #[arg(long, default_value_t = 0)]
    pub refine: usize,
    /// The refined model's training snapshots (default: the source the model records, relative
    /// to the working directory); its plan is read from `<stem>.plan.json` beside it.
    #[arg(long)]
    pub training: Option<PathBuf>,
    /// FE cases run in parallel by the refinement (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The refinement stops when the refit moves no recorded number's prediction by more than
    /// this many of its standard deviations from the verified set's (0: off; then only
    /// agreement, an unchanged set or --refine rounds stop it).
    #[arg(long, default_value_t = RefineSettings::default().data_tolerance)]
    pub refine_data_tolerance: f64,
    /// Output directory (report.json, configurations.csv, summary.md, SVG plots).
    #[arg(long, default_value = "calibration")]
    pub out: PathBuf,
}

/// Reads the recordings named on the command line, and only those; none named: the shipped
/// experiments of the repository, both files, as defaults.
pub fn recordings(a: &CalibrateArgs) -> Result<Recordings> {
    match (&a.bending, &a.force, &a.markers) {
        (None, None, None) => {
            let (b, f) = (
                repository_file(SHIPPED_BENDING),
                repository_file(SHIPPED_FORCE),
            );
            eprintln!(
                "no recordings named: reading the shipped experiments {} and {} (the defaults)",
                b.display(),
                f.display()
            );
            let rec = Recordings::read_files(&b, Some(&f), None).with_context(|| {
                "the default recordings (give --bending FILE and --force FILE)".to_string()
            })?;
            Ok(rec.as_defaults())
        }
        (None, f, m) => {
            let given = [
                f.as_ref().map(|_| "--force"),
                m.as_ref().map(|_| "--markers"),
            ];
            anyhow::bail!(
                "{} without --bending: the calibration needs bending recordings and reads only \
                 the files named; give --bending FILE (the shipped ones are {})",
                given
                    .into_iter()
                    .flatten()
                    .collect::<Vec<_>>()
                    .join(" and "),
                repository_file(SHIPPED_BENDING).display()
            )
        }
        (Some(b), f, m) => {
            if f.is_none() {
                eprintln!(
                    "no --force: only the files named are read; the blocked force is not compared"
                );
            }
            Ok(Recordings::read_files(b, f.as_deref(), m.as_deref())?)
        }
    }
}

/// The validated settings of the run.
pub fn settings(a: &CalibrateArgs) -> Result<CalibrationSettings> {
    let exclude = a
        .exclude
        .iter()
        .map(|e| Exclusion::parse(e))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(CalibrationSettings {
        weights: Weights::parse(&a.objective)?,
        selection: Selection {
            exclude,
            ..Selection::default()
        },
        exclude_flagged: a.exclude_flagged,
        multistart: MultistartSettings {
            starts: a.starts,
            seed: a.seed,
            ..MultistartSettings::default()
        },
        identify: IdentifySettings {
            profile_points: a.profile_points,
            ..IdentifySettings::default()
        },
        literature: OgdenSet::literature(&a.literature)?,
        per_configuration: a.per_configuration.then_some(a.box_fraction),
    })
}

/// Runs the subcommand.
pub fn run(a: CalibrateArgs) -> Result<()> {
    let (model_path, default) = given_or_default(a.model.as_deref(), DEFAULT_MODEL);
    let model = load_model(&model_path)?;
    let model_file = input_file("model", &model_path, default)?;
    let rec = recordings(&a)?;
    let s = settings(&a)?;
    let mesh = match a.verify_fe.as_str() {
        "none" => None,
        m => Some(m.parse::<MeshLevel>().map_err(anyhow::Error::msg)?),
    };
    if a.refine > 0 {
        anyhow::ensure!(
            mesh.is_none(),
            "--verify-fe {} with --refine {}: the refinement verifies on its training set's mesh; leave --verify-fe out",
            a.verify_fe,
            a.refine
        );
        return run_refine(&a, &model, &model_file, &rec, s);
    }
    let mut cal = calibrate(&model, &rec, &s, &|stage| eprintln!("{stage}"))?;
    cal.inputs.insert(0, model_file);
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let fe = match mesh {
        Some(level) => {
            let cache = a
                .fe_cache
                .clone()
                .unwrap_or_else(|| a.out.join(format!("fe_{}_ramps", level.name())));
            // the set as reported (4 significant digits)
            Some(run_fe(&model, &rec, &cal.best.rounded(4), level, &cache)?)
        }
        None => None,
    };
    let written = write_outputs(&a.out, &cal, fe.as_ref())?;
    print!("{}", summary_text(&cal, fe.as_ref()));
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// `--refine`: the rounds, then the usual outputs for the last calibration with its FE check,
/// and `refinement.md`, `refinement.json`, `refinement.svg`.
fn run_refine(
    a: &CalibrateArgs,
    model: &Surrogate,
    model_file: &InputFile,
    rec: &Recordings,
    calibration: CalibrationSettings,
) -> Result<()> {
    anyhow::ensure!(
        a.threads != Some(0),
        "--threads 0: expected at least 1 FE case at a time"
    );
    let training = match &a.training {
        Some(csv) => TrainingSet::read(csv, &surrogate::snapshots::merge::sidecar_path(csv))?,
        // the model's training source, relative to the repository for the default model
        None => TrainingSet::of_model(
            model,
            &if a.model.is_none() {
                repository_file("")
            } else {
                PathBuf::from(".")
            },
        )?,
    };
    let settings = RefineSettings {
        max_rounds: a.refine,
        calibration,
        threads: a.threads,
        data_tolerance: a.refine_data_tolerance,
        ..RefineSettings::default()
    };
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let dir = a.out.join("refine");
    let meshes = match &training.high {
        Some(h) => format!(
            "the {} mesh of {} and the {} mesh of {}",
            training.plan.settings.mesh.level.name(),
            training.snapshots.source,
            h.plan.settings.mesh.level.name(),
            h.snapshots.source
        ),
        None => format!(
            "the {} mesh of {}",
            training.plan.settings.mesh.level.name(),
            training.snapshots.source
        ),
    };
    eprintln!(
        "adaptive refinement: up to {} rounds on {meshes} (FE cached in {}; a rerun resumes)",
        a.refine,
        dir.display()
    );
    let bar = ProgressBar::hidden();
    bar.set_style(ProgressStyle::with_template(
        "{spinner} round {msg} FE cases [{bar:30}] {pos}/{len}, {elapsed_precise}, eta {eta}",
    )?);
    let runner = surrogate::snapshots::fe_runner::fe_runner;
    let mut r = refine(model, &training, rec, &settings, &runner, &dir, &|ev| {
        match ev {
            RefineEvent::Stage(s) => bar.suspend(|| eprintln!("{s}")),
            RefineEvent::Fe { round, progress } => {
                if progress.done == 0 {
                    bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
                    bar.reset();
                }
                bar.set_message(round.to_string());
                bar.set_length(progress.total as u64);
                bar.set_position(progress.done as u64);
                if progress.done == progress.total {
                    bar.finish_and_clear();
                }
            }
            RefineEvent::Round(r) => bar.suspend(|| {
                eprintln!(
                    "round {}: FE mean BE {:.2} mm; surrogate − FE max |Δ| {:.2}, {:.2} mm, {:.3} N; {} configurations beyond 2σ",
                    r.round,
                    r.verification.summary.mean_be_mm,
                    r.verification.max_abs_sur_fe[0],
                    r.verification.max_abs_sur_fe[1],
                    r.verification.max_abs_sur_fe[2],
                    r.verification.disagreements
                )
            }),
        }
    })?;
    r.last.inputs.insert(0, model_file.clone());
    let mut written = write_outputs(&a.out, &r.last, Some(r.final_verification()))?;
    let md = r.summary_markdown();
    let p = a.out.join("refinement.md");
    write_file(&p, md.as_bytes())?;
    written.push(p);
    let p = a.out.join("refinement.json");
    write_file(&p, serde_json::to_string_pretty(&r)?.as_bytes())?;
    written.push(p);
    let p = a.out.join("refinement.svg");
    crate::calibrate_plots::refinement(&r, &p)?;
    written.push(p);
    print!("{}", summary_text(&r.last, Some(r.final_verification())));
    print!("\n{md}");
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

fn run_fe(
    model: &Surrogate,
    rec: &Recordings,
    best: &OgdenSet,
    level: MeshLevel,
    cache: &Path,
) -> Result<FeVerification> {
    eprintln!(
        "FE verification on the {} mesh (ramps cached in {}; a rerun resumes)",
        level.name(),
        cache.display()
    );
    let bar = ProgressBar::new(0);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} FE ramps [{bar:30}] {pos}/{len}, {elapsed_precise}, eta {eta}",
    )?);
    let v = verify_fe(
        model,
        rec,
        best,
        MeshOptions::level(level),
        cache,
        |k, n| {
            bar.set_length(n as u64);
            bar.set_position(k as u64);
        },
    )?;
    bar.finish_and_clear();
    Ok(v)
}

/// Writes report.json, configurations.csv, summary.md and the plots (each atomically).
pub fn write_outputs(
    dir: &Path,
    cal: &Calibration,
    fe: Option<&FeVerification>,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let report = serde_json::json!({ "calibration": cal, "fe_verification": fe });
    let p = dir.join("report.json");
    write_file(&p, serde_json::to_string_pretty(&report)?.as_bytes())?;
    written.push(p);
    let p = dir.join("configurations.csv");
    write_file(&p, &configurations_csv(cal, fe)?)?;
    written.push(p);
    let p = dir.join("summary.md");
    write_file(&p, summary_text(cal, fe).as_bytes())?;
    written.push(p);
    written.extend(write_plots(cal, fe, dir)?);
    Ok(written)
}

/// Per configuration: measured, literature and calibrated (surrogate), FE at the optimum.
fn configurations_csv(cal: &Calibration, fe: Option<&FeVerification>) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "n_bellows",
        "wall_thickness_mm",
        "pressure_bar",
        "fitted",
        "uz_exp_mm",
        "uy_exp_mm",
        "angle_exp_deg",
        "force_exp_n",
        "uz_lit_sur_mm",
        "uy_lit_sur_mm",
        "angle_lit_sur_deg",
        "force_lit_sur_n",
        "be_lit_sur_mm",
        "uz_cal_sur_mm",
        "uy_cal_sur_mm",
        "angle_cal_sur_deg",
        "force_cal_sur_n",
        "be_cal_sur_mm",
        "uz_cal_fe_mm",
        "uy_cal_fe_mm",
        "angle_cal_fe_deg",
        "force_cal_fe_n",
        "be_cal_fe_mm",
    ])?;
    for r in &cal.configurations {
        let f = fe.and_then(|v| {
            v.rows.iter().find(|x| {
                x.config.n_bellows == r.n_bellows
                    && x.config.wall_thickness_mm == r.wall_thickness_mm
                    && x.config.pressure_bar == r.pressure_bar
            })
        });
        let nan = f64::NAN;
        let fev = f.map_or([nan; 5], |x| {
            [
                x.fe.uz_sim_mm,
                x.fe.uy_sim_mm,
                x.fe.angle_sim_deg,
                x.fe.force_sim_n,
                x.fe.be_mm,
            ]
        });
        let mut rec: Vec<String> = vec![
            r.n_bellows.to_string(),
            r.wall_thickness_mm.to_string(),
            r.pressure_bar.to_string(),
            r.fitted.to_string(),
        ];
        for v in [
            r.uz_exp_mm,
            r.uy_exp_mm,
            r.angle_exp_deg,
            r.force_exp_n,
            r.uz_lit_mm,
            r.uy_lit_mm,
            r.angle_lit_deg,
            r.force_lit_n,
            r.be_lit_mm,
            r.uz_cal_mm,
            r.uy_cal_mm,
            r.angle_cal_deg,
            r.force_cal_n,
            r.be_cal_mm,
        ]
        .into_iter()
        .chain(fev)
        {
            rec.push(if v.is_finite() {
                format!("{v:.4}")
            } else {
                String::new()
            });
        }
        w.write_record(&rec)?;
    }
    Ok(w.into_inner()?)
}

/// The report a person reads first (Markdown).
pub fn summary_text(cal: &Calibration, fe: Option<&FeVerification>) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let b = &cal.best;
    let l = &cal.literature;
    let _ = writeln!(s, "# Calibration\n");
    let _ = writeln!(
        s,
        "{}\n",
        verdict::fit_verdict(cal.chi2, cal.identifiability.dof)
    );
    let _ = writeln!(
        s,
        "Objective `{}`: {} observations at {} configurations, model {}.\n",
        cal.objective, cal.n_observations, cal.n_configurations, cal.model
    );
    let _ = writeln!(s, "{}", inputs::markdown(&cal.inputs));
    let _ = writeln!(s, "| set | μ1 (MPa) | α1 | μ2 (MPa) | α2 | μ0 (MPa) | χ² |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (name, p, c) in [
        ("literature", l, cal.chi2_literature),
        ("calibrated", b, cal.chi2),
    ] {
        // the set at full precision (shortest round trip): it is typed back as a material
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} | {} | {:.3} | {:.1} |",
            p.mu1_mpa,
            p.alpha1,
            p.mu2_mpa,
            p.alpha2,
            p.mu0_mpa(),
            c
        );
    }
    let _ = writeln!(
        s,
        "\nThe calibrated set as a material: `--material DIR/report.json` (this report's \
         directory; any command that takes a material), or `--material {},{},{},{}`.\n",
        b.mu1_mpa, b.alpha1, b.mu2_mpa, b.alpha2
    );
    let ls = &cal.literature_summary;
    let cs = &cal.calibrated;
    let _ = writeln!(
        s,
        "| through the surrogate | mean BE (mm) | median BE (mm) | the study's nine: mean BE (mm) | mean F error (N) | mean |F error| (N) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for (name, x) in [("literature", ls), ("calibrated", cs)] {
        let _ = writeln!(
            s,
            "| {name} | {:.2} | {:.2} | {:.2} | {:+.3} | {:.3} |",
            x.mean_be_mm,
            x.median_be_mm,
            x.paper_nine_mean_be_mm,
            x.mean_force_error_n,
            x.mean_abs_force_error_n
        );
    }
    if let Some(v) = fe {
        let x = &v.summary;
        let _ = writeln!(
            s,
            "| calibrated, FE ({} mesh) | {:.2} | {:.2} | {:.2} | {:+.3} | {:.3} |",
            v.mesh,
            x.mean_be_mm,
            x.median_be_mm,
            x.paper_nine_mean_be_mm,
            x.mean_force_error_n,
            x.mean_abs_force_error_n
        );
    }
    if let Some(line) = verdict::reference_study_line(&cal.inputs) {
        let _ = writeln!(s, "\n{line}");
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{} starts reached {} distinct minima (every end point is in report.json).",
        cal.starts.len(),
        cal.minima
    );
    let _ = writeln!(
        s,
        "\n| minimum | starts | χ² | μ1 (MPa) | α1 | μ2 (MPa) | α2 | on a bound |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for k in 0..cal.minima {
        let starts: Vec<_> = cal.starts.iter().filter(|st| st.minimum == k).collect();
        if let Some(f) = starts.first() {
            let e = &f.end;
            let _ = writeln!(
                s,
                "| {} | {} | {:.1} | {:.4} | {:.4} | {:.4} | {:.4} | {} |",
                k + 1,
                starts.len(),
                f.chi2,
                e.mu1_mpa,
                e.alpha1,
                e.mu2_mpa,
                e.alpha2,
                f.active_bounds.len()
            );
        }
    }
    let _ = writeln!(s);
    if cal.active_bounds.is_empty() {
        let _ = writeln!(
            s,
            "No bound of the training domain is active at the optimum."
        );
    } else {
        let _ = writeln!(
            s,
            "**The training box truncates this optimum**: it ends on {} (the fit would move \
             further if the box let it, and the surrogate does not know what lies there). The \
             numbers above are the best inside the box, not the best material; `surrogate \
             identify` fits straight on the FE model, without the box, and with the unstated \
             dimensions.",
            cal.active_bounds.join("; ")
        );
    }
    let id = &cal.identifiability;
    let _ = writeln!(
        s,
        "\n## What the data determine\n\nχ²/dof = {:.2} ({} observations − 4 parameters); covariance scaled by ŝ² = {:.2}.\n",
        cal.chi2 / id.dof as f64,
        cal.n_observations,
        id.variance_scale
    );
    let _ = writeln!(
        s,
        "| parameter | estimate | std error | 95 % profile interval | |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for (k, p) in id.profiles.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.3} | [{:.4}, {:.4}] | {} |",
            p.name,
            p.optimum,
            id.std_errors[k],
            p.interval[0],
            p.interval[1],
            p.determinacy.describe()
        );
    }
    let _ = writeln!(
        s,
        "\nEigen-directions of the information (unit box; std as a fraction of the box):\n"
    );
    for d in &id.directions {
        let v: Vec<String> = d
            .vector
            .iter()
            .filter(|(_, c)| c.abs() > 0.1)
            .map(|(n, c)| format!("{c:+.2} {n}"))
            .collect();
        let _ = writeln!(s, "- {} : std {:.3}", v.join(" "), d.std_fraction);
    }
    if !id.extra_measurements.is_empty() {
        let _ = writeln!(
            s,
            "\nExtra measurements (linearised; each row: the standard errors of {} with it added, as a fraction of today's):\n",
            id.names.join(" / ")
        );
        for m in &id.extra_measurements {
            let _ = writeln!(
                s,
                "- {}: × {}",
                m.measurement,
                m.ratio
                    .iter()
                    .map(|r| format!("{r:.2}"))
                    .collect::<Vec<_>>()
                    .join(" / ")
            );
        }
        for (k, p) in id.profiles.iter().enumerate() {
            if p.determinacy == surrogate::calibrate::identify::Determinacy::Determined {
                continue;
            }
            if let Some(m) = id
                .extra_measurements
                .iter()
                .min_by(|a, b| a.ratio[k].total_cmp(&b.ratio[k]))
            {
                let _ = writeln!(
                    s,
                    "\n{} is {}; the measurement that sharpens it most: {} (its standard error × {:.2}).",
                    p.name,
                    p.determinacy.describe(),
                    m.measurement,
                    m.ratio[k]
                );
            }
        }
    }
    if !cal.flags.is_empty() {
        let _ = writeln!(s, "\n## Data checks\n");
        for f in &cal.flags {
            let _ = writeln!(s, "- {} ({}): {}", f.config.label(), f.source, f.message);
        }
    }
    if !cal.excluded.is_empty() {
        let _ = writeln!(s, "\n## Excluded\n");
        for e in describe_exclusions(&cal.excluded) {
            let _ = writeln!(s, "- {e}");
        }
    }
    if let Some(st) = &cal.per_configuration {
        let _ = writeln!(
            s,
            "\n## The study's procedure: one set per configuration (±{:.0} % of the literature set)\n",
            100.0 * st.fraction
        );
        let _ = writeln!(
            s,
            "| | literature | per configuration | one set, same box |"
        );
        let _ = writeln!(s, "|---|---|---|---|");
        for (name, v) in [
            ("all, mean BE (mm)", &st.all),
            ("the study's nine, mean BE (mm)", &st.paper_nine),
        ] {
            let _ = writeln!(
                s,
                "| {name} | {:.2} | {:.2} | {:.2} |",
                v[0].mean_mm, v[1].mean_mm, v[2].mean_mm
            );
        }
        for (name, v) in [
            ("all, median BE (mm)", &st.all),
            ("the study's nine, median BE (mm)", &st.paper_nine),
        ] {
            let _ = writeln!(
                s,
                "| {name} | {:.2} | {:.2} | {:.2} |",
                v[0].median_mm, v[1].median_mm, v[2].median_mm
            );
        }
        let _ = writeln!(s, "\nSpread of the per-configuration sets:\n");
        let _ = writeln!(
            s,
            "| parameter | mean | std | CV | min | max | on the box |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for p in &st.spread {
            let _ = writeln!(
                s,
                "| {} | {:.4} | {:.4} | {:.1} % | {:.4} | {:.4} | {} of {} |",
                p.name,
                p.mean,
                p.std,
                100.0 * p.cv,
                p.min,
                p.max,
                p.on_box,
                st.fits.len()
            );
        }
    }
    if let Some(v) = fe {
        let _ = writeln!(
            s,
            "\n## FE verification ({} mesh)\n\nSurrogate vs FE at the optimum: mean |Δ| tip Uz {:.2} mm, tip Uy {:.2} mm, force {:.3} N (max {:.2} / {:.2} / {:.3}); {} configurations outside the surrogate's 2σ band.",
            v.mesh,
            v.mean_abs_sur_fe[0],
            v.mean_abs_sur_fe[1],
            v.mean_abs_sur_fe[2],
            v.max_abs_sur_fe[0],
            v.max_abs_sur_fe[1],
            v.max_abs_sur_fe[2],
            v.disagreements
        );
        if !v.designs_to_refine.is_empty() {
            let d: Vec<String> = v
                .designs_to_refine
                .iter()
                .map(|(n, t)| format!("N={n} T={t}"))
                .collect();
            let _ = writeln!(
                s,
                "Designs to add as high-fidelity cases before refitting: {}.",
                d.join(", ")
            );
        }
    }
    let _ = writeln!(s, "\nCalibration time: {:.2} s.", cal.wall_time_s);
    s
}
