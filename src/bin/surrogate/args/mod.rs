//! Command-line arguments (clap derive), one struct per subcommand, in one file per group:
//! the FE model (`fe`), the surrogate (`rom`) and the diagnoser (`diagnose`). The commands
//! whose arguments live beside their code (`campaign`, `model-form`, `calibrate`,
//! `snapshots`, `design`, `maps`) name them here.
mod diagnose;
mod fe;
mod rom;

use clap::{Args, Parser, Subcommand};

pub use diagnose::{ApproximationErrorArgs, DiagnoseArgs, TwinArgs, TwinStudyArgs};
pub use fe::{DemoArgs, EffectsArgs, IdentifyArgs, ModeArg, SimulateArgs, SolverArg, ValidateArgs};
pub use rom::{ExportArgs, PrecisionArg, PredictArgs, TrainArgs};

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

/// A finer or coarser discretisation than the `--mesh` level's, shared by the commands that
/// run FE on a mesh of their own (`simulate`, `twin`, `approximation-error`).
#[derive(Debug, Args)]
pub struct MeshRefinementArgs {
    /// Element size override in mm (default: the `--mesh` level's).
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Minimum number of elements through a wall (default: the `--mesh` level's).
    #[arg(long)]
    pub wall_elements: Option<usize>,
}

impl MeshRefinementArgs {
    /// The mesh of `--mesh level` with these overrides, validated; a bad value names its flag.
    pub fn options(&self, level: &str) -> anyhow::Result<surrogate::fe::mesh::MeshOptions> {
        crate::files::mesh_options(level, self.element_size, self.wall_elements)
    }
}
