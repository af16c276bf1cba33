//! The full design search (`surrogate::design::search`): every N the model predicts, a
//! multi-start Gauss–Newton in T each, angle and blocked-force targets at 2 bar, the pick with
//! its std and model-form error. On the shipped model (`models/actuator.json`: the identified
//! geometry, N = 7 … 15, 522 coarse cases corrected by 36 standard-mesh ones, sparse GP) at the
//! material calibrated through it on the shipped experiments, on the model of the geometry as
//! modelled (`models/as_modelled/actuator.json`, N = 9, 11, 13) at its calibrated material, on
//! the design-space coarse model over N = 7 … 15 (`models/design_space_coarse.json`, 450 coarse
//! cases, sparse GP) at the identified material, and on a synthetic model over N = 7 … 15
//! (300 cases, an exact GP) at Ogden 002.
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use surrogate::case::OgdenSet;
use surrogate::design::{search, DesignBounds, DesignSearch, Output, Target};
use surrogate::rom::batch::material_params;
use surrogate::rom::data::SnapshotSet;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::{train, Surrogate, TrainConfig};

/// The set a committed calibration report holds (`calibration.best`, as `--material
/// DIR/report.json` reads it).
fn calibrated(report: &str) -> OgdenSet {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(report);
    material_params(path.to_str().unwrap()).unwrap()
}
/// The identified set (`data/geometry/identified.json`, `fe_reference/identification/`).
const IDENTIFIED: OgdenSet = OgdenSet::from_array([0.535, 12.0, -0.2776, -0.5]);
const OGDEN_002: OgdenSet = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);

fn synthetic() -> Surrogate {
    let cfg = SyntheticConfig {
        n_cases: 300,
        n_values: (7..=15).collect(),
        ..Default::default()
    };
    let mut buf = Vec::new();
    write_csv(&cfg, &mut buf).unwrap();
    let cases = SnapshotSet::from_reader(buf.as_slice(), "bench")
        .unwrap()
        .into_cases()
        .unwrap();
    let tc = TrainConfig {
        folds: 2,
        ..Default::default()
    };
    train(&cases, "bench", 0, &tc, &|_, _| {})
        .unwrap()
        .surrogate
}

fn bench(c: &mut Criterion) {
    let targets = [
        Target::new(Output::AngleDeg, 2.0, 40.0, 1.0),
        Target::new(Output::ForceN, 2.0, 1.3, 0.05),
    ];
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let shipped = Surrogate::load(&models.join("actuator.json")).unwrap();
    let as_modelled = Surrogate::load(&models.join("as_modelled/actuator.json")).unwrap();
    let design_space = Surrogate::load(&models.join("design_space_coarse.json")).unwrap();
    let mut g = c.benchmark_group("design_search");
    g.measurement_time(Duration::from_secs(8)).sample_size(20);
    for (name, model, material) in [
        // the sets calibrated on the shipped experiments through each model
        (
            "shipped_n7_15",
            shipped,
            calibrated("fe_reference/identification/shipped_surrogate/report.json"),
        ),
        (
            "as_modelled_n9_13",
            as_modelled,
            calibrated("fe_reference/calibration/surrogate/report.json"),
        ),
        ("design_space_n7_15", design_space, IDENTIFIED),
        ("synthetic_n7_15", synthetic(), OGDEN_002),
    ] {
        let bounds = DesignBounds::of_model(&model);
        let settings = DesignSearch::default();
        let report = search(&model, material, &targets, &bounds, &settings).unwrap();
        eprintln!(
            "{name}: pick N = {}, T = {:.3} mm, {} scan and {} gradient evaluations over {} N",
            report.pick.n,
            report.pick.t_mm,
            report.evaluations.scan,
            report.evaluations.gradient,
            report.designs.len()
        );
        g.bench_function(name, |b| {
            b.iter(|| search(&model, black_box(material), &targets, &bounds, &settings).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
