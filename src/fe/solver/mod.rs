//! The nonlinear solver of the FE model: load control with adaptive substeps, Newton–Raphson,
//! augmented-Lagrangian contact and a stabilised continuation through instabilities, on any
//! [`NonlinearProblem`] (the actuator's [`FeModel`] is one).
//!
//! Each load step solves `r(u; λ) = 0` on the free unknowns for a load level λ
//! ([`LoadLevel`], a vector of named load factors: the solver ramps, extrapolates and compares
//! levels factor by factor, whatever factors the model's load terms read). A reader can take
//! the parts one at a time:
//!
//! | file | concern |
//! |---|---|
//! | [`problem`] | what the solver needs from a model: residual, tangent, load parameter, contact hooks |
//! | [`continuation`] | output steps cut into adaptive increments, cut-back, the path driver [`solve_path`] |
//! | [`predictor`] | the first guess of an increment, extrapolated along the path |
//! | [`newton`] | Newton iterations, admissibility guard, line search, early give-up |
//! | [`augmented`] | Uzawa updates of the contact gap shifts after each output step |
//! | [`stabilization`] | viscous pseudo-time stepping where load control stops |
//! | [`linear`] | the sparse LDLᵀ (and LLᵀ) factorisation and its fill-reducing ordering |
//! | [`minimise`] | the other solver ([`SolverKind::Minimise`]): minimisation of the total potential with barrier contact |
//! | [`settings`] | settings, step reports, errors |
//! | [`state`] | the path state and the stabilisation's viscous term |
//! | [`warm`] | warm starts: a level solved directly from a neighbouring case's converged state |
//!
//! Why it is built this way:
//!
//! - **Mixed tangent.** With a bulk modulus κ = 1000 μ0, a Newton step along the soft bending
//!   mode (a linearised rotation) violates J = 1 at second order, and κ turns that into a large
//!   spurious pressure. The default iteration ([`SolverSettings::mixed_tangent`]) carries the
//!   element pressures linearly instead (the mixed u–θ–π Newton of Simo–Taylor–Pister,
//!   condensed per element): same residual and solution, quadratic convergence after the first
//!   two iterations.
//! - **Predictor.** A quadratic extrapolation of the path carries its curvature, which the
//!   tangent does not, and violates J = 1 only at third order; guarded against contact that the
//!   extrapolation cannot know about.
//! - **Giving up early.** An attempt that diverges or stalls far from the solution is ended
//!   and its increment halved, rather than spending the remaining iterations.
//! - **Augmented Lagrangian.** The penalty contact's error is removed by Uzawa updates of gap
//!   shifts between solves, so the walls touch to within [`AUGMENTED_GAP_TOL`] · ε.
//! - **Stabilisation.** Only where plain load control has stopped (a limit point), so every
//!   result that converged without it is unchanged, and only undamped equilibria are reported.
//! - **Factor reuse only where the load is fixed.** Every Newton iteration of the load path
//!   factorises its tangent; the augmented re-solves, where the load does not change, keep
//!   the last factor while each iteration contracts the residual enough (modified Newton,
//!   [`SolverSettings::reuse_factor`], the default; results computed before keep their cache
//!   keys, see its docs). The factorisation runs on one thread
//!   ([`linear::factor_parallelism`]).
//! - **Warm starts.** In a campaign the neighbouring case's converged state is a far better
//!   start than the undeformed actuator ([`warm`]). Where Newton fails from it, a Newton
//!   homotopy from that state is tried before the load path.
//!
//! The measurements behind each of these choices (iteration counts and wall times of the
//! alternatives that were tried) are recorded in `docs/SOLVER_MEASUREMENTS.md`.

pub mod augmented;
pub mod continuation;
pub mod linear;
pub mod minimise;
pub mod newton;
pub mod predictor;
pub mod problem;
pub mod settings;
pub mod stabilization;
pub mod state;
pub mod warm;

pub use continuation::{solve_path, solve_path_from};
pub use linear::{LinearSolver, Ordering};
pub use problem::NonlinearProblem;
pub use settings::{
    MinimiseSettings, SolverError, SolverKind, SolverSettings, StepReport, AUGMENTED_GAP_TOL,
    DEFAULT_STABILIZATION, REUSE_CONTRACTION,
};
pub use state::PathState;
pub use warm::{solve_path_guided, LevelGuess};

use super::assembly::{FeModel, LoadLevel};
use super::element::ElementError;
use state::Stabilization;

/// Drives a model along a load path.
pub struct Solver<'m, P: NonlinearProblem = FeModel> {
    model: &'m P,
    linear: LinearSolver,
    settings: SolverSettings,
    r_full: Vec<f64>,
    u_pred: Vec<f64>,
    r_free: Vec<f64>,
    k: Vec<f64>,
    du: Vec<f64>,
    du_full: Vec<f64>,
    trial: Vec<f64>,
    /// Element pressures carried by the mixed iteration (valid when `use_tangent_pressure`).
    tangent_pressure: Vec<[f64; 4]>,
    use_tangent_pressure: bool,
    /// External-force norm of the residual that the step guard of [`Self::line_search`]
    /// assembled at exactly the state the step moved to (then in `r_full` / `r_free`).
    guard_residual: Option<f64>,
    factor_seconds: f64,
    assembly_seconds: f64,
    /// Floor of the force scale: 1e-3 · μ0 · V^(2/3) (a characteristic internal force).
    force_scale: f64,
    /// Pressure increment of the last converged substep.
    last_increment: Option<f64>,
    /// Viscous term of the stabilised continuation, while it is on.
    stab: Option<Stabilization>,
    /// Force scale of the last Newton iteration's convergence test.
    last_force_scale: f64,
    /// The Newton homotopy's residual at its start on the free unknowns ([`warm`]), kept
    /// between its steps (empty until the first homotopy).
    homotopy_r0: Vec<f64>,
    /// Weight `1 − t` of `homotopy_r0` taken off the residual while a homotopy step is
    /// solved; 0 otherwise.
    homotopy_weight: f64,
}

impl<'m, P: NonlinearProblem> Solver<'m, P> {
    /// Prepares a solver (symbolic factorisation) for a model.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if the symbolic analysis fails.
    pub fn new(model: &'m P, settings: SolverSettings) -> Result<Self, SolverError> {
        let n = model.n_free();
        Ok(Self {
            model,
            linear: LinearSolver::new(model)?,
            settings,
            r_full: vec![0.0; model.n_full()],
            u_pred: Vec::new(),
            r_free: vec![0.0; n],
            k: vec![0.0; model.pattern().nnz()],
            du: vec![0.0; n],
            du_full: vec![0.0; model.n_full()],
            trial: vec![0.0; n],
            tangent_pressure: vec![[0.0; 4]; model.n_mixed_fields()],
            use_tangent_pressure: false,
            guard_residual: None,
            factor_seconds: 0.0,
            assembly_seconds: 0.0,
            last_increment: None,
            stab: None,
            last_force_scale: 0.0,
            force_scale: model.force_floor(),
            homotopy_r0: Vec::new(),
            homotopy_weight: 0.0,
        })
    }

    /// The settings the solver steps with.
    // public for the tests in tests/fe/
    #[doc(hidden)]
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// The settings, to change between steps.
    // public for the tests in tests/fe/
    #[doc(hidden)]
    pub fn settings_mut(&mut self) -> &mut SolverSettings {
        &mut self.settings
    }

    /// The homotopy's weight `1 − t` of its start residual ([`warm`]): 0 outside a homotopy.
    // public for the tests in tests/fe/
    #[doc(hidden)]
    pub fn homotopy_weight(&self) -> f64 {
        self.homotopy_weight
    }

    /// The residual (all dofs, reactions at constrained ones) of the last assembly.
    pub fn residual_full(&self) -> &[f64] {
        &self.r_full
    }

    /// Residual (and tangent) at `u_full`, the expansion of `u_free` at `level`; with the
    /// stabilised continuation on, its viscous term is added on the free unknowns, and during
    /// a homotopy step ([`warm`]) `(1 − t) r₀` is taken off them. Returns the norm of the
    /// external forces on the free unknowns.
    pub(super) fn assemble(
        &mut self,
        u_free: &[f64],
        u_full: &[f64],
        level: &LoadLevel,
        with_k: bool,
    ) -> Result<f64, ElementError> {
        let t = std::time::Instant::now();
        let k = with_k.then_some(&mut self.k[..]);
        let tp = (with_k && self.use_tangent_pressure).then_some(&self.tangent_pressure[..]);
        let external = self
            .model
            .residual(u_full, level, &mut self.r_full, k, tp)?;
        self.model.restrict(&self.r_full, &mut self.r_free);
        if self.homotopy_weight != 0.0 {
            let w = self.homotopy_weight;
            for (r, r0) in self.r_free.iter_mut().zip(&self.homotopy_r0) {
                *r -= w * r0;
            }
        }
        if let Some(st) = &self.stab {
            for (((r, c), u), u0) in self
                .r_free
                .iter_mut()
                .zip(&st.damping)
                .zip(u_free)
                .zip(&st.u_ref)
            {
                *r += st.scale * c * (u - u0);
            }
            if with_k {
                for (&p, c) in self.model.pattern().col_ptr.iter().zip(&st.damping) {
                    self.k[p] += st.scale * c;
                }
            }
        }
        self.assembly_seconds += t.elapsed().as_secs_f64();
        Ok(external)
    }
}

pub(super) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
