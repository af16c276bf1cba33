//! The models the design tests search: the shipped one, and a small synthetic one trained
//! over N = 7 … 15.
use std::path::Path;
use std::sync::OnceLock;

use surrogate::case::OgdenSet;
use surrogate::design::{search, DesignBounds, DesignReport, DesignSearch, Output, Target};
use surrogate::rom::data::SnapshotSet;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::{train, Surrogate, TrainConfig};

/// Ogden 002, inside the synthetic model's domain.
pub const OGDEN_002: OgdenSet = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);

/// The set calibrated on the shipped experiments (`fe_reference/calibration/surrogate/`).
pub const CALIBRATED: OgdenSet = OgdenSet::from_array([
    0.03821164173136228,
    5.99612765572898,
    -5.194862363697796,
    -1.996454844367204,
]);

/// The shipped model.
pub fn shipped() -> &'static Surrogate {
    static MODEL: OnceLock<Surrogate> = OnceLock::new();
    MODEL.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/as_modelled/actuator.json");
        Surrogate::load(&path).unwrap()
    })
}

/// A synthetic model over N = 7 … 15 (5 cases per N, 3 folds).
pub fn synthetic() -> &'static Surrogate {
    static MODEL: OnceLock<Surrogate> = OnceLock::new();
    MODEL.get_or_init(|| {
        let cfg = SyntheticConfig {
            n_cases: 45,
            n_values: (7..=15).collect(),
            ..Default::default()
        };
        let mut csv = Vec::new();
        write_csv(&cfg, &mut csv).unwrap();
        let cases = SnapshotSet::from_reader(csv.as_slice(), "synthetic")
            .unwrap()
            .into_cases()
            .unwrap();
        let tc = TrainConfig {
            folds: 3,
            ..Default::default()
        };
        train(&cases, "synthetic", 0, &tc, &|_, _| {})
            .unwrap()
            .surrogate
    })
}

/// Angle (1°) and force (0.05 N) targets at 2 bar.
pub fn angle_and_force(angle: f64, force: f64) -> [Target; 2] {
    [
        Target::new(Output::AngleDeg, 2.0, angle, 1.0),
        Target::new(Output::ForceN, 2.0, force, 0.05),
    ]
}

/// The search over the model's whole domain with the default settings.
pub fn search_all(model: &Surrogate, material: OgdenSet, targets: &[Target]) -> DesignReport {
    let bounds = DesignBounds::of_model(model);
    search(model, material, targets, &bounds, &DesignSearch::default()).unwrap()
}
