//! `surrogate calibrate`: one Ogden set for the recordings, through the surrogate; its
//! identifiability, the study's per-configuration procedure, and the FE verification.
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::calibrate::experiments::{SHIPPED_BENDING, SHIPPED_FORCE};
use surrogate::calibrate::extend::ExtendSettings;
use surrogate::calibrate::identify::IdentifySettings;
use surrogate::calibrate::inputs::InputFile;
use surrogate::calibrate::objective::Exclusion;
use surrogate::calibrate::optimise::MultistartSettings;
use surrogate::calibrate::refine::{refine, RefineEvent, RefineSettings, Refinement, TrainingSet};
use surrogate::calibrate::verify::{verify_fe, FeVerification};
use surrogate::calibrate::{
    calibrate, Calibration, CalibrationSettings, Recordings, Selection, Weights,
};
use surrogate::case::OgdenSet;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::rom::Surrogate;
use surrogate::snapshots::run::{AnalyticRunner, CaseRunner};

use crate::calibrate_plots::write_plots;
use crate::files::{
    given_or_default, input_file, load_model, repository_file, write_file, DEFAULT_MODEL,
};
use crate::snapshots::RunnerArg;

/// The report a person reads first (Markdown).
pub use surrogate::calibrate::summary::summary_markdown as summary_text;

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
    /// The refined or extended model's training snapshots (default: the source the model
    /// records, relative to the working directory); its plan is read from `<stem>.plan.json`
    /// beside it. A multi-fidelity model needs both of its sets: leave --training out.
    #[arg(long)]
    pub training: Option<PathBuf>,
    /// FE cases run in parallel by the refinement or the box extension (default: one per
    /// core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The refinement stops when the refit moves no recorded number's prediction by more than
    /// this many of its standard deviations from the verified set's (0: off; then only
    /// agreement, an unchanged set or --refine rounds stop it).
    #[arg(long, default_value_t = RefineSettings::default().data_tolerance)]
    pub refine_data_tolerance: f64,
    /// Box extension: up to this many rounds, each moving out the bounds of the training box
    /// that the calibrated optimum presses (by --extend-step of the coordinate's range, up to
    /// its physical limit: μ0 0.01–100 MPa, term1_share 0.001–0.999, |α| 0.001–20), running
    /// --extend-cases new FE cases in the slab beyond (the training plan's settings; both
    /// meshes of a multi-fidelity model), retraining the surrogate and refitting (0: off).
    /// Stops when the optimum lies inside the box, when every bound it presses is at its
    /// physical limit, or after K rounds. Needs the model's training set (--training, or the
    /// source the model records); FE cases, retrained models, extension.json and extension.md
    /// in `<out>/extend/` (a rerun resumes); summary.md gets a "Box extension" section.
    #[arg(long, default_value_t = 0, value_name = "K")]
    pub extend_box: usize,
    /// How far each pressed bound moves per round, as a fraction of its coordinate's current
    /// range (in ln μ0 for μ0); > 0.
    #[arg(long, default_value_t = ExtendSettings::default().step)]
    pub extend_step: f64,
    /// New FE cases per extension round, shared among the slabs by volume and stratified over
    /// the trained values of N (at least 2 per value).
    #[arg(long, default_value_t = ExtendSettings::default().cases_per_round)]
    pub extend_cases: usize,
    /// Seed of the extension rounds' Latin hypercubes (the same seed plans the same cases).
    #[arg(long, default_value_t = ExtendSettings::default().seed)]
    pub extend_seed: u64,
    /// Who runs the cases of --refine and --extend-box: the FE model, or the closed-form
    /// stand-in (dry runs of the rounds' machinery, no physics).
    #[arg(long, value_enum, default_value = "fe")]
    pub runner: RunnerArg,
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

/// What every calibration reads and checks first: the model (and its file, for the report),
/// the recordings, the settings and the mesh of `--verify-fe`.
pub struct Inputs {
    /// The surrogate.
    pub model: Surrogate,
    /// Its file, checksummed.
    pub model_file: InputFile,
    /// The recordings.
    pub rec: Recordings,
    /// The calibration's settings.
    pub settings: CalibrationSettings,
    /// `--verify-fe` (`None`: no FE verification).
    pub mesh: Option<MeshLevel>,
}

/// Reads and checks the [`Inputs`] of `a`.
pub fn inputs(a: &CalibrateArgs) -> Result<Inputs> {
    let (model_path, default) = given_or_default(a.model.as_deref(), DEFAULT_MODEL);
    let model = load_model(&model_path)?;
    let model_file = input_file("model", &model_path, default)?;
    let rec = recordings(a)?;
    let settings = settings(a)?;
    let mesh = match a.verify_fe.as_str() {
        "none" => None,
        m => Some(m.parse::<MeshLevel>().map_err(anyhow::Error::msg)?),
    };
    Ok(Inputs {
        model,
        model_file,
        rec,
        settings,
        mesh,
    })
}

/// Runs the subcommand (`--extend-box` is [`crate::calibrate_extend::run`]).
pub fn run(a: CalibrateArgs) -> Result<()> {
    let Inputs {
        model,
        model_file,
        rec,
        settings: s,
        mesh,
    } = inputs(&a)?;
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
    let training = training_set(a, model)?;
    let settings = RefineSettings {
        max_rounds: a.refine,
        train: RefineSettings::default().train.like(&model.training),
        calibration,
        threads: a.threads,
        data_tolerance: a.refine_data_tolerance,
    };
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let dir = a.out.join("refine");
    eprintln!(
        "adaptive refinement: up to {} rounds on {} (FE cached in {}; a rerun resumes)",
        a.refine,
        meshes(&training),
        dir.display()
    );
    let bar = ProgressBar::hidden();
    bar.set_style(ProgressStyle::with_template(
        "{spinner} round {msg} FE cases [{bar:30}] {pos}/{len}, {elapsed_precise}, eta {eta}",
    )?);
    let runner = runner(a);
    let mut r = refine(
        model,
        &training,
        rec,
        &settings,
        runner.as_ref(),
        &dir,
        &|ev| show_refine_event(&bar, ev),
    )?;
    r.last.inputs.insert(0, model_file.clone());
    let mut written = write_outputs(&a.out, &r.last, Some(r.final_verification()))?;
    let md = r.summary_markdown();
    written.extend(write_refinement(&a.out, &r, &md)?);
    print!("{}", summary_text(&r.last, Some(r.final_verification())));
    print!("\n{md}");
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The case runner of `--refine` and `--extend-box` (`--runner`).
pub fn runner(a: &CalibrateArgs) -> Box<dyn CaseRunner> {
    match a.runner {
        RunnerArg::Fe => Box::new(surrogate::snapshots::fe_runner::fe_runner),
        RunnerArg::Analytic => Box::new(AnalyticRunner::default()),
    }
}

/// The refined or extended model's training set: `--training` (its plan beside it), or the
/// source the model records (relative to the repository for the default model).
pub fn training_set(a: &CalibrateArgs, model: &Surrogate) -> Result<TrainingSet> {
    Ok(match &a.training {
        Some(csv) => TrainingSet::read(csv, &surrogate::snapshots::merge::sidecar_path(csv))?,
        None => TrainingSet::of_model(
            model,
            &if a.model.is_none() {
                repository_file("")
            } else {
                PathBuf::from(".")
            },
        )?,
    })
}

/// The meshes the refinement runs on, in words.
fn meshes(training: &TrainingSet) -> String {
    let low = format!(
        "the {} mesh of {}",
        training.plan.settings.mesh.level.name(),
        training.snapshots.source
    );
    match &training.high {
        Some(h) => format!(
            "{low} and the {} mesh of {}",
            h.plan.settings.mesh.level.name(),
            h.snapshots.source
        ),
        None => low,
    }
}

/// One round's FE cases on the progress bar `bar` (shown from the round's first case, cleared
/// after its last), labelled `round`.
pub(crate) fn show_fe_progress(
    bar: &ProgressBar,
    round: &dyn std::fmt::Display,
    progress: &surrogate::snapshots::run::Progress,
) {
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

/// A refinement event on stderr: stages and rounds as lines, FE cases on the progress bar.
fn show_refine_event(bar: &ProgressBar, ev: RefineEvent) {
    match ev {
        RefineEvent::Stage(s) => bar.suspend(|| eprintln!("{s}")),
        RefineEvent::Fe { round, progress } => {
            show_fe_progress(bar, &round, &progress);
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
}

/// Writes `refinement.md` (the account `md`), `refinement.json` and `refinement.svg`.
fn write_refinement(out: &Path, r: &Refinement, md: &str) -> Result<Vec<PathBuf>> {
    let p = out.join("refinement.md");
    write_file(&p, md.as_bytes())?;
    let q = out.join("refinement.json");
    write_file(&q, serde_json::to_string_pretty(r)?.as_bytes())?;
    let v = out.join("refinement.svg");
    crate::calibrate_plots::refinement(r, &v)?;
    Ok(vec![p, q, v])
}

/// The FE verification of `best` on `level`, compared with `model`, cached in `cache`.
pub fn run_fe(
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
