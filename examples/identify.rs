//! Identify the material together with dimensions the reference study does not state (here
//! the gap between the bellows and the side-wall thickness), straight on the FE model: one
//! Levenberg–Marquardt step per FE sweep over the recorded designs, with the FE sensitivities
//! as Jacobian. Each sweep is 18 coarse ramps (about 10 min on 2 cores); the cache makes a
//! rerun resume.
//!
//! ```sh
//! cargo run --release --example identify -- 3     # at most 3 FE sweeps
//! ```
use std::path::PathBuf;

use surrogate::calibrate::joint::{identify, JointPoint, JointSettings, ModelSigma, Unknown};
use surrogate::calibrate::Recordings;
use surrogate::case::OgdenSet;
use surrogate::fe::effects::Effects;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;

fn main() -> surrogate::Result<()> {
    let max_sweeps = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let unknowns = ["mu1", "mu2", "gap", "side_wall"]
        .iter()
        .map(|n| Unknown::from_name(n))
        .collect::<Result<Vec<_>, _>>()?;
    let settings = JointSettings {
        unknowns,
        // Ogden 002 (Reppel and Weinberg), the modelled geometry with 2 mm side walls
        start: JointPoint {
            ogden: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
            geometry: Geometry {
                name: "start".into(),
                side_wall_mm: Some(2.0),
                ..Geometry::as_modelled()
            },
            effects: Effects::default(),
        },
        mesh: MeshOptions::level(MeshLevel::Coarse),
        max_sweeps,
        lambda0: 1e-2,
        max_step: 0.1,
        // 2 mm on a tip coordinate, 0.15 N on the force, added to the recorded scatter
        model_sigma: ModelSigma::default(),
        cache: Some(PathBuf::from("identify_example/fe_ramps")),
        // each sweep's ramps start from the previous sweep's converged states
        warm_start: true,
        exclude: Vec::new(),
        correction: None,
    };
    let report = identify(&settings, &Recordings::shipped()?, |sweep, done, total| {
        eprintln!("sweep {sweep}: {done}/{total} FE ramps")
    })?;
    for e in &report.estimates {
        println!(
            "{:>10} = {:.4} ± {:.4}{}",
            e.name,
            e.value,
            e.std_error,
            if e.on_bound { " (on a bound)" } else { "" }
        );
    }
    println!(
        "mean tip BE {:.2} mm (the study's nine: {:.2} mm), mean |F error| {:.3} N, stopped: {:?}",
        report.mean_be_mm, report.mean_be_paper_nine_mm, report.mean_abs_force_error_n, report.stop
    );
    Ok(())
}
