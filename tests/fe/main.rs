//! The full FE model (`surrogate::fe`): derivatives against finite differences, contact,
//! materials, the solver's continuation, the verification cases against analytic and reference
//! solutions, and `docs/MODEL.md` against the code's constants.
//!
//! One test binary; each module is one subject.

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
