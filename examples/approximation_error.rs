//! The diagnosing model's own error as a random quantity: sample it from reference FE runs
//! without any effect (the blind study's committed null twins, 5 mm elements, against the
//! coarse surrogate), then diagnose a twin with a concealed effect with and without it.
//! No FE runs: the reference ramps are committed.
//!
//! ```sh
//! cargo run --release --example approximation_error
//! ```
use std::path::Path;

use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::Recordings;
use surrogate::diagnose::study::{
    diagnose_twin, null_approximation_error, Diagnoser, StudyDirs, StudyPlan,
};
use surrogate::rom::Surrogate;

fn main() -> surrogate::Result<()> {
    let study = Path::new("fe_reference/diagnosis/blind");
    let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json"))?;
    let sens = SweepSensitivities::read(Path::new("data/sensitivities/ogden002_coarse.json"))?;
    let plan = StudyPlan::read(&study.join("plan.json"))?;
    let dirs = StudyDirs::under(study);
    // one sample per null group: the FE's exact outputs against the surrogate at its material
    let error = null_approximation_error(
        &plan,
        &Recordings::shipped()?,
        &dirs,
        &model,
        "models/as_modelled/actuator_coarse.json",
    )?;
    println!(
        "{} samples of the coarse surrogate's error against {}",
        error.samples.len(),
        error.reference
    );
    // a twin with pressure_loss = 0.05 concealed, diagnosed both ways
    let twin = dirs.twins.join("pressure_loss_1_s1");
    for (what, approximation) in [("without", None), ("with", Some(&error))] {
        let by = Diagnoser {
            model: &model,
            sens: &sens,
            mesh_reference: None,
            markers: false,
            approximation,
        };
        let d = diagnose_twin(&twin, &by)?;
        if let Some(n) = d.naming() {
            println!("{what} the approximation error: {}", n.verdict);
        }
    }
    Ok(())
}
