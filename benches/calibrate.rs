//! Wall time of a calibration through the shipped surrogate (`models/actuator.json`), all 27
//! configurations of the shipped experiments, multistart (24 Latin-hypercube starts + Ogden
//! 002), identifiability and profiles included: the objective `tip` (the default) and
//! `tip,angle,force` (the identification's); and the study's per-configuration procedure on
//! its own, through the model of the geometry as modelled (`models/as_modelled/actuator.json`),
//! whose domain holds the study's box around Ogden 002 (the shipped model's does not).
//!
//! ```sh
//! cargo bench --bench calibrate
//! ```
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use surrogate::calibrate::study::per_configuration;
use surrogate::calibrate::{calibrate, CalibrationSettings, Recordings, Selection, Weights};
use surrogate::rom::Surrogate;

fn bench(c: &mut Criterion) {
    let model = Surrogate::load(Path::new("models/actuator.json")).unwrap();
    let rec = Recordings::shipped().unwrap();
    let mut g = c.benchmark_group("calibrate");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    for objective in ["tip", "tip,angle,force"] {
        let s = CalibrationSettings {
            weights: Weights::parse(objective).unwrap(),
            ..CalibrationSettings::default()
        };
        g.bench_function(format!("all_27_{}", objective.replace(',', "_")), |b| {
            b.iter(|| black_box(calibrate(&model, &rec, &s, &|_| {}).unwrap()))
        });
    }
    let s = CalibrationSettings::default();
    let as_modelled = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    g.bench_function("per_configuration_27", |b| {
        b.iter(|| {
            black_box(
                per_configuration(
                    &as_modelled,
                    &rec,
                    &s.literature,
                    0.1,
                    &Selection::default(),
                    &s.multistart,
                )
                .unwrap(),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
