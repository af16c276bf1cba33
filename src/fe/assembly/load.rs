//! The load parameter of a state: [`LoadLevel`], the factors of pressure, gravity, dead
//! traction and prescribed displacement along which the solver continues.

use serde::{Deserialize, Serialize};

/// Load factors of one state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LoadLevel {
    /// Cavity pressure (MPa).
    pub pressure: f64,
    /// Gravity factor (1 = full self-weight).
    pub gravity: f64,
    /// Dead-traction factor.
    pub traction: f64,
    /// Prescribed-displacement factor.
    pub prescribed: f64,
}

impl LoadLevel {
    /// Linear interpolation between two levels.
    pub fn lerp(&self, other: &Self, s: f64) -> Self {
        let l = |a: f64, b: f64| a + s * (b - a);
        Self {
            pressure: l(self.pressure, other.pressure),
            gravity: l(self.gravity, other.gravity),
            traction: l(self.traction, other.traction),
            prescribed: l(self.prescribed, other.prescribed),
        }
    }
}
