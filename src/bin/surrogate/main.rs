//! The `surrogate` command-line tool: parse → validated configuration → one library call.
use std::process::ExitCode;

use clap::Parser;

mod args;
mod simulate;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Simulate(a) => simulate::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
