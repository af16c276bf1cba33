//! How one increment of the minimisation ended ([`Stop`], [`Outcome`]).

/// How the minimisation of one increment stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// ‖r‖ ≤ rtol · force scale.
    Converged,
    /// [`crate::fe::solver::SolverSettings::max_iterations`] reached.
    MaxIterations,
    /// No step length gave a sufficient decrease of Π.
    LineSearch,
    /// No descent direction (every fallback of the tangent failed).
    NoDescent,
    /// The starting state is inadmissible (an inverted element, a gap ≤ 0 under the barrier).
    Inadmissible,
    /// A non-finite residual.
    NotFinite,
}

/// The outcome of one increment.
#[derive(Clone, Copy, Debug)]
pub struct Outcome {
    /// Why it stopped.
    pub stop: Stop,
    /// Newton iterations (factorised directions).
    pub iterations: usize,
    /// Last normalised residual ‖r‖ / force scale.
    pub residual: f64,
    /// Last normalised update α‖Δu‖ / ‖u‖.
    pub update: f64,
}
