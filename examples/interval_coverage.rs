//! How often the calibrator's interval of μ0 covers the true μ0: the recovery of
//! `tests/calibrate/calibrate.rs` (the coarse-mesh FE at a known material, the 9 designs at 1,
//! 2 and 3 bar, noise at the experiments' standard deviations, fitted through
//! `models/as_modelled/actuator_coarse.json`) over noise seeds 1 … 30 at the 95 % level, with the
//! projection of the joint region and with the pointwise profile interval
//! (`surrogate::calibrate::coverage`). Writes every seed and the counts to
//! `fe_reference/calibration/interval_coverage.json` (or the file given).
//!
//! ```sh
//! cargo run --release --example interval_coverage [-- OUT.json]
//! ```
use std::path::{Path, PathBuf};

use surrogate::calibrate::coverage::{interval_coverage, CoverageSettings};
use surrogate::calibrate::synthetic::TrueOutputs;
use surrogate::calibrate::Recordings;
use surrogate::case::{MaterialCoords, OgdenSet};
use surrogate::rom::Surrogate;

const MODEL: &str = "models/as_modelled/actuator_coarse.json";
const CASES: &str = "fe_reference/calibration/synthetic_coarse/cases/cases";
const COMMAND: &str = "cargo run --release --example interval_coverage";

/// The material of the synthetic FE runs (`fe_reference/calibration/synthetic_coarse/plan.json`).
const TRUTH: MaterialCoords = MaterialCoords {
    mu0_mpa: 4.5,
    share: 0.4,
    alpha1: 2.5,
    alpha2: -1.2,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args().nth(1).map_or_else(
        || root.join("fe_reference/calibration/interval_coverage.json"),
        PathBuf::from,
    );
    let model = Surrogate::load(&root.join(MODEL))?;
    let truth = TrueOutputs::read_cases(&root.join(CASES), &[1.0, 2.0, 3.0])?;
    let true_set = OgdenSet::from_coords(TRUTH)?;
    let settings = CoverageSettings::default();
    eprintln!(
        "{} seeds, {} configurations, true set {:?}",
        settings.seeds.len(),
        truth.len(),
        true_set
    );
    let study = interval_coverage(
        &model,
        &truth,
        TRUTH.mu0_mpa,
        &Recordings::shipped()?,
        &settings,
        &|s| {
            eprintln!(
                "seed {:2}: mu0 {:.3} MPa, projection [{:.3}, {:.3}] {}, pointwise [{:.3}, {:.3}] {}",
                s.seed,
                s.mu0_mpa,
                s.projection[0],
                s.projection[1],
                if s.projection_covers { "covers" } else { "misses" },
                s.pointwise[0],
                s.pointwise[1],
                if s.pointwise_covers { "covers" } else { "misses" },
            )
        },
    )?;
    let file = serde_json::json!({
        "command": COMMAND,
        "model": MODEL,
        "model_checksum": model.checksum()?,
        "cases": CASES,
        "true_material": true_set,
        "coverage": study,
    });
    std::fs::write(&out, serde_json::to_string_pretty(&file)? + "\n")?;
    println!(
        "mu0 at {} %: the projection covers the truth in {} of {} seeds, the pointwise interval \
         in {} of {}; wrote {}",
        100.0 * study.level,
        study.projection_covered,
        study.seeds.len(),
        study.pointwise_covered,
        study.seeds.len(),
        out.display()
    );
    Ok(())
}
