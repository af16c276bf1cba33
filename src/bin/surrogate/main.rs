//! The `surrogate` command-line tool: parse → validated configuration → one library call per
//! subcommand.
mod args;
mod calibrate;
mod calibrate_plots;
mod demo;
mod export;
mod predict;
mod simulate;
mod snapshots;
mod speedup;
mod train;
mod validate;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Demo(a) => demo::run(a),
        args::Command::Simulate(a) => simulate::run(a),
        args::Command::Train(a) => train::run(a),
        args::Command::Predict(a) => predict::run(a),
        args::Command::Export(a) => export::run(a),
        args::Command::Validate(a) => validate::run(a),
        args::Command::Calibrate(a) => calibrate::run(*a),
        args::Command::Snapshots(a) => snapshots::run(*a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
