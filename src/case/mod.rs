//! The case vocabulary, on the ground floor: what the snapshot plans, the surrogate, the
//! calibrator and the diagnoser say about a case, named once below all of them.
//!
//! - [`material`]: the Ogden material `(μ₁, α₁, μ₂, α₂)` as one type ([`OgdenSet`]), its
//!   check, its array and FE conversions, and its sampling coordinates `(μ0, s, α₁, α₂)`
//!   ([`MaterialCoords`]).
//! - [`inputs`]: the design `(N, T)` and the material of a case ([`CaseInputs`]); [`Query`]: the
//!   same at a gauge pressure `P` (bar), where a surrogate is evaluated.
//! - [`features`]: the coordinates `z = (N, T, ln μ0, α₁, s, α₂)` in which plans sample and
//!   the surrogate regresses, and the box a set of cases spans in them ([`FeatureScaler`]).
//! - [`domain`]: the parameter box of a model or a plan ([`Domain`]) and the one check of a
//!   query against it ([`Domain::violations`]).
//! - [`CaseError`]: a case value that is not admissible, naming the field, the value and what
//!   is allowed.
//!
//! The snapshot file's columns are in [`crate::schema`] ([`crate::schema::SNAPSHOT_COLUMNS`]).
//! This module imports nothing above the ground floor (`tests/import_graph/`).

pub mod domain;
mod error;
pub mod features;
pub mod inputs;
pub mod material;

pub use domain::{
    BatchDomainReport, BoundSnap, Domain, DomainViolation, InputRange, PlanDomain, BOUND_TOLERANCE,
};
pub use error::CaseError;
pub use features::{raw_features, FeatureScaler, FEATURE_NAMES};
pub use inputs::{CaseInputs, Query};
pub use material::{MaterialCoords, OgdenSet};
