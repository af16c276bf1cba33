//! Prediction latency of the surrogate: library path (scalars only, all outputs, with std,
//! with gradient) and the embedded predictor (f32, f64), for a GP-based and a polynomial model
//! trained on a synthetic set of 300 cases (the size of the shipped set), and a GP model with one
//! kernel per POD block (`gp_per_block`); then the same library
//! paths of the shipped model trained on FE snapshots (`models/actuator.json`, or, until it
//! exists, `models/actuator_coarse.json`) at N = 11, T = 2 mm, 2.1 bar, with the first of
//! Ogden 002 and the set calibrated through the shipped model
//! (`fe_reference/identification/shipped_surrogate/`) that lies inside the model's domain
//! (`SURROGATE_BENCH_MODEL=path` measures another model file there).
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use surrogate::case::{OgdenSet, Query};
use surrogate::predict::{evaluate, evaluate_ramp, RampTables};
use surrogate::rom::batch::material_params;
use surrogate::rom::data::SnapshotSet;
use surrogate::rom::export::EmbeddedTables;
use surrogate::rom::fast::kernel_vector;
use surrogate::rom::regression::RegressorKind;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::{train, Jacobian, Surrogate, TrainConfig};

fn model(only: RegressorKind, kernel_per_block: bool) -> Surrogate {
    let cfg = SyntheticConfig {
        n_cases: 300,
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
        only: Some(only),
        kernel_per_block,
        ..Default::default()
    };
    train(&cases, "bench", 0, &tc, &|_, _| {})
        .unwrap()
        .surrogate
}

fn bench(c: &mut Criterion) {
    let q = Query {
        n: 11,
        t_mm: 2.0,
        p_bar: 2.1,
        material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    };
    // the GP kernel vector alone: 300 training points, 6 features
    let (n, d) = (300, 6);
    let xs_t: Vec<f64> = (0..n * d)
        .map(|e| ((e * 7919) % 1000) as f64 / 500.0 - 1.0)
        .collect();
    let inv_len = [1.3, 0.7, 2.0, 0.9, 1.1, 0.5];
    let x = [0.1, -0.2, 0.3, 0.05, -0.7, 0.4];
    let mut k = vec![0.0; n];
    c.bench_function("gp/kernel_vector_300x6", |b| {
        b.iter(|| kernel_vector(black_box(&xs_t), &inv_len, black_box(&x), &mut k))
    });
    shipped(c);
    // `gp_per_block`: one kernel per POD block (`train --kernel-per-block`)
    for (kind, per_block) in [
        (RegressorKind::GP, false),
        (RegressorKind::POLY, false),
        (RegressorKind::GP, true),
    ] {
        let m = model(kind.clone(), per_block);
        let name = if per_block {
            "gp_per_block"
        } else {
            kind.name()
        };
        let mut pred = m.new_prediction();
        let mut jac = Jacobian::default();
        c.bench_function(&format!("{name}/library/tip_angle_force"), |b| {
            b.iter(|| m.predict_scalars_into(black_box(&q), &mut pred).unwrap())
        });
        c.bench_function(&format!("{name}/library/all_outputs"), |b| {
            b.iter(|| m.predict_into(black_box(&q), &mut pred).unwrap())
        });
        c.bench_function(&format!("{name}/library/all_with_std"), |b| {
            b.iter(|| m.predict_with_std_into(black_box(&q), &mut pred).unwrap())
        });
        c.bench_function(&format!("{name}/library/gradient"), |b| {
            b.iter(|| m.gradient_into(black_box(&q), &mut pred, &mut jac).unwrap())
        });
        // design and material fixed, pressure varying: the prepared ramp
        c.bench_function(&format!("{name}/ramp/build"), |b| {
            b.iter(|| m.ramp(black_box(&q)).unwrap())
        });
        let ramp = m.ramp(&q).unwrap();
        c.bench_function(&format!("{name}/ramp/tip_angle_force"), |b| {
            b.iter(|| ramp.predict_scalars(black_box(q.p_bar)).unwrap())
        });
        c.bench_function(&format!("{name}/ramp/all_outputs"), |b| {
            b.iter(|| ramp.predict_into(black_box(q.p_bar), &mut pred).unwrap())
        });
        let t32 = EmbeddedTables::<f32>::from_surrogate(&m).unwrap();
        let b32 = t32.block_tables();
        let e32 = t32.view(&b32);
        let a = q.as_array();
        let in32: [f32; 7] = std::array::from_fn(|i| a[i] as f32);
        let mut out32 = [0f32; 22];
        c.bench_function(&format!("{name}/embedded_f32/all_outputs"), |b| {
            b.iter(|| evaluate(&e32, black_box(&in32), &mut out32).unwrap())
        });
        let t64 = EmbeddedTables::<f64>::from_surrogate(&m).unwrap();
        let b64 = t64.block_tables();
        let e64 = t64.view(&b64);
        let mut out64 = [0f64; 22];
        c.bench_function(&format!("{name}/embedded_f64/all_outputs"), |b| {
            b.iter(|| evaluate(&e64, black_box(&a), &mut out64).unwrap())
        });
        // an exported ramp (`export --ramp`), f32
        let v32: Vec<f32> = ramp.values().iter().map(|&v| v as f32).collect();
        let r32 = RampTables {
            pressures: ramp.pressures(),
            values: &v32,
        };
        c.bench_function(&format!("{name}/embedded_ramp_f32/all_outputs"), |b| {
            b.iter(|| evaluate_ramp(&r32, black_box(2.1f32), &mut out32).unwrap())
        });
    }
}

/// The shipped model (real FE snapshots): what a user's optimisation loop calls.
fn shipped(c: &mut Criterion) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    // SURROGATE_BENCH_MODEL=path measures another model file on the same paths (a design-space
    // model while its set grows, a retrained one)
    let path = match std::env::var_os("SURROGATE_BENCH_MODEL") {
        Some(p) => std::path::PathBuf::from(p),
        None => ["actuator.json", "actuator_coarse.json"]
            .iter()
            .map(|f| root.join(f))
            .find(|p| p.exists())
            .expect("a shipped model in models/"),
    };
    eprintln!("shipped/*: {}", path.display());
    let m = Surrogate::load(&path).unwrap();
    let report = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fe_reference/identification/shipped_surrogate/report.json");
    let calibrated = material_params(report.to_str().unwrap()).unwrap();
    let q = [material_params("ogden_002").unwrap(), calibrated]
        .into_iter()
        .map(|material| Query {
            n: 11,
            t_mm: 2.0,
            p_bar: 2.1,
            material,
        })
        .find(|q| m.check_query(q).is_ok() && m.domain_violations(q).is_empty())
        .expect("Ogden 002 or the calibrated set inside the model's domain");
    eprintln!("shipped/*: material {:?}", q.material);
    let mut pred = m.new_prediction();
    let mut jac = Jacobian::default();
    c.bench_function("shipped/library/tip_angle_force", |b| {
        b.iter(|| m.predict_scalars_into(black_box(&q), &mut pred).unwrap())
    });
    c.bench_function("shipped/library/all_outputs", |b| {
        b.iter(|| m.predict_into(black_box(&q), &mut pred).unwrap())
    });
    c.bench_function("shipped/library/all_with_std", |b| {
        b.iter(|| m.predict_with_std_into(black_box(&q), &mut pred).unwrap())
    });
    c.bench_function("shipped/library/gradient", |b| {
        b.iter(|| m.gradient_into(black_box(&q), &mut pred, &mut jac).unwrap())
    });
}

criterion_group! {
    name = rom;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30);
    targets = bench
}
criterion_main!(rom);
