//! # surrogate
//!
//! Finite-element model, snapshot generator and reduced-order surrogate of 3D-printed soft
//! pneumatic bellow actuators (the physical model, its parameters, loads, outputs, sign
//! conventions and units: `docs/MODEL.md` in the repository).
//!
//! ```text
//!   Design (N, T, dims) ─► fe::mesh ─► fe::assembly + fe::solver ─► Response (markers, tip, angle, force)
//!                                                         │
//!   sampling plan ─► snapshots (resumable, sharded) ◄─────┘
//!                         │
//!                         ▼
//!   rom: POD of marker fields + regression ─► Surrogate (library, CLI, embedded predictor)
//!                         │
//!                         ▼
//!   calibrate (the material, and with `identify` the unstated dimensions, fitted to
//!              recordings; identifiability, FE verification, box extension)
//!                         │
//!                         ▼
//!   design (search every N and a continuous T for targets, maps over the design space)
//!   diagnose (locate the residual over N, T, P and along the actuator → name the missing
//!             physics among the effects → refit with it and confirm by FE → plan the
//!             measurements that would separate the candidates left tied)
//! ```
//!
//! The embedded predictor is a crate of its own, `surrogate-predict` (`predict/` in the
//! repository: `#![no_std]`, no dependencies), re-exported here as [`predict`]; a controller
//! depends on it alone and compiles a model written by [`rom::export`] (`surrogate export`).
//!
//! # Features
//!
//! - `cli` (default): the `surrogate` program and its dependencies (clap, indicatif,
//!   plotters, anyhow). The library needs none of them; a library user depends on
//!   `surrogate` with `default-features = false`.
//!
//! Every CSV column and file quantity (name, unit, meaning) and the column order of each file
//! format are defined once, in [`schema`]; the inputs of a case, its query at a pressure and the
//! parameter box, in [`case`].
//!
//! The modules stand on floors, the shared vocabulary ([`case`], [`schema`], [`io`]) on the
//! ground and each stage of the pipeline above the one it uses; a module imports only from its
//! own floor and the floors below (the table: the README's Layout; `tests/import_graph/`
//! checks it).
//!
//! Each module returns its own error type; [`Error`] gathers them for a program that chains
//! the stages, and [`io::write_atomic`] writes every file the crate produces.
#![warn(missing_docs)]

pub mod calibrate;
pub mod case;
pub mod design;
pub mod diagnose;
pub mod error;
pub mod fe;
pub mod io;
// public for the tests in tests/case/ and tests/calibrate/
#[doc(hidden)]
pub mod random;
pub mod rom;
pub mod schema;
pub mod snapshots;

pub use error::{Error, Result};

/// The embedded predictor (`core` only, no allocation): the `surrogate-predict` crate of this
/// workspace, which a controller depends on directly.
pub use surrogate_predict as predict;
