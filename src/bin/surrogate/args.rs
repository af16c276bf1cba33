//! Command-line arguments (clap derive), one struct per subcommand.
use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand, ValueEnum};
use surrogate::rom::regression::{Registry, RegressorKind};

use crate::files::material_spec;

/// Finite-element model and reduced-order surrogate of soft pneumatic bellow actuators.
#[derive(Debug, Parser)]
#[command(name = "surrogate", version, about)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The main job on the shipped data: FE model of an experimental design vs the experiments.
    Demo(DemoArgs),
    /// Run the full FE model of one design over a pressure ramp.
    Simulate(SimulateArgs),
    /// FE campaigns with warm starts: `--bench` measures a material sweep cold against warm.
    Campaign(crate::campaign::CampaignArgs),
    /// Train a POD + regression surrogate on a snapshot CSV.
    Train(TrainArgs),
    /// Predict with a trained surrogate (one query or a CSV batch).
    Predict(PredictArgs),
    /// Export a surrogate for the embedded predictor (Rust tables + C header).
    Export(ExportArgs),
    /// Learn the model-form error (how far the calibrated model misses the recordings) from a
    /// calibration report and store it in the model file.
    ModelForm(crate::model_form::ModelFormArgs),
    /// The literature baseline: FE with contact vs every experimental configuration.
    Validate(ValidateArgs),
    /// Fit one Ogden set to the recordings through the surrogate; identifiability, FE verification.
    Calibrate(Box<crate::calibrate::CalibrateArgs>),
    /// Snapshots: sampling plans, shard runs (resumable), merges.
    Snapshots(Box<crate::snapshots::SnapshotsArgs>),
    /// List the effect library: physics the nominal model leaves out (name, meaning, unit,
    /// neutral value, range).
    Effects(EffectsArgs),
    /// Twin recordings: the FE model with concealed effects, noise at the experiments'
    /// standard deviations, in the experiments' format; the settings to a key file only.
    Twin(TwinArgs),
    /// Where the calibrated model misses the recordings: residuals over N, T, P (and along
    /// the actuator), their structure and sign patterns in words, what the recordings lack.
    Diagnose(DiagnoseArgs),
    /// The diagnoser's blind study: twins with concealed effects and null twins, each
    /// diagnosed without its key, scored against the keys.
    TwinStudy(TwinStudyArgs),
    /// The model's approximation error: reference FE (another mesh, no effect) at materials
    /// spread over the domain against the surrogate, for `diagnose --approximation-error`.
    ApproximationError(ApproximationErrorArgs),
    /// Identify the material and the dimensions the reference study leaves unstated (gap,
    /// base, side walls, the force rig's plate) jointly, straight on the FE model.
    Identify(IdentifyArgs),
    /// Design through the surrogate: the number of bellows and the wall thickness that reach
    /// target outputs (angle, force, tip) at given pressures, the best wall for every N.
    Design(crate::design::DesignArgs),
    /// Maps of the outputs over N and T at a few pressures (SVG heat maps and CSV), walls
    /// that leave no cavity greyed out.
    Maps(crate::maps::MapsArgs),
}

/// `surrogate identify`.
#[derive(Debug, Args)]
pub struct IdentifyArgs {
    /// The unknowns, comma-separated: mu1, alpha1, mu2, alpha2, gap, base, duct, side_wall,
    /// free_length, wall_law_offset, wall_law_inverse_cavity (every wall of a design off by
    /// offset + inverse_cavity / c, c its drawn cavity length), or an effect name
    /// (plate_offset, wall_bias_bellows, clamp_compliance, …).
    #[arg(
        long,
        default_value = "mu1,alpha1,mu2,alpha2,gap,side_wall,base,plate_offset"
    )]
    pub unknowns: String,
    /// Starting material: a name, mu1,alpha1,mu2,alpha2 (second-order Ogden) or a calibration
    /// report DIR/report.json.
    #[arg(long, default_value = "ogden_002", value_parser = material_spec)]
    pub material: String,
    /// Starting geometry: as_modelled or a preset file (.json).
    #[arg(long, default_value = "as_modelled")]
    pub geometry: String,
    /// Starting values, NAME=VALUE (repeatable): a dimension (gap=0.5, side_wall=1.2) or an
    /// effect (plate_offset=-2).
    #[arg(long = "set")]
    pub set: Vec<String>,
    /// Directory of the recordings (bending_experiments.csv, blocked_force_experiments.csv);
    /// default: the shipped experiments in training_data/, named in the report.
    #[arg(long)]
    pub recordings: Option<PathBuf>,
    /// FE mesh level: coarse | standard | fine.
    #[arg(long, default_value = "coarse")]
    pub mesh: String,
    /// Largest number of FE sweeps (one sweep: every recorded design in both rigs, with the
    /// sensitivities).
    #[arg(long, default_value_t = 12)]
    pub max_sweeps: usize,
    /// Initial Levenberg–Marquardt damping.
    #[arg(long, default_value_t = 1e-2)]
    pub lambda: f64,
    /// Initial trust radius: the largest move of an unknown in one step, as a fraction of its
    /// range (halved when a step it shortened fails, doubled when one it shortened succeeds and
    /// was well predicted).
    #[arg(long, default_value_t = 0.1)]
    pub max_step: f64,
    /// Start every ramp from the undeformed actuator. By default each sweep's ramps start from
    /// the previous sweep's converged states, moved by their sensitivities (same answers to
    /// the solver's tolerance, a fraction of the Newton iterations).
    #[arg(long)]
    pub cold: bool,
    /// Model-form floor on each tip coordinate (mm), added in quadrature to the recorded
    /// scatter (chord × angle scatter).
    #[arg(long, default_value_t = 2.0)]
    pub model_sigma_tip: f64,
    /// Model-form floor on the blocked force (N), added in quadrature to its recorded scatter.
    #[arg(long, default_value_t = 0.15)]
    pub model_sigma_force: f64,
    /// Leave a recorded row out of the fit: N,T,P (both recordings), bending:N,T,P or
    /// force:N,T,P (repeatable). Its FE values are still reported, marked.
    #[arg(long, allow_hyphen_values = true)]
    pub exclude: Vec<String>,
    /// Also leave out every row the data checks flag (listed in the summary with the reason).
    #[arg(long)]
    pub exclude_flagged: bool,
    /// Fit what the standard mesh gives while running the coarse one: FINE.csv,COARSE.csv, two
    /// `surrogate validate` tables at the same point (for example the start), whose
    /// difference is added to every FE value (space mapping's output correction). Verify the
    /// optimum on the standard mesh afterwards.
    #[arg(long, value_name = "FINE.csv,COARSE.csv")]
    pub mesh_correction: Option<String>,
    /// Output directory: report.json, summary.md, the identified geometry (geometry.json) and
    /// the FE cache (fe_ramps/; a rerun resumes from it).
    #[arg(long, default_value = "identify_output")]
    pub out: PathBuf,
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
    /// Element size override of the reference in mm.
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Minimum number of the reference's elements through a wall.
    #[arg(long)]
    pub wall_elements: Option<usize>,
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
    /// The diagnosing surrogate [default: models/actuator_coarse.json of the repository the
    /// program was built from, from any working directory].
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// The FE sensitivities the Name and Model stages use [default:
    /// data/sensitivities/ogden002_coarse.json of the repository].
    #[arg(long)]
    pub sensitivities: Option<PathBuf>,
    /// Recordings whose designs, pressures and standard deviations the twins take [default:
    /// training_data/ of the repository].
    #[arg(long)]
    pub noise_from: Option<PathBuf>,
    /// Diagnose with the twins' marker recordings (`yes`/`no`; default: the plan's
    /// `markers`); results with another setting than the plan's go to results_markers.* /
    /// results_no_markers.*.
    #[arg(long)]
    pub markers: Option<String>,
    /// A surrogate of the same plan on another mesh: its difference to `--model` is tested
    /// as the model's own mesh error beside the effects, as `diagnose` does by default
    /// (`auto`: the other shipped model, `models/actuator.json` beside the coarse one, results
    /// then go to results*_mesh.*; a model file; `none`: not tested, as the approximation
    /// error of `--approximation-error nulls` holds the model's mesh error already).
    #[arg(long, default_value = "none")]
    pub mesh_reference: String,
    /// The diagnosing model's approximation error against the twins' discretisation:
    /// `nulls` samples it from the null twins' noise-free FE (each null twin diagnosed
    /// without its own group's sample; written to `<out>/approximation_error.json`), `none`
    /// leaves it out (results then go to results*_no_approx.*).
    #[arg(long, default_value = "nulls")]
    pub approximation_error: String,
    /// Only these groups of the plan (comma list of ids, e.g. `null_1,gap_bias_2`; default
    /// all): two processes with disjoint groups keep two cores busy.
    #[arg(long, value_delimiter = ',')]
    pub groups: Vec<String>,
}

/// `surrogate diagnose`.
#[derive(Debug, Args)]
pub struct DiagnoseArgs {
    /// Surrogate model file (the calibration and the predictions go through it) [default:
    /// models/actuator.json of the repository the program was built from, from any working
    /// directory].
    #[arg(long)]
    pub model: Option<PathBuf>,
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
    /// FE sensitivities of the effect library at the calibrated material (written by
    /// `validate --sensitivities all`); the Name stage ranks the effects with them.
    /// `calibrated` runs that sweep now, at the material just calibrated (18 ramps on
    /// --sweep-mesh, cached in `<out>/fe_sensitivities`); `none` skips Name and Model
    /// [default: data/sensitivities/calibrated_coarse.json of the repository, the sweep at the
    /// shipped experiments' calibrated material].
    #[arg(long)]
    pub sensitivities: Option<PathBuf>,
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
    /// FE cache of the confirmation (default: `<out>/fe_ramps`).
    #[arg(long)]
    pub fe_cache: Option<PathBuf>,
    /// Mesh of the sweep `--sensitivities calibrated` runs (coarse | standard).
    #[arg(long, default_value = "coarse")]
    pub sweep_mesh: String,
    /// A surrogate of the same plan on another mesh: its difference to `--model` at the
    /// calibrated material is tested as the model's own mesh error beside the effects
    /// (`auto`: the other shipped model, `models/actuator_coarse.json` beside
    /// `models/actuator.json` and the reverse; `none`: not tested; or a model file).
    #[arg(long, default_value = "auto")]
    pub mesh_reference: String,
    /// The model's approximation error against a finer reference (a file `twin-study`
    /// writes as `approximation_error.json`, or one made with
    /// `surrogate::diagnose::approx_error`): the recordings are corrected by its mean and
    /// the Name stage weighs the residual by its covariance. Default: none.
    #[arg(long)]
    pub approximation_error: Option<PathBuf>,
    /// Measurements to propose (0 to 3) that would best separate the candidates the Name
    /// stage finds tied with the first: markers, other pressures or designs, blocked forces
    /// the FE sensitivities evaluate and the recordings lack (T-optimal discrimination);
    /// written as "What to measure next" in summary.md and `measurement_plan` in
    /// diagnosis.json; 0 plans nothing.
    #[arg(long, default_value_t = surrogate::diagnose::measure_design::MAX_PLANNED)]
    pub plan_measurements: usize,
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
    /// Element size override in mm (a discretisation other than the diagnosing model's).
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Minimum number of elements through a wall (overrides the level's).
    #[arg(long)]
    pub wall_elements: Option<usize>,
    /// The dimensions the reference study leaves unstated: as_modelled, or a geometry preset
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

/// `surrogate effects`.
#[derive(Debug, Args)]
pub struct EffectsArgs {
    /// Write the library as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// `surrogate train`.
#[derive(Debug, Args)]
pub struct TrainArgs {
    /// Snapshot CSV (see the snapshot contract). The plan beside it (`<stem>.plan.json`,
    /// written by `snapshots merge`), when present, gives the model's domain its nominal
    /// ranges where the cases cover them (stated in the model file).
    #[arg(long, required_unless_present = "synthetic")]
    pub data: Option<PathBuf>,
    /// Train on a built-in synthetic set of this many cases instead of --data (demos, tests).
    #[arg(long, conflicts_with = "data")]
    pub synthetic: Option<usize>,
    /// High-fidelity snapshots of a subset of the --data cases (`snapshots subset`, same case
    /// ids): the low-fidelity set is corrected by a surrogate of the discrepancy before training.
    #[arg(long, requires = "data")]
    pub high_fidelity: Option<PathBuf>,
    /// With --high-fidelity: also measure the whole pipeline against high-fidelity cases it
    /// never saw (k-fold over the high-fidelity cases: discrepancy, correction and surrogate
    /// refitted per fold) and store the result in the model; about 2 × folds trainings more.
    #[arg(long, requires = "high_fidelity")]
    pub check_high_fidelity: bool,
    /// With --high-fidelity: warp the low-fidelity ramps in pressure (a scale per case,
    /// regressed on the design and material) before the additive discrepancy, for a low
    /// fidelity whose contact sets in at another pressure (`src/rom/warp.rs`).
    #[arg(long, requires = "high_fidelity")]
    pub pressure_warp: bool,
    /// Output model file (required: the shipped `models/actuator.json` is what every other
    /// command reads by default). Written atomically; an existing file is an error without
    /// --force.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing --out file.
    #[arg(long)]
    pub force: bool,
    /// Cross-validation folds (by case).
    #[arg(long, default_value_t = 5)]
    pub folds: usize,
    /// Seed of the fold assignment and the optimiser starts.
    #[arg(long, default_value_t = 2024)]
    pub seed: u64,
    /// Repeated k-fold: this many fold assignments (seeds `seed`, `seed + 1`, …), their
    /// held-out errors pooled; steadier figures when a few cases dominate the error, at
    /// `repeats × folds` fits.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=20))]
    pub repeats: u16,
    /// POD energy tolerance (discarded fraction of the energy).
    #[arg(long, default_value_t = 1e-7)]
    pub pod_tol: f64,
    /// Largest number of POD modes of the field block (all 22 quantities).
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u16).range(1..))]
    pub max_field_modes: u16,
    /// Largest number of POD modes of each direct block (one scalar's ramp); a value at or
    /// above the number of pressure levels keeps the whole ramp (no truncation).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u16).range(1..))]
    pub max_direct_modes: u16,
    /// One GP kernel (length scales, nugget) per POD block instead of one shared by all
    /// blocks: each output gets its own smoothness; a prediction then computes one kernel
    /// vector per block it needs.
    #[arg(long)]
    pub kernel_per_block: bool,
    /// Restrict the choice to one regressor of the registry, by name.
    #[arg(long, value_name = "REGRESSOR", value_parser = registered_regressor())]
    pub only: Option<RegressorKind>,
    /// Keep the faster polynomial unless the GP's held-out RMSE is smaller by more than this
    /// relative margin (e.g. 0.2); 0 chooses by accuracy alone.
    #[arg(long, default_value_t = 0.0)]
    pub prefer_poly_within: f64,
    /// Also use truncated ramps (≥ half the grid converged) for the regression, through gappy POD.
    #[arg(long)]
    pub fill_truncated: bool,
    /// N as an ordinal input: the model predicts every integer N between the smallest and the
    /// largest trained one, not only the trained ones (check it with --hold-out-n).
    #[arg(long)]
    pub ordinal_n: bool,
    /// With --ordinal-n: first train without the cases of these numbers of bellows (each
    /// strictly between the trained ends), predict them and store the errors in the model's
    /// validation (tip, angle, force), then train the model on every case. One training more.
    #[arg(long, value_delimiter = ',', requires = "ordinal_n")]
    pub hold_out_n: Vec<u32>,
    /// Learning curve: also train on the first K cases (by case id) for each K of this
    /// comma-separated list and print the held-out RMSE of every output per K (the model
    /// saved is the one trained on all cases).
    #[arg(long, value_delimiter = ',')]
    pub learning_curve: Vec<usize>,
    /// Write every held-out prediction of the scalar outputs (case, fold, pressure, output,
    /// FE value, prediction, std) to this CSV.
    #[arg(long)]
    pub held_out: Option<PathBuf>,
    /// Draw the held-out errors (surrogate − FE) against the FE values into this SVG (one
    /// panel per scalar output, coloured by N, pooled RMSE in the title).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `surrogate predict`.
#[derive(Debug, Args)]
pub struct PredictArgs {
    /// Model file (default: the shipped models/actuator.json of the repository the program
    /// was built from, from any working directory).
    #[arg(long, default_value_os_t = crate::files::repository_file(crate::files::DEFAULT_MODEL))]
    pub model: PathBuf,
    /// Number of bellows.
    #[arg(long, required_unless_present_any = ["csv", "validation"])]
    pub n: Option<u32>,
    /// Wall thickness, mm.
    #[arg(long, required_unless_present_any = ["csv", "validation"], allow_negative_numbers = true)]
    pub t: Option<f64>,
    /// Gauge pressure, bar.
    #[arg(long, required_unless_present_any = ["csv", "validation", "bench_fe"], allow_negative_numbers = true)]
    pub pressure: Option<f64>,
    /// Material: a name (ogden_002, ogden_005), `mu1,alpha1,mu2,alpha2` or a calibration
    /// report `DIR/report.json` (its calibrated set).
    #[arg(long, required_unless_present_any = ["csv", "validation"], allow_hyphen_values = true, value_parser = material_spec)]
    pub material: Option<String>,
    /// Also output the surrogate's predictive standard deviations: its error against the FE
    /// model it was trained on, not the model's error against real actuators (that is the
    /// model-form error, printed whenever the model file carries one).
    #[arg(long)]
    pub std: bool,
    /// Batch mode: query CSV.
    #[arg(long, conflicts_with_all = ["n", "t", "pressure", "material"], requires = "out")]
    pub csv: Option<PathBuf>,
    /// Batch mode: output CSV (`-`: stdout), written atomically.
    #[arg(long, requires = "csv")]
    pub out: Option<PathBuf>,
    /// Predict inputs outside the training domain too (an error by default): the pressure is
    /// then clamped to the grid's ends, the other inputs extrapolated, and the JSON
    /// (`in_domain`, `outside_domain`) or the CSV (`in_domain`, `outside_domain` columns) says
    /// which inputs were outside and whether they were clamped.
    #[arg(long)]
    pub allow_extrapolation: bool,
    /// Inputs outside the training domain are an error (the default; kept for scripts).
    #[arg(long, hide = true, conflicts_with = "allow_extrapolation")]
    pub strict: bool,
    /// Print the model's stored validation table to stdout (and nothing else without a query).
    #[arg(long)]
    pub validation: bool,
    /// Speed-up benchmark on this mesh level (coarse, standard, fine): one full FE ramp of the
    /// query's design and material (bending, contact, gravity, on the model's pressure grid),
    /// then the surrogate at the same pressures, in the same run; JSON to --bench-out.
    #[arg(long, value_name = "MESH", requires_all = ["n", "t", "material", "bench_out"], conflicts_with = "csv")]
    pub bench_fe: Option<String>,
    /// Where the speed-up benchmark writes its JSON summary.
    #[arg(long, requires = "bench_fe")]
    pub bench_out: Option<PathBuf>,
}

/// Export precision.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PrecisionArg {
    /// Single precision.
    F32,
    /// Double precision.
    F64,
}

/// `surrogate export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Model file.
    #[arg(long)]
    pub model: PathBuf,
    /// Output Rust source (const tables + extern "C" entry point), a module of a crate that
    /// depends on the `surrogate-predict` crate (`predict/`).
    #[arg(long)]
    pub rust: PathBuf,
    /// Output C header (default: the Rust path with extension .h).
    #[arg(long)]
    pub header: Option<PathBuf>,
    /// Precision of the tables.
    #[arg(long, value_enum, default_value = "f32")]
    pub precision: PrecisionArg,
    /// Export one design and material as its reconstructed pressure ramp (needs --n, --t and
    /// --material): a table of 22 × n_p values and `surrogate_ramp_f32/f64(p_bar, out)`, for a
    /// controller whose actuator and calibrated material are fixed.
    #[arg(long)]
    pub ramp: bool,
    /// Number of bellows of the exported ramp.
    #[arg(long = "n")]
    pub n: Option<u32>,
    /// Wall thickness of the exported ramp, mm.
    #[arg(long = "t", allow_negative_numbers = true)]
    pub t: Option<f64>,
    /// Material of the exported ramp: a name (ogden_002, ogden_005), `mu1,alpha1,mu2,alpha2`
    /// or a calibration report `DIR/report.json` (its calibrated set).
    #[arg(long, allow_hyphen_values = true, value_parser = material_spec)]
    pub material: Option<String>,
    /// Export a ramp whose design or material lies outside the training domain (an error by
    /// default); the header then says which inputs are outside (`SURROGATE_RAMP_IN_DOMAIN 0`).
    #[arg(long, requires = "ramp")]
    pub allow_extrapolation: bool,
}

/// Measurement mode.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum ModeArg {
    /// Free bending.
    Bending,
    /// Blocked force.
    Force,
}

/// `surrogate simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Number of bellows N (7..=15).
    #[arg(long = "n", default_value_t = 11)]
    pub n: usize,
    /// Wall thickness T in mm (1.2..=2.8).
    #[arg(long = "t", default_value_t = 2.0)]
    pub t: f64,
    /// The dimensions the reference study leaves unstated (gap, base, duct, side walls, free
    /// length): as_modelled, or a geometry preset file such as `surrogate identify` writes
    /// (geometry.json).
    #[arg(long, default_value = "as_modelled")]
    pub geometry: String,
    /// Gauge pressures in bar, increasing: a comma list (0,1,2,3) or max:step (3:0.5 = 0, 0.5,
    /// …, 3).
    #[arg(long, default_value = "0,1,2,3", allow_hyphen_values = true)]
    pub pressures: String,
    /// Material: ogden_002 | ogden_005 | mooney_rivlin_5 | mu1,alpha1,mu2,alpha2 | neo_hookean:MU
    /// | DIR/report.json (the calibrated set of a `calibrate` report, at full precision).
    #[arg(long, default_value = "ogden_002", allow_hyphen_values = true, value_parser = material_spec)]
    pub material: String,
    /// Bulk modulus as a multiple of the initial shear modulus.
    #[arg(long, default_value_t = surrogate::fe::material::DEFAULT_BULK_RATIO)]
    pub bulk_ratio: f64,
    /// Switch self-weight off.
    #[arg(long)]
    pub no_gravity: bool,
    /// Mesh level: coarse | standard | fine (with --bench: a comma list or "all").
    #[arg(long, default_value = "standard")]
    pub mesh: String,
    /// Element size override in mm.
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Minimum number of elements through a wall (overrides the level's).
    #[arg(long)]
    pub wall_elements: Option<usize>,
    /// Write the result as JSON here (stdout if absent or `-`), atomically.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the deformed mesh of every step as .vtu files into this directory.
    #[arg(long)]
    pub vtk: Option<PathBuf>,
    /// What to measure: bending (markers, tip, angle) or force (blocked force on a plate 5 mm
    /// below the hanging tip; adds `force_n` per step).
    #[arg(long, value_enum, default_value = "bending")]
    pub mode: ModeArg,
    /// Switch bellow-to-bellow and clamp contact off (walls may then interpenetrate).
    #[arg(long)]
    pub no_contact: bool,
    /// Contact penalty stiffness (MPa per mm of penetration).
    #[arg(long, default_value_t = 20.0)]
    pub contact_stiffness: f64,
    /// Contact smoothing width (mm): contact pressure starts at this gap.
    #[arg(long, default_value_t = 0.05)]
    pub contact_smoothing: f64,
    /// Bellow walls in contact: gap to the closest point of the facing wall (frictionless
    /// under sliding) instead of between points of equal reference position.
    #[arg(long)]
    pub closest_point_contact: bool,
    /// Physics beyond the nominal model, NAME=VALUE (repeatable), e.g. --effect wall_bias=-0.1
    /// --effect clamp_compliance=0.2; `surrogate effects` lists the names, units and ranges.
    #[arg(long, value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub effect: Vec<String>,
    /// Also differentiate every output of every step with respect to these parameters
    /// (`all`, or a comma-separated list of mu1, alpha1, mu2, alpha2 and effect names), by
    /// direct differentiation of each converged state (see `docs/MODEL.md`).
    #[arg(long, value_name = "NAME,...|all")]
    pub sensitivities: Option<String>,
    /// Where the sensitivities go (JSON); default: beside --out as <stem>_sensitivities.json,
    /// or sensitivities.json.
    #[arg(long, requires = "sensitivities")]
    pub sensitivities_out: Option<PathBuf>,
    /// Largest pressure increment of one load substep (bar).
    #[arg(long, default_value_t = 0.5)]
    pub max_increment: f64,
    /// Line search on the directional residual in every Newton iteration.
    #[arg(long)]
    pub line_search: bool,
    /// No predictor: start each increment from the last converged state instead of the
    /// extrapolated path (for comparisons; the predictor is on by default).
    #[arg(long)]
    pub no_predictor: bool,
    /// Full Newton in the re-solves after each augmented-Lagrangian update. By default they
    /// reuse the last factorised tangent while the residual falls at least fourfold per
    /// iteration (modified Newton: same tolerance, 13 % less time on the standard mesh).
    #[arg(long)]
    pub no_reuse_factor: bool,
    /// Newton tolerance on the normalised residual.
    #[arg(long, default_value_t = surrogate::fe::solver::SolverSettings::default().rtol)]
    pub rtol: f64,
    /// Grow the next increment after a substep that took at most this many iterations.
    #[arg(long, default_value_t = surrogate::fe::solver::SolverSettings::default().grow_below_iterations)]
    pub grow_below: usize,
    /// Augmented-Lagrangian contact: up to this many Uzawa updates of the contact gap shifts
    /// per output step, so that walls in contact touch (gap within 1e-3 mm) whatever the
    /// penalty stiffness (0: plain penalty).
    #[arg(long, default_value_t = surrogate::fe::solver::SolverSettings::default().augmented_updates)]
    pub augmented: usize,
    /// Benchmark mode: run the full ramp 0→3 bar (0.5 bar steps) on each mesh level and write a
    /// JSON summary (to --out).
    #[arg(long)]
    pub bench: bool,
    /// Nonlinear solver: newton (residual Newton, augmented-Lagrangian contact: the reference)
    /// or minimise (minimisation of the total potential with log-barrier contact).
    #[arg(long, value_enum, default_value = "newton")]
    pub solver: SolverArg,
    /// Activation distance of the barrier contact of --solver minimise (mm).
    #[arg(long, default_value_t = surrogate::fe::solver::MinimiseSettings::default().dhat_mm)]
    pub barrier_dhat: f64,
    /// Pressure scale of the barrier contact of --solver minimise (MPa).
    #[arg(long, default_value_t = surrogate::fe::solver::MinimiseSettings::default().barrier_pressure)]
    pub barrier_pressure: f64,
}

/// `--solver`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SolverArg {
    /// Residual Newton with augmented-Lagrangian contact (the reference).
    Newton,
    /// Minimisation of the total potential with barrier contact.
    Minimise,
}

/// `surrogate validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Geometry preset: as_modelled or a preset file (see `simulate --help`).
    #[arg(long, default_value = "as_modelled")]
    pub geometry: String,
    /// Material (see `simulate --help`).
    #[arg(long, default_value = "ogden_002", allow_hyphen_values = true, value_parser = material_spec)]
    pub material: String,
    /// Mesh level.
    #[arg(long, default_value = "standard")]
    pub mesh: String,
    /// Element size override (mm).
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Contact penalty stiffness (MPa/mm).
    #[arg(long, default_value_t = 20.0)]
    pub contact_stiffness: f64,
    /// Contact smoothing width (mm).
    #[arg(long, default_value_t = 0.05)]
    pub contact_smoothing: f64,
    /// Bellow walls in contact: gap to the closest point of the facing wall.
    #[arg(long)]
    pub closest_point_contact: bool,
    /// Physics beyond the nominal model for every ramp, NAME=VALUE (repeatable), e.g.
    /// --effect wall_bias=-0.1; `surrogate effects` lists the names, units and ranges. Cached
    /// ramps are keyed by the effects too.
    #[arg(long, value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub effect: Vec<String>,
    /// Also differentiate every ramp with respect to these parameters (`all`, or a list of
    /// mu1, alpha1, mu2, alpha2 and effect names; see `simulate --sensitivities`) and write
    /// them to <out stem>_sensitivities.json (what `diagnose` reads).
    #[arg(long, value_name = "NAME,...|all")]
    pub sensitivities: Option<String>,
    /// Output CSV (one row per configuration); an SVG plot is written beside it.
    #[arg(long)]
    pub out: PathBuf,
    /// Directory caching each finished FE ramp (default: `<out stem>_ramps/` beside the CSV);
    /// a later run with the same settings resumes from it.
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Only redraw the SVG from the existing --out CSV (no FE run).
    #[arg(long)]
    pub plot_only: bool,
}

/// `surrogate demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Number of bellows of the design re-verified live by the FE model.
    #[arg(long = "n", default_value_t = 11)]
    pub n: usize,
    /// Wall thickness (mm) of the design re-verified live.
    #[arg(long = "t", default_value_t = 2.0)]
    pub t: f64,
    /// Material of the live FE run: `calibrated` (the set the calibration finds) or a material
    /// spec (see `simulate --help`).
    #[arg(long, default_value = "calibrated", value_parser = material_spec)]
    pub material: String,
    /// Mesh level of the live FE run.
    #[arg(long, default_value = "coarse")]
    pub mesh: String,
    /// Where the plots, the calibration report and the JSON go.
    #[arg(long, default_value = "demo_output")]
    pub out_dir: PathBuf,
    /// Surrogate the calibration runs through (standard-mesh values) [default:
    /// models/actuator.json of the repository the program was built from, from any working
    /// directory].
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Surrogate compared with the live FE run (its mesh's values; skipped with a note if it
    /// cannot be used) [default: models/actuator_coarse.json of the repository].
    #[arg(long)]
    pub live_model: Option<PathBuf>,
    /// Committed FE ramps of the calibrated set on the standard mesh [default:
    /// data/demo/fe_standard_ramps/ of the repository].
    #[arg(long)]
    pub fe_cache: Option<PathBuf>,
}

/// A regressor of the built-in registry by name (`--only`): the registry's names are the
/// possible values, listed in the help and in the error for any other.
fn registered_regressor() -> impl TypedValueParser<Value = RegressorKind> {
    PossibleValuesParser::new(Registry::builtin().names()).map(|name| RegressorKind::named(&name))
}
