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
//!   calibrate (fit the material to recordings, identifiability, FE verification)
//! ```
//!
//! Each module returns its own error type; [`Error`] gathers them for a program that chains
//! the stages, and [`io::write_atomic`] writes every file the crate produces.
#![warn(missing_docs)]

pub mod calibrate;
pub mod error;
pub mod fe;
pub mod io;
pub mod predict;
pub mod rom;
pub mod snapshots;

pub use error::{Error, Result};
