//! The diagnoser's commands: `diagnose`, `twin`, `twin-study`, `approximation-error`.
use std::path::PathBuf;

use clap::Args;
use surrogate::diagnose::setup::{
    ApproximationSource, DiagnosisSetup, MeshReference, Sensitivities, SetupFile,
};

use super::MeshRefinementArgs;
use crate::files::material_spec;

/// How a diagnosis is set up, the same flags for `diagnose` and `twin-study`
/// ([`surrogate::diagnose::setup`]); a flag left out takes the command's default.
#[derive(Debug, Args)]
#[command(next_help_heading = "Diagnosis setup (the same flags in `diagnose` and `twin-study`)")]
pub struct DiagnosisSetupArgs {
    /// The diagnosing surrogate, through which the calibration and the predictions go
    /// [default: models/actuator_coarse.json for `diagnose`,
    /// models/as_modelled/actuator_coarse.json for `twin-study` (its twins are built on the
    /// geometry as modelled); of the repository the program was built from, from any working
    /// directory].
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// FE sensitivities of the effect library (a file of `validate --sensitivities all`),
    /// with which Name ranks the effects and Model and show refits; `diagnose` also takes
    /// `calibrated` (that sweep run now at the material just calibrated on --sweep-mesh, 18
    /// ramps cached in `<out>/fe_sensitivities`) and `none` (no Name, no Model) [default:
    /// data/sensitivities/identified_calibrated_coarse.json for `diagnose` (at the shipped
    /// experiments' calibrated material, on the shipped models' geometry),
    /// data/sensitivities/ogden002_coarse.json for `twin-study`; of the repository].
    #[arg(long, value_name = "FILE|calibrated|none")]
    pub sensitivities: Option<String>,
    /// A surrogate on another mesh whose difference to --model at the calibrated material is
    /// tested as the model's own mesh error: `auto` (actuator.json beside a model named
    /// actuator_coarse.json and the other way round, else none), `none` or a model
    /// file; `twin-study` writes its results with one to results*_mesh.* [default: none (the
    /// approximation error holds the model's mesh error)].
    #[arg(long, value_name = "auto|none|FILE")]
    pub mesh_reference: Option<String>,
    /// The model's approximation error against a finer discretisation, by whose mean the
    /// recordings are corrected and by whose covariance Name weighs the residual: `none`, a
    /// file (as `approximation-error` writes) or `nulls` (`twin-study` only: sampled from the
    /// null twins' noise-free FE, each null twin diagnosed without its own group's sample,
    /// written to `<out>/approximation_error.json`); `twin-study` writes its results without
    /// one to results*_no_approx.*, with `nulls` to results*_nulls.* [default: the default
    /// model of the command against FE on 4 mm elements, of the repository:
    /// data/approximation_error/identified_coarse_vs_4mm.json for `diagnose`,
    /// data/approximation_error/coarse_vs_4mm.json for `twin-study`].
    #[arg(long, value_name = "none|nulls|FILE")]
    pub approximation_error: Option<String>,
}

impl DiagnosisSetupArgs {
    /// The command's setup `defaults` ([`DiagnosisSetup::recordings`] or
    /// [`DiagnosisSetup::blind_study`]) with the flags given.
    pub fn setup(&self, defaults: DiagnosisSetup) -> DiagnosisSetup {
        let mut s = defaults;
        if let Some(p) = &self.model {
            s.model = SetupFile::Given(p.clone());
        }
        if let Some(v) = &self.sensitivities {
            s.sensitivities = Sensitivities::from_flag(v);
        }
        if let Some(v) = &self.mesh_reference {
            s.mesh_reference = MeshReference::from_flag(v);
        }
        if let Some(v) = &self.approximation_error {
            s.approximation_error = ApproximationSource::from_flag(v);
        }
        s
    }
}

/// `surrogate diagnose`.
#[derive(Debug, Args)]
pub struct DiagnoseArgs {
    /// Directory of recordings in the shipped experiments' format: bending_experiments.csv
    /// (required), blocked_force_experiments.csv and marker_experiments.csv (where they
    /// exist; what is missing is said in the report) [default: training_data/ of the
    /// repository; every file read is listed in the report, defaults as such].
    #[arg(long)]
    pub recordings: Option<PathBuf>,
    /// Objective of the calibration: tip, angle, force, markers, all, or weights such as
    /// tip=1,force=0.5; the recorded outputs it leaves out are diagnosed too.
    #[arg(long, default_value = "tip")]
    pub objective: String,
    /// Leave out a configuration: N,T,P (both recordings), bending:N,T,P or force:N,T,P
    /// (repeatable; listed in the report).
    #[arg(long, allow_hyphen_values = true)]
    pub exclude: Vec<String>,
    /// Also leave out every row the data checks flag.
    #[arg(long)]
    pub exclude_flagged: bool,
    /// Family-wise significance level of all the report's tests together (Holm), in (0, 0.5].
    #[arg(long, default_value_t = surrogate::diagnose::LocateSettings::default().alpha)]
    pub alpha: f64,
    /// Output directory: diagnosis.json, summary.md, residual_map.svg, residual_trends.svg
    /// (and along_actuator.svg with marker recordings).
    #[arg(long, default_value = "diagnosis")]
    pub out: PathBuf,
    /// Model and show: `auto` refits the material with the effect the Name stage names (and
    /// nothing when it names none), `none` skips the refit, or a comma list of effects to
    /// refit with whatever the Name stage says (`force_scale`, `gap_bias,pressure_loss`).
    #[arg(long, default_value = "auto")]
    pub refit: String,
    /// Confirm the refit with the FE model on this mesh (coarse | standard; `none` skips):
    /// the recorded designs run with the effect on at its refitted values, the refit redone
    /// around the FE where the two differ (18 ramps per round, cached).
    #[arg(long, default_value = "none")]
    pub confirm_fe: String,
    /// Rank the Name stage's top K candidates (significant, at a plausible size) by
    /// FE-confirmed nonlinear fits instead of their linearised Δχ²: each refitted with the
    /// material, run on the FE model on the `--confirm-fe` mesh and refitted around it (18
    /// ramps per round and candidate, cached in `<fe-cache>/rank_<effect>/`); `--refit auto`
    /// then refits the FE's first. 0 (the default) ranks by the linearisation alone.
    #[arg(long, default_value_t = 0)]
    pub rank_fe: usize,
    /// FE cache of the confirmation (default: `<out>/fe_ramps`).
    #[arg(long)]
    pub fe_cache: Option<PathBuf>,
    /// Mesh of the sweep `--sensitivities calibrated` runs (coarse | standard).
    #[arg(long, default_value = "coarse")]
    pub sweep_mesh: String,
    /// Measurements to propose (0 to 3) that would best separate the candidates the Name
    /// stage finds tied with the first: markers, other pressures or designs, blocked forces
    /// the FE sensitivities evaluate and the recordings lack (T-optimal discrimination);
    /// written as "What to measure next" in summary.md and `measurement_plan` in
    /// diagnosis.json; 0 plans nothing.
    #[arg(long, default_value_t = surrogate::diagnose::measure_design::MAX_PLANNED)]
    pub plan_measurements: usize,
    /// The model, the FE sensitivities, the mesh reference, the approximation error (last:
    /// their help heading is not carried over to the flags after them).
    #[command(flatten)]
    pub setup: DiagnosisSetupArgs,
}

/// `surrogate twin`.
#[derive(Debug, Args)]
pub struct TwinArgs {
    /// A concealed effect, NAME=VALUE (repeatable; none: a twin of the material alone);
    /// `surrogate effects` lists the names, units and ranges.
    #[arg(long, value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub effect: Vec<String>,
    /// Material (see `simulate --help`).
    #[arg(long, allow_hyphen_values = true, value_parser = material_spec)]
    pub material: String,
    /// Mesh level: coarse | standard | fine.
    #[arg(long, default_value = "standard")]
    pub mesh: String,
    /// A discretisation other than the diagnosing model's.
    #[command(flatten)]
    pub refinement: MeshRefinementArgs,
    /// The dimensions the reference study leaves unstated: as_modelled, identified, or a geometry preset
    /// file such as `surrogate identify` writes (geometry.json); in the key.
    #[arg(long, default_value = "as_modelled")]
    pub geometry: String,
    /// Directory with the recordings whose designs, pressures and standard deviations the
    /// twin takes (bending_experiments.csv, blocked_force_experiments.csv) [default:
    /// training_data/ of the repository the program was built from, from any working
    /// directory].
    #[arg(long)]
    pub noise_from: Option<PathBuf>,
    /// Seed of the noise.
    #[arg(long)]
    pub seed: u64,
    /// Output directory: bending_experiments.csv, blocked_force_experiments.csv,
    /// marker_experiments.csv, nothing else.
    #[arg(long)]
    pub out: PathBuf,
    /// Key file (JSON: effects, material, mesh, seed, version and commit); outside --out.
    #[arg(long)]
    pub key: Option<PathBuf>,
    /// FE cache (default: `twin_fe_ramps/` beside --out, shared by every twin there; ramps
    /// are keyed by every setting, so a twin with another seed runs no FE); outside --out.
    #[arg(long)]
    pub cache: Option<PathBuf>,
}

/// `surrogate twin-study`.
#[derive(Debug, Args)]
pub struct TwinStudyArgs {
    /// Output directory: plan.json, fe_cache/, twins/, keys/, diagnoses/, results.json,
    /// results.md [default: fe_reference/diagnosis/blind/ of the repository the program was
    /// built from, from any working directory].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The plan (default `<out>/plan.json`; the standard plan is written there if absent).
    #[arg(long)]
    pub plan: Option<PathBuf>,
    /// Seed of the standard plan's material draws (when it is written).
    #[arg(long, default_value_t = 2026)]
    pub draw_seed: u64,
    /// What to run: twins (the FE, resumable), diagnose (the twins made so far), all (both),
    /// or loop: each twin diagnosed, the measurements its plan proposes made on the twin's
    /// FE with fresh noise and the twin diagnosed again, against as many measurements drawn at
    /// random (results_loop*.json / .md).
    #[arg(long, default_value = "all")]
    pub stage: String,
    /// Measurements planned per twin by `--stage loop` (1 to 3).
    #[arg(long, default_value_t = 3)]
    pub loop_k: usize,
    /// `--stage loop`: plan the measurements one at a time, each on the diagnosis with the
    /// ones before (results_loop_sequential*.json / .md).
    #[arg(long)]
    pub loop_sequential: bool,
    /// Recordings whose designs, pressures and standard deviations the twins take [default:
    /// training_data/ of the repository].
    #[arg(long)]
    pub noise_from: Option<PathBuf>,
    /// Diagnose with the twins' marker recordings (`yes`/`no`; default: the plan's
    /// `markers`); results with another setting than the plan's go to results_markers.* /
    /// results_no_markers.*.
    #[arg(long)]
    pub markers: Option<String>,
    /// Only these groups of the plan (comma list of ids, e.g. `null_1,gap_bias_2`; default
    /// all): two processes with disjoint groups keep two cores busy.
    #[arg(long, value_delimiter = ',')]
    pub groups: Vec<String>,
    /// The model, the FE sensitivities, the mesh reference, the approximation error (last:
    /// their help heading is not carried over to the flags after them).
    #[command(flatten)]
    pub setup: DiagnosisSetupArgs,
}

/// `surrogate approximation-error`.
#[derive(Debug, Args)]
pub struct ApproximationErrorArgs {
    /// The surrogate whose error is sampled [default: models/actuator.json of the
    /// repository the program was built from, from any working directory].
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// The reference FE's mesh level: coarse | standard | fine.
    #[arg(long, default_value = "fine")]
    pub mesh: String,
    /// The reference's element size and elements through a wall.
    #[command(flatten)]
    pub refinement: MeshRefinementArgs,
    /// Number of materials, drawn by a Latin hypercube over the central 80 % of the model's
    /// training domain (each costs 2 FE ramps per recorded design).
    #[arg(long, default_value_t = 6)]
    pub materials: usize,
    /// Seed of the draw.
    #[arg(long, default_value_t = 2026)]
    pub seed: u64,
    /// Directory with the recordings whose designs and pressures are sampled (and whose
    /// standard deviations scale the error in reports) [default: training_data/ of the
    /// repository the program was built from, from any working directory].
    #[arg(long)]
    pub recordings: Option<PathBuf>,
    /// FE cache (default: `approximation_fe_ramps/` beside `--out`; a rerun resumes).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// The file to write.
    #[arg(long)]
    pub out: PathBuf,
}
