//! The calibrator (`surrogate::calibrate`) on recordings made by the FE model, the recording
//! readers on bad files (`tests/data/bad_recordings/`) and random ones. The diagnoser's tests
//! are in `tests/diagnose/`, the command-line tests in `tests/cli/`.
//!
//! `unit/`: the library's unit tests of `src/calibrate/`, one file per source module, named after
//! its path below `src/calibrate/` (`src/calibrate/extend/plan.rs`: `unit/extend_plan.rs`). `cargo
//! test --release --test calibrate unit::` runs them alone. The library has no unit-test harness
//! (`[lib] test = false` in `Cargo.toml`, so that `cargo test` compiles it once), so these tests
//! see its public API; the few private items they need are `pub` and `#[doc(hidden)]`, each marked
//! `// public for the tests in tests/calibrate/`.

mod analytic;
mod bad_recordings;
mod calibrate;
mod extend;
mod fuzz_recordings;
mod refine;
mod twin;

/// The library's unit tests of this floor (see the module docs).
mod unit {
    mod baseline;
    mod checks;
    mod experiments;
    mod extend_limits;
    mod extend_material_box;
    mod extend_plan;
    mod inputs;
    mod joint;
    mod optimise;
    mod params;
    mod synthetic;
    mod twin;
    mod units;
    mod verdict;
}
