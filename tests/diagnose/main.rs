//! The diagnoser (`surrogate::diagnose`): the Locate stage on recordings with a planted
//! residual (`diagnose`), Model and show (`refit`), the sensitivities against the model they are
//! used with (`built_with`), the model's mesh error (`mesh_error`) and approximation error
//! (`approx_error`) as candidates, and the blind study's plan, scoring, noise and closed loop
//! (`study`, `study_noise`, `closed_loop`). The command-line tests are in `tests/cli/`.
//!
//! `unit/`: the library's unit tests of `src/diagnose/`, one file per source module, named after
//! its path below `src/diagnose/` (`src/diagnose/name/ties.rs`: `unit/name_ties.rs`).
//! `unit/cells.rs` holds no tests, only the fitted cell the tests build tables from (`Cell::unit`).
//! `cargo test --release --test diagnose unit::` runs them alone. The library has no unit-test
//! harness (`[lib] test = false` in `Cargo.toml`, so that `cargo test` compiles it once), so these
//! tests see its public API; the few private items they need are `pub` and `#[doc(hidden)]`, each
//! marked `// public for the tests in tests/diagnose/`.

mod approx_error;
mod built_with;
mod closed_loop;
mod diagnose;
mod mesh_error;
mod refit;
mod study;
mod study_noise;

/// The library's unit tests of this floor (see the module docs).
mod unit {
    mod approx_error;
    mod cells;
    mod discrimination;
    mod findings;
    mod fixtures;
    mod groups;
    mod measure_design;
    mod name;
    mod name_ties;
    mod refit_confirm;
    mod refit_rank;
    mod setup;
    mod structure;
    mod study_closed_loop;
}

/// The diagnoser's settings of the Model-and-show and mesh-error tests: the `tip` objective,
/// 6 starts, 4 profile points.
pub fn quick_diagnose_settings() -> surrogate::diagnose::DiagnoseSettings {
    let mut c = surrogate::calibrate::CalibrationSettings {
        weights: surrogate::calibrate::Weights::parse("tip").unwrap(),
        multistart: surrogate::calibrate::optimise::MultistartSettings {
            starts: 6,
            ..surrogate::calibrate::optimise::MultistartSettings::default()
        },
        ..surrogate::calibrate::CalibrationSettings::default()
    };
    c.identify.profile_points = 4;
    surrogate::diagnose::DiagnoseSettings {
        calibration: c,
        ..surrogate::diagnose::DiagnoseSettings::default()
    }
}
