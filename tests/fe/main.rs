//! The full FE model (`surrogate::fe`): derivatives against finite differences, contact,
//! materials, the solver's continuation, the verification cases against analytic and reference
//! solutions, and `docs/MODEL.md` against the code's constants.
//!
//! One test binary; each module is one subject.
//!
//! `unit/`: the library's unit tests of `src/fe/`, one file per source module, named after its path
//! below `src/fe/` (`src/fe/solver/warm.rs`: `unit/solver_warm.rs`). `unit/assembly_model.rs` holds
//! no tests, only the small model the tests of the assembly and the solver share (`clamped_block`).
//! `cargo test --release --test fe unit::` runs them alone. The library has no unit-test harness
//! (`[lib] test = false` in `Cargo.toml`, so that `cargo test` compiles it once), so these tests
//! see its public API; the few private items they need are `pub` and `#[doc(hidden)]`, each marked
//! `// public for the tests in tests/fe/`.

#[path = "../common/mod.rs"]
mod common;

mod actuator_tangent;
mod contact_pairs;
mod contact_plane;
mod effects;
mod element_tangent;
mod force_plate_faces;
mod materials;
mod minimise;
mod model_doc;
mod sensitivities;
mod shared_runs;
mod solver_stabilization;
mod toy_effect;
mod toy_load_term;
mod verification_cantilever;
mod verification_cook;
mod verification_cylinder;
mod verification_homogeneous;
mod verification_patch;
mod warm_start;

/// The library's unit tests of this floor (see the module docs).
mod unit {
    mod assembly_load;
    mod assembly_load_factor;
    mod assembly_model;
    mod assembly_projection;
    mod assembly_terms;
    mod assembly_terms_barrier;
    mod contact;
    mod contact_cp;
    mod effects;
    mod element;
    mod geometry;
    mod loads;
    mod material_fibre;
    mod material_literature;
    mod material_ogden;
    mod mesh;
    mod ordering;
    mod preset;
    mod runner;
    mod sensitivity_params;
    mod simulate_case;
    mod solver_linear;
    mod solver_settings;
    mod solver_warm;
    mod warm_start_transfer;
}
