//! `surrogate model-form`: the model-form error learned from a calibration report, written
//! into the model file beside the model (`surrogate::rom::model_form`).
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use surrogate::rom::model_form_report::from_calibration_report;

/// `surrogate model-form`.
#[derive(Debug, Args)]
pub struct ModelFormArgs {
    /// Model file the calibration was made through.
    #[arg(long)]
    pub model: PathBuf,
    /// The calibration report (`report.json` of `surrogate calibrate --out DIR`) whose
    /// residuals give the model-form error; they are recomputed through --model and checked
    /// against the report's own predictions.
    #[arg(long)]
    pub calibration: PathBuf,
    /// Where the model file with its model-form error is written (atomically); the model
    /// itself and its checksum are unchanged.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing --out (it may be --model itself).
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: ModelFormArgs) -> Result<()> {
    surrogate::rom::model::refuse_existing(&a.out, a.force)
        .context("give --force to replace it")?;
    let mut model = crate::files::load_model(&a.model)?;
    let error = from_calibration_report(&model, &a.calibration)?;
    print!("{}", error.table());
    model.model_form = Some(error);
    model.save(&a.out)?;
    eprintln!(
        "wrote {} (model {}, with its model-form error)",
        a.out.display(),
        model.checksum()?
    );
    Ok(())
}
