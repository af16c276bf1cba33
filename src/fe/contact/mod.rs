//! Frictionless contact of element faces with rigid planes (the clamp block, the force plate).
//!
//! Penalty with a C² barrier: with the signed gap `g = n·(x − x₀)` of a face quadrature point
//! (`n` the plane's unit normal pointing towards the body), the contact energy per reference area
//! is
//!
//! ```text
//!   ψ(g) = 0                                  g ≥ δ
//!   ψ(g) = ε (δ − g)³ / (6δ)                  0 ≤ g < δ
//!   ψ(g) = ε (δ²/6 − δ g/2 + g²/2)            g < 0
//! ```
//!
//! so the contact pressure `t = −ψ'(g)` rises smoothly from zero at `g = δ` and grows as `ε·(−g)`
//! in penetration, and the tangent `ψ''` is continuous: Newton sees no jump when contact opens
//! or closes. Residual and tangent of a face (3×3 Gauss points, reference area `dA₀`):
//!
//! ```text
//!   r_a = ∫ ψ'(g) N_a n dA₀          K_ab = ∫ ψ''(g) N_a N_b n⊗n dA₀
//! ```
//!
//! The plane's reaction on the body is `F = ∫ −ψ'(g) dA₀` along `n`.

// Index loops mirror the tensor notation of the equations (a, b: nodes; c, e: components).
#![allow(clippy::needless_range_loop)]

mod face;
mod law;
mod pair;
mod plane;

use thiserror::Error;

pub use law::{barrier, update_shift};
pub use pair::{
    pair_centre_gap, pair_face, pair_face_gaps, pair_face_with, pair_orientation, FacePair,
    PairSettings, PAIR_DOFS,
};
pub use plane::{plane_face, plane_face_gaps, plane_face_with, RigidPlane};

/// Errors of contact settings.
#[derive(Debug, Error, PartialEq)]
pub enum ContactError {
    /// A setting out of range.
    #[error("contact setting {field} = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// Setting.
        field: &'static str,
        /// Value.
        value: f64,
        /// Allowed range.
        expected: String,
    },
    /// A contact pair couples two nodes that the sparse pattern does not.
    #[error("contact pair couples nodes {0} and {1}, which the sparse pattern does not hold")]
    MissingCoupling(usize, usize),
}
