//! The FE model's commands: `demo`, `simulate`, `validate`, `identify`, `effects`.
use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::files::material_spec;

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
    /// length): as_modelled, identified (the joint identification's), or a geometry preset file such as `surrogate identify` writes
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
    /// Overrides of the level's element size and elements through a wall.
    #[command(flatten)]
    pub refinement: super::MeshRefinementArgs,
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

/// Measurement mode.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum ModeArg {
    /// Free bending.
    Bending,
    /// Blocked force.
    Force,
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
    /// Geometry preset: as_modelled, identified or a preset file (see `simulate --help`).
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
    /// Starting geometry: as_modelled, identified or a preset file (.json).
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

/// `surrogate effects`.
#[derive(Debug, Args)]
pub struct EffectsArgs {
    /// Write the library as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}
