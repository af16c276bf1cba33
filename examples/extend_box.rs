//! Box extension of a calibration: where the optimum presses a bound of the surrogate's
//! training box, the bound moves out (up to its physical limit), FE cases fill the slab beyond,
//! the surrogate is retrained and the material refitted, round by round.
//!
//! On the coarse-mesh surrogate and the shipped experiments (the optimum sits on bounds of
//! term1_share, α1 and α2): each round runs 36 coarse FE cases, about 10 minutes of FE on 2 cores;
//! the cases are cached per case, so a rerun resumes. Give the directory as the argument:
//!
//! ```sh
//! cargo run --release --example extend_box -- /tmp/extend_coarse
//! ```
//!
//! It stops when the optimum lies inside the box, when every bound it presses is at its
//! physical limit, or after `max_rounds`; the summary says which, and names the limits.
use std::path::{Path, PathBuf};

use surrogate::calibrate::extend::{extend_box, ExtendEvent, ExtendSettings};
use surrogate::calibrate::refine::TrainingSet;
use surrogate::calibrate::summary::summary_markdown_extended;
use surrogate::calibrate::Recordings;
use surrogate::rom::Surrogate;
use surrogate::snapshots::fe_runner::fe_runner;

fn main() -> surrogate::Result<()> {
    let dir = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("calibration/extend"), PathBuf::from);
    let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json"))?;
    // the snapshots the model was trained on, and their plan (the FE settings of every case)
    let training = TrainingSet::of_model(&model, Path::new("."))?;
    let settings = ExtendSettings {
        max_rounds: 2,
        ..ExtendSettings::default()
    };
    let e = extend_box(
        &model,
        &training,
        &Recordings::shipped()?,
        &settings,
        &fe_runner,
        &dir,
        &|ev| match ev {
            ExtendEvent::Stage(s) => eprintln!("{s}"),
            ExtendEvent::Fe { round, progress } => eprintln!(
                "round {round}: {} of {} FE cases",
                progress.done, progress.total
            ),
            ExtendEvent::Round(r) => eprintln!(
                "round {}: refit χ² {:.1}, {} bounds still active",
                r.round,
                r.refit.chi2,
                r.refit.active_bounds.len()
            ),
        },
    )?;
    if let Some(cal) = &e.last {
        print!("{}", summary_markdown_extended(cal, None, Some(&e)));
    }
    Ok(())
}
