//! Calibrate the Ogden parameters to the shipped experiments through the shipped surrogate,
//! and print what the data determine.
//!
//! ```sh
//! cargo run --release --example calibrate          # tip, angle and force
//! cargo run --release --example calibrate -- tip   # the tip alone
//! ```
use std::path::Path;

use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings, Weights};
use surrogate::rom::Surrogate;

fn main() -> surrogate::Result<()> {
    let model = Surrogate::load(Path::new("models/actuator.json"))?;
    let recordings = Recordings::shipped()?;
    let settings = CalibrationSettings {
        // tip (the study's BE), bending angle and blocked force, each residual in units of its
        // noise (the identification's objective); another as the first argument, e.g. `tip`
        weights: Weights::parse(&std::env::args().nth(1).unwrap_or("tip,angle,force".into()))?,
        ..CalibrationSettings::default()
    };
    let cal = calibrate(&model, &recordings, &settings, &|stage| {
        eprintln!("{stage}")
    })?;
    let b = &cal.best;
    println!(
        "best set: mu1 {:.4} MPa, alpha1 {:.3}, mu2 {:.3} MPa, alpha2 {:.4} (mu0 {:.3} MPa)",
        b.mu1_mpa,
        b.alpha1,
        b.mu2_mpa,
        b.alpha2,
        b.mu0_mpa()
    );
    println!(
        "chi2 {:.1} (literature {:.1}); mean BE {:.2} mm (literature {:.2} mm); mean force error {:+.3} N (literature {:+.3} N)",
        cal.chi2,
        cal.chi2_literature,
        cal.calibrated.mean_be_mm,
        cal.literature_summary.mean_be_mm,
        cal.calibrated.mean_force_error_n,
        cal.literature_summary.mean_force_error_n
    );
    println!(
        "{} starts reached {} distinct minima",
        cal.starts.len(),
        cal.minima
    );
    for bound in &cal.active_bounds {
        println!("active bound: {bound}");
    }
    for p in &cal.identifiability.profiles {
        println!(
            "{:<12} {:>9.4}  95% [{:.4}, {:.4}]  {}",
            p.name,
            p.optimum,
            p.interval[0],
            p.interval[1],
            p.determinacy.describe()
        );
    }
    for f in &cal.flags {
        println!(
            "data check: {} ({}): {}",
            f.config.label(),
            f.source,
            f.message
        );
    }
    println!("calibration took {:.2} s", cal.wall_time_s);
    Ok(())
}
