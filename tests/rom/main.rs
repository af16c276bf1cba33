//! The POD surrogate (`surrogate::rom`) and the embedded predictor: snapshot data, model files,
//! gradients, the allocation-free and fast paths, ramps, exports, the training domain, the
//! shared output schema, the shipped models, and a regressor registered from outside the crate.
//!
//! One test binary; each module is one subject.
//!
//! `unit/`: the library's unit tests of `src/rom/`, one file per source module, named after its
//! path below `src/rom/` (`src/rom/regression/gp/fit.rs`: `unit/regression_gp_fit.rs`). `cargo test
//! --release --test rom unit::` runs them alone. The library has no unit-test harness (`[lib] test
//! = false` in `Cargo.toml`, so that `cargo test` compiles it once), so these tests see its public
//! API; the few private items they need are `pub` and `#[doc(hidden)]`, each marked `// public for
//! the tests in tests/rom/`.

#[path = "../shared/counting_alloc.rs"]
mod counting_alloc;
#[path = "../rom_common/mod.rs"]
mod rom_common;

mod domain;
mod fuzz_parsers;
mod model_form;
mod ordinal_n;
mod output_schema;
mod rom_alloc;
mod rom_data;
mod rom_embedded;
mod rom_fast;
mod rom_gradients;
mod rom_model;
mod rom_ramp;
mod shipped_model;
mod sparse_gp;
mod toy_regressor;
mod unseen;

/// The library's unit tests of this floor (see the module docs).
mod unit {
    mod fast;
    mod material_spec;
    mod model_form;
    mod regression_gp;
    mod regression_gp_fit;
    mod regression_gp_likelihood;
    mod regression_gp_sparse;
    mod regression_linalg;
    mod regression_poly;
    mod warp;
}
