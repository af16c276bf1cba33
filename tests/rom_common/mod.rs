//! Shared fixtures of the `rom_*` tests: small synthetic snapshot sets and models.
#![allow(dead_code)]

use surrogate::rom::data::{CaseSet, SnapshotSet};
use surrogate::rom::regression::RegressorKind;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::{train, Surrogate, TrainConfig};

/// Synthetic CSV text.
pub fn synthetic_csv(n_cases: usize, seed: u64) -> String {
    let cfg = SyntheticConfig {
        n_cases,
        seed,
        ..Default::default()
    };
    let mut buf = Vec::new();
    write_csv(&cfg, &mut buf).unwrap();
    String::from_utf8(buf).unwrap()
}

/// Synthetic cases ready for training.
pub fn synthetic_cases(n_cases: usize, seed: u64) -> CaseSet {
    let text = synthetic_csv(n_cases, seed);
    SnapshotSet::from_reader(text.as_bytes(), "synthetic")
        .unwrap()
        .into_cases()
        .unwrap()
}

/// A small model (40 cases, 3 folds), optionally restricted to one regressor family.
pub fn small_model(only: Option<RegressorKind>) -> Surrogate {
    small_model_with(only, false)
}

/// The small model with one GP kernel per POD block (GP only).
pub fn grouped_model() -> Surrogate {
    small_model_with(Some(RegressorKind::GP), true)
}

/// The small model with a sparse GP on 16 inducing points (GP only; the folds' fits, on 26
/// or 27 cases, are sparse too).
pub fn sparse_model() -> Surrogate {
    let cases = synthetic_cases(40, 7);
    let cfg = TrainConfig {
        folds: 3,
        only: Some(RegressorKind::GP),
        gp: surrogate::rom::regression::gp::GpParams {
            inducing: Some(16),
            ..Default::default()
        },
        ..Default::default()
    };
    train(&cases, "synthetic", 0, &cfg, &|_, _| {})
        .unwrap()
        .surrogate
}

fn small_model_with(only: Option<RegressorKind>, kernel_per_block: bool) -> Surrogate {
    let cases = synthetic_cases(40, 7);
    let cfg = TrainConfig {
        folds: 3,
        only,
        kernel_per_block,
        ..Default::default()
    };
    train(&cases, "synthetic", 0, &cfg, &|_, _| {})
        .unwrap()
        .surrogate
}
