//! The static problem as the minimisation of its total potential.
//!
//! Every load of the actuator model is conservative (hyperelasticity, gravity, the cavity
//! pressure on a surface closed by the symmetry plane and the clamped face, frictionless
//! contact), so an equilibrium at a load level λ is a stationary point of one potential
//!
//! ```text
//!   Π(u; λ) = Σ_e ∫ W dV  −  p ΔV_cavity(u)  −  λ_g f_g · u  +  Σ_contact ∫ ψ(g) dA  (+ foundation)
//! ```
//!
//! whose gradient is the residual of [`super::NonlinearProblem::residual`] and whose Hessian is
//! its tangent ([`super::NonlinearProblem::potential`]). This solver minimises Π at each load
//! increment instead of zeroing the residual:
//!
//! - **Contact by a barrier.** The contact law is the clamped log barrier of
//!   [`crate::fe::assembly::terms::barrier`] (activation distance d̂ in mm): every state of
//!   finite Π has every gap strictly positive, and there are no multipliers to update, so no
//!   outer loop.
//! - **Descent directions.** The Newton system is factorised by Cholesky (LLᵀ). Where that
//!   fails (the tangent is not positive definite, as at the start of most increments: the
//!   follower pressure's load stiffness), the same tangent is factorised by LDLᵀ and its
//!   Newton direction kept if it descends on Π; otherwise the tangent is rebuilt from element
//!   tangents projected onto the positive semi-definite cone, then shifted on its diagonal
//!   until LLᵀ succeeds: the direction always descends on Π.
//! - **Step filter and line search on Π** ([`descent`]). A step is first shortened so that no
//!   contact gap reaches zero (a linear estimate of the time of impact per contact point,
//!   checked); full steps are then taken under a watchdog that requires Π to decrease within
//!   a few steps, and otherwise a backtracking Armijo search on Π takes over; once the
//!   decrease is below the round-off of Π the step is taken in full.
//! - **Load increments by iteration count.** An increment that took at most
//!   [`MinimiseSettings::target_iterations`] iterations is followed by one twice as large,
//!   one that took at most twice that by one 1.5 times as large; only a failed increment is
//!   halved (smaller increments do not need fewer iterations: each starts with the same
//!   overshoot of the first Newton step).
//!   Each increment starts from the path extrapolated in the load (as the residual solver's
//!   predictor), kept only where it has a lower Π than the last state.
//!
//! Convergence is tested exactly as in the residual Newton (‖r‖ ≤ rtol · force scale), so the
//! two solvers reach the same equilibria up to the contact law: the barrier's gap, within d̂,
//! against the augmented-Lagrangian penalty's.

pub mod descent;
pub mod outcome;

use std::time::Instant;

use super::linear::LinearSolver;
use super::problem::NonlinearProblem;
use super::settings::{MinimiseSettings, SolverError, SolverKind, SolverSettings, StepReport};
use super::state::PathState;
use crate::fe::assembly::LoadLevel;

/// Drives a problem along a load path by minimising its total potential.
pub struct Minimiser<'m, P: NonlinearProblem> {
    model: &'m P,
    linear: LinearSolver,
    settings: SolverSettings,
    opts: MinimiseSettings,
    r_full: Vec<f64>,
    r_free: Vec<f64>,
    k: Vec<f64>,
    diag: Vec<f64>,
    du: Vec<f64>,
    du_full: Vec<f64>,
    trial: Vec<f64>,
    trial_full: Vec<f64>,
    u_full: Vec<f64>,
    gaps0: Vec<f64>,
    gaps1: Vec<f64>,
    watch_u: Vec<f64>,
    tangent_pressure: Vec<[f64; 4]>,
    use_tangent_pressure: bool,
    /// Floor of the force scale (as in the residual Newton).
    force_scale: f64,
    factor_seconds: f64,
    assembly_seconds: f64,
    /// Pressure increment for the next substep (MPa).
    last_increment: Option<f64>,
    /// Directions from the LDLᵀ of a tangent that is not positive definite (descending).
    pub indefinite: usize,
    /// Tangents rebuilt from projected element tangents.
    pub projections: usize,
    /// Diagonal shifts of a projected tangent.
    pub shifts: usize,
}

impl<'m, P: NonlinearProblem> Minimiser<'m, P> {
    /// Prepares the solver (symbolic factorisation) for a problem.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if the symbolic analysis fails.
    pub fn new(model: &'m P, settings: SolverSettings) -> Result<Self, SolverError> {
        let opts = match settings.kind {
            SolverKind::Minimise(m) => m,
            SolverKind::Newton => MinimiseSettings::default(),
        };
        let (n, nf) = (model.n_free(), model.n_full());
        Ok(Self {
            model,
            linear: LinearSolver::new(model)?,
            settings,
            opts,
            r_full: vec![0.0; nf],
            r_free: vec![0.0; n],
            k: vec![0.0; model.pattern().nnz()],
            diag: vec![0.0; n],
            du: vec![0.0; n],
            du_full: vec![0.0; nf],
            trial: vec![0.0; n],
            trial_full: vec![0.0; nf],
            u_full: vec![0.0; nf],
            gaps0: Vec::new(),
            gaps1: Vec::new(),
            watch_u: vec![0.0; n],
            tangent_pressure: vec![[0.0; 4]; model.n_mixed_fields()],
            use_tangent_pressure: false,
            force_scale: model.force_floor(),
            factor_seconds: 0.0,
            assembly_seconds: 0.0,
            last_increment: None,
            indefinite: 0,
            projections: 0,
            shifts: 0,
        })
    }

    /// Π, the residual (into `r_full`, `r_free`) and, with `tangent`, the tangent (into `k`)
    /// at the full displacement `u_full`; `None` if the state is inadmissible (an inverted
    /// element; an infinite Π is returned as such).
    fn eval(
        &mut self,
        u_full: &[f64],
        level: &LoadLevel,
        tangent: bool,
        project: bool,
    ) -> Result<Option<(f64, f64)>, SolverError> {
        let t = Instant::now();
        let mixed = (tangent && self.use_tangent_pressure && !project)
            .then_some(&self.tangent_pressure[..]);
        let k = tangent.then_some(&mut self.k[..]);
        let res = self
            .model
            .potential(u_full, level, &mut self.r_full, k, mixed, project);
        self.assembly_seconds += t.elapsed().as_secs_f64();
        match res {
            Ok(Some(v)) => {
                self.model.restrict(&self.r_full, &mut self.r_free);
                Ok(Some(v))
            }
            Ok(None) => Err(SolverError::NoPotential),
            Err(_) => Ok(None),
        }
    }

    /// Advances `state` to `target` with adaptive increments, each a minimisation of Π.
    ///
    /// # Errors
    /// [`SolverError::NotConverged`] (with `completed = 0` and no reports: the caller fills
    /// them in) if an increment fails after [`SolverSettings::max_cutbacks`] halvings.
    pub fn advance(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
    ) -> Result<StepReport, SolverError> {
        let start = state.level;
        let dp = start.bounded_increment(&target);
        let max_increment = self.settings.max_pressure_increment;
        let max_frac = |dp: f64| {
            if dp > 0.0 {
                (max_increment / dp).min(1.0)
            } else {
                1.0
            }
        };
        let mut frac = self.settings.initial_fraction.min(1.0);
        if dp > 0.0 {
            let first = self
                .last_increment
                .unwrap_or(self.settings.initial_pressure_increment);
            frac = frac.min(first / dp).min(max_frac(dp));
        }
        let mut report = StepReport {
            level: target,
            newton_iterations: 0,
            substeps: 0,
            cutbacks: 0,
            residual: 0.0,
            update: 0.0,
            converged: false,
            factor_seconds: 0.0,
            assembly_seconds: 0.0,
            augmented_updates: 0,
            augmented_failed: false,
            factorizations: 0,
            stabilized: false,
            warm_start: false,
            homotopy_steps: 0,
        };
        let (f0, a0, n0) = (
            self.factor_seconds,
            self.assembly_seconds,
            self.linear.factorizations,
        );
        let target_its = self.opts.target_iterations;
        let (mut s, mut consecutive_cuts, mut retry_plain) = (0.0, 0, false);
        while s < 1.0 - 1e-12 {
            let s_next = (s + frac).min(1.0);
            let level = start.lerp(&target, s_next);
            let saved = state.u_free.clone();
            let predicted =
                self.settings.predictor && !retry_plain && self.predict(state, &level)?;
            retry_plain = false;
            let out = self.descend(state, &level)?;
            report.newton_iterations += out.iterations;
            report.residual = out.residual;
            report.update = out.update;
            if out.stop == outcome::Stop::Converged {
                if state.history.len() == 2 {
                    state.history.remove(0);
                }
                state.history.push((saved, state.level));
                state.level = level;
                s = s_next;
                report.substeps += 1;
                consecutive_cuts = 0;
                // the iterations of an increment do not fall below about 6–10 with smaller
                // increments (the first Newton step's second-order violation of J = 1, module
                // docs), so a converged increment is never shrunk: only a failed one is halved
                if out.iterations <= target_its {
                    frac *= 2.0;
                } else if out.iterations <= 2 * target_its {
                    frac *= 1.5;
                }
                frac = frac.min(max_frac(dp));
                if dp > 0.0 {
                    self.last_increment = Some(frac * dp);
                }
            } else if predicted {
                // the same increment from the last converged state
                state.u_free = saved;
                retry_plain = true;
            } else {
                state.u_free = saved;
                report.cutbacks += 1;
                consecutive_cuts += 1;
                frac = 0.5 * (s_next - s);
                self.last_increment = None;
                if consecutive_cuts > self.settings.max_cutbacks {
                    self.model
                        .expand(&state.u_free, &state.level, &mut state.u_full);
                    return Err(SolverError::NotConverged {
                        target: Box::new(target),
                        reached: Box::new(state.level),
                        cutbacks: report.cutbacks,
                        residual: out.residual,
                        completed: 0,
                        reports: Vec::new(),
                    });
                }
            }
        }
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        report.converged = true;
        report.factor_seconds = self.factor_seconds - f0;
        report.assembly_seconds = self.assembly_seconds - a0;
        report.factorizations = self.linear.factorizations - n0;
        Ok(report)
    }

    /// Moves `state.u_free` to the path extrapolated to `level` (quadratic through the last
    /// three converged states, linear through two) if that state is admissible and has a
    /// lower Π at `level` than the last converged state; returns whether it did.
    fn predict(&mut self, state: &mut PathState, level: &LoadLevel) -> Result<bool, SolverError> {
        let mut pred = std::mem::take(&mut self.trial);
        let ok = super::predictor::extrapolate(state, level, &mut pred).is_some();
        if !ok {
            // the scratch keeps its length
            pred.resize(self.model.n_free(), 0.0);
            self.trial = pred;
            return Ok(false);
        }
        let mut full = std::mem::take(&mut self.trial_full);
        self.model.expand(&state.u_free, level, &mut full);
        let last = self.eval(&full, level, false, false)?;
        self.model.expand(&pred, level, &mut full);
        let predicted = self.eval(&full, level, false, false)?;
        self.trial_full = full;
        let accept = match (last, predicted) {
            (Some((e0, _)), Some((e1, _))) => e1.is_finite() && e1 < e0,
            _ => false,
        };
        if self.settings.trace {
            eprintln!("  predictor: {}", if accept { "used" } else { "rejected" });
        }
        if accept {
            state.u_free.copy_from_slice(&pred);
        }
        self.trial = pred;
        Ok(accept)
    }
}

/// [`super::solve_path_from`] for [`SolverKind::Minimise`]: minimises the problem's total
/// potential at each output level in turn, continuing from `state`.
///
/// # Errors
/// [`SolverError::NotConverged`] carrying the reports of the steps that converged;
/// [`SolverError::NoPotential`] for a problem without a potential.
pub fn solve_path_from<P: NonlinearProblem>(
    model: &P,
    settings: SolverSettings,
    state: &mut PathState,
    levels: &[LoadLevel],
    mut observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    let mut solver = Minimiser::new(model, settings)?;
    let mut reports = Vec::with_capacity(levels.len());
    for (i, level) in levels.iter().enumerate() {
        match solver.advance(state, *level) {
            Ok(rep) => {
                observe(i, state, &rep);
                reports.push(rep);
            }
            Err(e) => return Err(e.after(reports)),
        }
    }
    Ok(reports)
}
