//! The data the solver carries: the state along a load path ([`PathState`]) and the viscous
//! term of the stabilised continuation while it is on. Kept apart from the algorithms so
//! that each of those files depends on this one and on no other of its siblings' data.

use super::problem::NonlinearProblem;
use crate::fe::assembly::LoadLevel;

/// The state carried along a load path.
pub struct PathState {
    /// Free unknowns at the last converged level.
    pub u_free: Vec<f64>,
    /// Full displacement vector at the last converged level.
    pub u_full: Vec<f64>,
    /// The last converged level.
    pub level: LoadLevel,
    /// Up to two earlier converged states (oldest first), for the predictor.
    pub(super) history: Vec<(Vec<f64>, LoadLevel)>,
}

impl PathState {
    /// The undeformed state at zero load (and the model's contact gap shifts reset).
    pub fn new(model: &impl NonlinearProblem) -> Self {
        model.reset_contact_shifts();
        Self {
            u_free: vec![0.0; model.n_free()],
            u_full: vec![0.0; model.n_full()],
            level: LoadLevel::default(),
            history: Vec::new(),
        }
    }
}

/// The viscous term `c ⊙ (u − u_ref)` of the stabilised continuation
/// ([`SolverSettings::stabilization`](super::SolverSettings::stabilization)), on the free unknowns.
pub(super) struct Stabilization {
    /// β · |K₀ᵢᵢ| per free unknown.
    pub(super) damping: Vec<f64>,
    /// The state of the last substep.
    pub(super) u_ref: Vec<f64>,
    /// The undamped equilibrium it started from, restored if it fails.
    pub(super) origin: (Vec<f64>, LoadLevel),
    /// Factor on `damping` (pseudo-time step⁻¹ of the relaxation).
    pub(super) scale: f64,
}

/// First pressure increment (MPa) of the stabilised continuation.
pub(super) const STABILIZED_INCREMENT: f64 = 0.0025;

/// Whether `level` is where `state` already is (no load factor changes).
pub(super) fn level_is_zero_increment(state: &PathState, level: &LoadLevel) -> bool {
    state.level.changing(level).next().is_none()
}
