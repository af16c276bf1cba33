//! The full finite-element model of the bellow actuator.
//!
//! Pipeline: [`geometry::Design`] → [`mesh::ActuatorMesh`] → [`assembly::FeModel`]
//! (elements from [`element`], loads from [`loads`], material from [`material`]) →
//! [`solver`] (load stepping + Newton) → [`simulate`] (markers, tip, angle).
pub mod assembly;
pub mod contact;
pub mod contact_cp;
pub mod element;
pub mod geometry;
pub mod loads;
pub mod material;
pub mod mesh;
pub mod ordering;
pub mod simulate;
pub mod solver;
pub mod vtk;
