//! Command-line arguments (clap derive). Every subcommand has its own argument struct.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Fast, verified models of 3D-printed soft pneumatic bellow actuators.
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
    /// Run the full FE model of one design over a pressure ramp.
    Simulate(SimulateArgs),
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
    /// Comma-separated gauge pressures in bar, increasing (e.g. 0,1,2,3).
    #[arg(long, default_value = "0,1,2,3")]
    pub pressures: String,
    /// Material: ogden_002 | ogden_005 | mooney_rivlin_5 | mu1,alpha1,mu2,alpha2 | neo_hookean:MU.
    #[arg(long, default_value = "ogden_002")]
    pub material: String,
    /// Bulk modulus as a multiple of the initial shear modulus.
    #[arg(long, default_value_t = 1000.0)]
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
    /// Write the result as JSON here (stdout if absent).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the deformed mesh of every step as .vtu files into this directory.
    #[arg(long)]
    pub vtk: Option<PathBuf>,
    /// Benchmark mode: run the full ramp 0→3 bar (0.5 bar steps) on each mesh level and write a
    /// JSON summary (to --out).
    #[arg(long)]
    pub bench: bool,
}
