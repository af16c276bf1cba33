//! The ground floor (`surrogate::case`, `surrogate::schema`, `surrogate::io` and the crate's
//! seeded random draws): the library's unit tests of the modules below `fe`.
//!
//! `unit/`: one file per source module, named after its path below `src/` (`src/case/inputs.rs`:
//! `unit/case_inputs.rs`). `cargo test --release --test case unit::` runs them alone. The library
//! has no unit-test harness (`[lib] test = false` in `Cargo.toml`, so that `cargo test` compiles it
//! once), so these tests see its public API; the few private items they need are `pub` and
//! `#[doc(hidden)]`, each marked `// public for the tests in tests/case/`.

/// The library's unit tests of this floor (see the module docs).
mod unit {
    mod case_inputs;
    mod case_material;
    mod io;
    mod random;
    mod schema;
}
