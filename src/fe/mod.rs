//! The full finite-element model of the bellow actuator.
//!
//! Pipeline: [`geometry::Design`] → [`mesh::ActuatorMesh`] → [`assembly::FeModel`]
//! (elements from [`element`], loads from [`loads`], material from [`material`]) →
//! [`solver`] (load stepping + Newton) → [`simulate`] (markers, tip, angle); [`runner`] runs
//! campaigns of such cases in parallel, cached and resumable.
pub mod assembly;
pub mod campaign;
pub mod contact;
pub mod contact_cp;
pub mod effects;
pub mod element;
pub mod geometry;
pub mod loads;
pub mod material;
pub mod mesh;
pub mod ordering;
pub mod preset;
pub mod runner;
pub mod sensitivity;
pub mod simulate;
pub mod solver;
pub mod vtk;
pub mod warm_start;

use thiserror::Error;

/// A setting outside its range: the field, its value and what was expected. Settings
/// ([`solver::SolverSettings`], [`mesh::MeshOptions`], [`simulate::Case`]) validate
/// themselves with it; a caller that reads them from a file or a command line puts its own
/// prefix or flag name on the field ([`Self::within`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[error("{field} = {value}: expected {expected}")]
pub struct InvalidSetting {
    /// The field, e.g. `solver.rtol`.
    pub field: String,
    /// Its value.
    pub value: f64,
    /// What was expected.
    pub expected: String,
}

impl InvalidSetting {
    /// A setting error.
    pub fn new(field: impl Into<String>, value: f64, expected: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            value,
            expected: expected.into(),
        }
    }

    /// The same error with `prefix` put before the field (`solver.` + `rtol`).
    #[must_use]
    pub fn within(mut self, prefix: &str) -> Self {
        self.field = format!("{prefix}{}", self.field);
        self
    }
}
