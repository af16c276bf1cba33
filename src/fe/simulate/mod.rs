//! `simulate(&Case) -> Response`: mesh → model → load path → measurements.
//!
//! One driver in four steps, one file each:
//!
//! | file | concern |
//! |---|---|
//! | [`case`] | the case ([`Case`], [`Mode`], [`ContactSettings`]), its checks, the pressure list's syntax |
//! | [`model`] | building the model of a case: mesh, constraints, loads, obstacles ([`ActuatorModel`]) |
//! | [`path`] | the load-path driver: self-weight, plate, pressure ramp, compliant plate ([`run_warm`]) |
//! | [`measure`] | markers, tip, angle, forces and gaps of a converged state ([`StepResult`], [`Response`]) |
//!
//! The load path: gravity is applied first (the state reported at P = 0), then the pressure is
//! ramped through the requested values. Outputs follow the SPEC's conventions:
//! `Uz = −Δz`, `Uy = Δy` of the tip (marker 9), bending angle `α = atan2(−y_tip, z_tip)`
//! measured from the support point (W/2, 0, 0).

use thiserror::Error;

use crate::fe::contact::ContactError;
use crate::fe::effects::EffectError;
use crate::fe::element::ElementError;
use crate::fe::geometry::GeometryError;
use crate::fe::solver::SolverError;

pub mod case;
pub mod measure;
pub mod model;
pub mod path;

pub use crate::fe::warm_start::ConvergedState;
pub use case::{
    parse_pressures, validate_pressures, Case, ContactSettings, Mode, BAR, MAX_PRESSURE_BAR,
};
pub use measure::{marker_list, Marker, Response, StepResult};
pub use model::{ActuatorModel, DENSITY, FORCE_MODEL_REVISION, GRAVITY, PLATE_REACH};
pub use path::{
    run, run_warm, simulate, simulate_with, simulate_with_progress, Ran, PLATE_OFFSET,
    PLATE_SETTLE_ITERATIONS, PLATE_SETTLE_MM,
};

/// Errors of a simulation.
#[derive(Debug, Error)]
pub enum SimulateError {
    /// Invalid design.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// A geometry preset that cannot build the design ([`crate::fe::preset`]).
    #[error(transparent)]
    Preset(#[from] crate::fe::preset::PresetError),
    /// Invalid mesh.
    #[error(transparent)]
    Element(#[from] ElementError),
    /// The solver stopped.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// Invalid contact settings.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// An invalid effect.
    #[error(transparent)]
    Effect(#[from] EffectError),
    /// An invalid material (including one an effect makes, e.g. anisotropy).
    #[error(transparent)]
    Material(#[from] crate::fe::material::MaterialError),
    /// The plate on a spring (`plate_compliance`) did not settle at a pressure.
    #[error(
        "the compliant plate did not settle at {pressure_bar} bar: after {iterations} re-solves \
         its position is {mismatch_mm:.2e} mm from c·F (expected below {PLATE_SETTLE_MM} mm)"
    )]
    PlateNotSettled {
        /// The gauge pressure (bar).
        pressure_bar: f64,
        /// Re-solves made.
        iterations: usize,
        /// Last `|y − (y0 − c·F)|` (mm).
        mismatch_mm: f64,
    },
    /// A setting out of range (solver, mesh).
    #[error(transparent)]
    Setting(#[from] crate::fe::InvalidSetting),
    /// Invalid pressure list.
    #[error("pressure {value} bar at position {} of the list is invalid: expected {expected}", .index + 1)]
    Pressure {
        /// Position in the list, from 0 (messages count from 1).
        index: usize,
        /// The value.
        value: f64,
        /// What was expected.
        expected: String,
    },
    /// A pressure list entry that is not a number, or a malformed `max:step`.
    #[error("pressure list {list:?}: {what}")]
    PressureText {
        /// The list as given.
        list: String,
        /// What is wrong, with the position counted from 1.
        what: String,
    },
}
