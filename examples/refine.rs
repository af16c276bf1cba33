//! Adaptive refinement of a calibration: the FE model at the calibrated set, added to the
//! surrogate's training set where the two disagree, retrained and refitted, round by round.
//!
//! On the coarse-mesh surrogate and the shipped experiments, reading the committed rounds of
//! `fe_reference/calibration/refine_coarse/refine/` (a round that is not there is run: about
//! 20 minutes of FE on 2 cores). Give another directory to start afresh:
//!
//! ```sh
//! cargo run --release --example refine
//! cargo run --release --example refine -- /tmp/my_refinement
//! ```
//!
//! The default settings stop when surrogate and FE agree, when the refit is the set already
//! verified, or when the refit moves no recorded number by more than its σ
//! (`RefineSettings::data_tolerance`, the answer to a refit that walks along a direction the
//! recordings do not determine); the summary says which.
use std::path::{Path, PathBuf};

use surrogate::calibrate::refine::{refine, RefineEvent, RefineSettings, TrainingSet};
use surrogate::calibrate::Recordings;
use surrogate::rom::Surrogate;
use surrogate::snapshots::fe_runner::fe_runner;

fn main() -> surrogate::Result<()> {
    let dir = std::env::args().nth(1).map_or_else(
        || PathBuf::from("fe_reference/calibration/refine_coarse/refine"),
        PathBuf::from,
    );
    let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json"))?;
    // the snapshots the model was trained on, and their plan (the FE settings of every round)
    let training = TrainingSet::of_model(&model, Path::new("."))?;
    let r = refine(
        &model,
        &training,
        &Recordings::shipped()?,
        &RefineSettings::default(),
        &fe_runner,
        &dir,
        &|ev| match ev {
            RefineEvent::Stage(s) => eprintln!("{s}"),
            RefineEvent::Fe { round, progress } => eprintln!(
                "round {round}: {} of {} FE cases",
                progress.done, progress.total
            ),
            RefineEvent::Round(r) => eprintln!(
                "round {}: {} configurations where surrogate and FE disagree",
                r.round, r.verification.disagreements
            ),
        },
    )?;
    print!("{}", r.summary_markdown());
    Ok(())
}
