//! The smoothly clamped log barrier of incremental-potential contact (Li et al. 2020), the
//! contact law of the minimisation solver ([`crate::fe::solver::minimise`]).
//!
//! With the activation distance `d̂` (mm) and a pressure scale `p̂` (MPa), the contact energy
//! per reference area of a contact point with gap `g` is
//!
//! ```text
//!   ψ(g) = p̂ d̂ b(g/d̂),   b(x) = −(x − 1)² ln x   for 0 < x < 1,   b = 0 for x ≥ 1,
//!   ψ'(g) = p̂ b'(x),      b'(x) = (1 − x)(2 ln x − 1/x + 1),
//!   ψ''(g) = (p̂/d̂) b''(x), b''(x) = (1/x + 2)/x − 2 ln x − 3,
//! ```
//!
//! and `ψ = +∞` for `g ≤ 0`. `b` is C² at `x = 1` (value, slope and curvature vanish), so the
//! barrier switches on smoothly at `g = d̂`; it grows without bound as `g → 0⁺`, so a state of
//! finite energy has every gap strictly positive, whatever the load: no penetration, no
//! multiplier updates. The contact pressure `−ψ'(g)` is `p̂` at `x ≈ 0.37` and `1.19 p̂` at
//! `x = ½`; a point in contact sits at a gap in `(0, d̂)`, which bounds the error of the
//! contact surface by `d̂`. The same geometry as the penalty contact
//! ([`crate::fe::contact::plane_face`], [`crate::fe::contact::pair_face`]) carries it: only
//! `ψ` changes.

use serde::{Deserialize, Serialize};

use crate::fe::contact::ContactError;

/// The clamped log barrier `ψ(g) = p̂ d̂ b(g/d̂)` (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct IpcBarrier {
    /// Activation distance `d̂` (mm): the barrier acts on gaps below it.
    pub dhat: f64,
    /// Pressure scale `p̂` (MPa).
    pub pressure: f64,
}

/// Default activation distance `d̂` (mm).
pub const DEFAULT_DHAT: f64 = 1e-3;
/// Default pressure scale `p̂` (MPa): the order of the cavity pressures.
pub const DEFAULT_BARRIER_PRESSURE: f64 = 0.1;

impl Default for IpcBarrier {
    fn default() -> Self {
        Self {
            dhat: DEFAULT_DHAT,
            pressure: DEFAULT_BARRIER_PRESSURE,
        }
    }
}

impl IpcBarrier {
    /// A validated barrier: `d̂ ∈ [1e-6, 0.5]` mm, `p̂ ∈ [1e-4, 1e3]` MPa.
    ///
    /// # Errors
    /// [`ContactError::OutOfRange`] naming the setting.
    pub fn new(dhat: f64, pressure: f64) -> Result<Self, ContactError> {
        if !(dhat.is_finite() && (1e-6..=0.5).contains(&dhat)) {
            return Err(ContactError::OutOfRange {
                field: "barrier activation distance",
                value: dhat,
                expected: "a distance d̂ in [1e-6, 0.5] mm".into(),
            });
        }
        if !(pressure.is_finite() && (1e-4..=1e3).contains(&pressure)) {
            return Err(ContactError::OutOfRange {
                field: "barrier pressure scale",
                value: pressure,
                expected: "a pressure scale p̂ in [1e-4, 1e3] MPa".into(),
            });
        }
        Ok(Self { dhat, pressure })
    }

    /// ψ(g), ψ'(g), ψ''(g); `(+∞, −∞, +∞)` for `g ≤ 0` (an inadmissible state).
    pub fn eval(&self, g: f64) -> (f64, f64, f64) {
        if g >= self.dhat {
            return (0.0, 0.0, 0.0);
        }
        if g <= 0.0 || g.is_nan() {
            return (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        }
        let x = g / self.dhat;
        let ln = x.ln();
        let b = -(x - 1.0) * (x - 1.0) * ln;
        let db = (1.0 - x) * (2.0 * ln - 1.0 / x + 1.0);
        let ddb = (1.0 / x + 2.0) / x - 2.0 * ln - 3.0;
        (
            self.pressure * self.dhat * b,
            self.pressure * db,
            self.pressure / self.dhat * ddb,
        )
    }
}
