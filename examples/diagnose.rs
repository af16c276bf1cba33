//! Locate where the calibrated model misses the shipped experiments: calibrate one Ogden set
//! through the shipped surrogate, then the residual's structure over N, T and P in words.
//!
//! ```sh
//! cargo run --release --example diagnose
//! ```
use std::path::Path;

use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings};
use surrogate::diagnose::cells::Family;
use surrogate::diagnose::structure::Term;
use surrogate::diagnose::{locate, LocateSettings};
use surrogate::rom::Surrogate;

fn main() -> surrogate::Result<()> {
    let model = Surrogate::load(Path::new("models/actuator.json"))?;
    let recordings = Recordings::shipped()?;
    // the study's objective (tip alone): the force is then predicted, not fitted
    let cal = calibrate(
        &model,
        &recordings,
        &CalibrationSettings::default(),
        &|_| {},
    )?;
    let loc = locate(&cal, &model, &recordings, &LocateSettings::default())?;

    println!("findings:");
    for f in &loc.findings {
        println!("- {}", f.text);
    }
    // the numbers behind them: the tip Uz residual's trend over the wall thickness
    if let Some(t) = loc.structure(Family::TipUz).and_then(|s| s.term(Term::T)) {
        println!(
            "tip Uz: {:+.2} ± {:.2} σ per mm of T (t = {:.1}, significant: {})",
            t.coefficient, t.std_error, t.t, t.significant
        );
    }
    println!("the largest cells (share of χ²):");
    let mut cells = loc.cells.clone();
    cells.sort_by(|a, b| b.chi2_share.total_cmp(&a.chi2_share));
    for c in cells.iter().take(5) {
        println!(
            "  N={} T={} P={} {}: z = {:+.2} ({:.1} %)",
            c.n_bellows,
            c.wall_thickness_mm,
            c.pressure_bar,
            c.family.label(),
            c.standardised,
            100.0 * c.chi2_share
        );
    }
    println!("what the recordings lack:");
    for m in &loc.missing {
        println!("- {}", m.what);
    }
    Ok(())
}
