//! The `surrogate` command-line tool: parse → validated configuration → one library call per
//! subcommand.
mod approximation_error;
mod args;
mod calibrate;
mod calibrate_extend;
mod calibrate_plots;
mod campaign;
mod demo;
mod design;
mod diagnose;
mod diagnose_plots;
mod effects;
mod export;
mod figure;
mod files;
mod identify;
mod maps;
mod maps_plots;
mod model_form;
mod predict;
mod simulate;
mod snapshots;
mod speedup;
mod train;
mod twin;
mod twin_study;
mod validate;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Demo(a) => demo::run(a),
        args::Command::Simulate(a) => simulate::run(a),
        args::Command::Campaign(a) => campaign::run(a),
        args::Command::Train(a) => train::run(a),
        args::Command::Predict(a) => predict::run(a),
        args::Command::Export(a) => export::run(a),
        args::Command::ModelForm(a) => model_form::run(a),
        args::Command::Validate(a) => validate::run(a),
        args::Command::Calibrate(a) if a.extend_box > 0 => calibrate_extend::run(*a),
        args::Command::Calibrate(a) => calibrate::run(*a),
        args::Command::Snapshots(a) => snapshots::run(*a),
        args::Command::Effects(a) => effects::run(a),
        args::Command::Twin(a) => twin::run(a),
        args::Command::Diagnose(a) => diagnose::run(a),
        args::Command::TwinStudy(a) => twin_study::run(a),
        args::Command::ApproximationError(a) => approximation_error::run(a),
        args::Command::Identify(a) => identify::run(a),
        args::Command::Design(a) => design::run(a),
        args::Command::Maps(a) => maps::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // a reader that closed the pipe (`surrogate predict … | head`) is not an error
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", flatten(&e));
            ExitCode::FAILURE
        }
    }
}

/// Whether the error (or a cause) is a write to a closed pipe.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// An error and its causes as one line, `outer: inner: …`, each message once: a cause whose
/// text its parent already shows (a library error that prints its source) is not repeated.
pub fn flatten(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if text.is_empty() || out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::flatten;

    #[test]
    fn flatten_drops_causes_already_shown() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let lib = surrogate::rom::RomError::Io {
            path: "m.json".into(),
            source: io,
        };
        let e = anyhow::Error::from(lib).context("loading the model");
        assert_eq!(flatten(&e), "loading the model: m.json: no such file");
    }
}
