//! The full finite-element model of the bellow actuator.
pub mod material;
