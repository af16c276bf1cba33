//! The surrogate's commands: `train`, `predict`, `export`.
use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use surrogate::rom::regression::{Registry, RegressorKind};

use crate::files::material_spec;

/// `surrogate train`.
#[derive(Debug, Args)]
pub struct TrainArgs {
    /// Snapshot CSV (see the snapshot contract). The plan beside it (`<stem>.plan.json`,
    /// written by `snapshots merge`), when present, gives the model's domain its nominal
    /// ranges where the cases cover them (stated in the model file).
    #[arg(long, required_unless_present = "synthetic")]
    pub data: Option<PathBuf>,
    /// Further snapshot CSVs of the same actuator appended to --data (repeatable), such as a
    /// box extension's rounds (`extend/extend_1.csv`, their plans beside them): each plan
    /// must build its cases as the plan beside --data does (geometry, fixed effects), and no
    /// case may repeat. The model's domain is then the box of all the cases.
    #[arg(long, value_name = "FILE", requires = "data")]
    pub add_data: Vec<PathBuf>,
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
    /// Sparse GP: put the weights on M inducing points (training inputs chosen by pivoted
    /// Cholesky, the subset-of-regressors mean of every point), so that a prediction costs M
    /// kernel values instead of one per training case. At least twice the regression inputs;
    /// a fit of no more than M cases is exact.
    #[arg(long, value_name = "M")]
    pub inducing: Option<usize>,
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
    #[arg(long, required_unless_present_any = ["csv", "validation", "check"])]
    pub n: Option<u32>,
    /// Wall thickness, mm.
    #[arg(long, required_unless_present_any = ["csv", "validation", "check"], allow_negative_numbers = true)]
    pub t: Option<f64>,
    /// Gauge pressure, bar.
    #[arg(long, required_unless_present_any = ["csv", "validation", "bench_fe", "check"], allow_negative_numbers = true)]
    pub pressure: Option<f64>,
    /// Material: a name (ogden_002, ogden_005), `mu1,alpha1,mu2,alpha2` or a calibration
    /// report `DIR/report.json` (its calibrated set).
    #[arg(long, required_unless_present_any = ["csv", "validation", "check"], allow_hyphen_values = true, value_parser = material_spec)]
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
    /// Check the model against FE cases it never saw: a snapshot CSV (`snapshots merge`), every
    /// case predicted at its design, material and pressures above 0 and compared with its FE;
    /// a table per case, per N and overall on stdout (mean |error|: tip distance, angle, force).
    #[arg(long, value_name = "SNAPSHOTS_CSV", conflicts_with_all = ["n", "t", "pressure", "material", "csv", "bench_fe"])]
    pub check: Option<PathBuf>,
    /// With --check: also write the report as JSON (atomically).
    #[arg(long, value_name = "OUT", requires = "check")]
    pub check_json: Option<PathBuf>,
    /// Speed-up benchmark on this mesh level (coarse, standard, fine): one full FE ramp of the
    /// query's design and material (bending, contact, gravity, on the model's pressure grid),
    /// then the surrogate at the same pressures, in the same run; JSON to --bench-out.
    #[arg(long, value_name = "MESH", requires_all = ["n", "t", "material", "bench_out"], conflicts_with = "csv")]
    pub bench_fe: Option<String>,
    /// Where the speed-up benchmark writes its JSON summary.
    #[arg(long, requires = "bench_fe")]
    pub bench_out: Option<PathBuf>,
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

/// Export precision.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PrecisionArg {
    /// Single precision.
    F32,
    /// Double precision.
    F64,
}

/// A regressor of the built-in registry by name (`--only`): the registry's names are the
/// possible values, listed in the help and in the error for any other.
fn registered_regressor() -> impl TypedValueParser<Value = RegressorKind> {
    PossibleValuesParser::new(Registry::builtin().names()).map(|name| RegressorKind::named(&name))
}
