//! Load control with adaptive substeps: the path from one output level to the next is cut
//! into increments that grow after easy ones and are halved after a failure, each solved by
//! Newton ([`super::newton`]) from the predictor's guess ([`super::predictor`]); where plain
//! load control keeps failing, the stabilised continuation takes over
//! ([`super::stabilization`]).

use super::problem::NonlinearProblem;
use super::settings::{SolverError, SolverSettings, StepReport};
use super::state::{PathState, STABILIZED_INCREMENT};
use super::Solver;
use crate::fe::assembly::LoadLevel;

impl<P: NonlinearProblem> Solver<'_, P> {
    /// Advances `state` to `target` with adaptive substeps.
    ///
    /// # Errors
    /// [`SolverError::NotConverged`] (with `completed = 0` and no reports: the caller fills
    /// them in) if the step fails after all cut-backs.
    pub fn advance(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
    ) -> Result<StepReport, SolverError> {
        let start = state.level;
        let dp = start.bounded_increment(&target);
        let mut frac = self.settings.initial_fraction.min(1.0);
        if dp > 0.0 {
            let first = self
                .last_increment
                .unwrap_or(self.settings.initial_pressure_increment);
            frac = frac.min(first.min(self.settings.max_pressure_increment) / dp);
        }
        let mut s = 0.0;
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
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        let mut consecutive_cuts = 0;
        let mut retry_plain = false;
        self.stab = None;
        while s < 1.0 - 1e-12 {
            let s_next = (s + frac).min(1.0);
            let level = start.lerp(&target, s_next);
            let saved = state.u_free.clone();
            let predicted = self.settings.predictor
                && !retry_plain
                && self.stab.is_none()
                && self.predict(state, &level);
            retry_plain = false;
            let out = self.newton(state, &level, false)?;
            report.newton_iterations += out.iterations;
            report.residual = out.residual;
            report.update = out.update;
            if !out.converged && predicted {
                // retry the same increment from the last converged state
                state.u_free = saved;
                retry_plain = true;
                continue;
            }
            if out.converged {
                if let Some(st) = &mut self.stab {
                    // the next substep is damped against this state; the predictor must not
                    // extrapolate across the jump
                    st.u_ref.copy_from_slice(&state.u_free);
                    state.history.clear();
                } else {
                    if state.history.len() == 2 {
                        state.history.remove(0);
                    }
                    state.history.push((saved, state.level));
                }
                state.level = level;
                s = s_next;
                report.substeps += 1;
                consecutive_cuts = 0;
                if dp > 0.0 {
                    self.last_increment = Some(frac * dp);
                }
                if out.iterations <= self.settings.grow_below_iterations {
                    frac *= 1.5;
                }
                if dp > 0.0 {
                    frac = frac.min(self.settings.max_pressure_increment / dp);
                }
            } else {
                state.u_free = saved;
                report.cutbacks += 1;
                consecutive_cuts += 1;
                // halve the increment actually tried (it may have been clipped to the end
                // of the step), so that the retry is a different, smaller one
                frac = 0.5 * (s_next - s);
                self.last_increment = None;
                if consecutive_cuts > self.settings.max_cutbacks
                    && self.stab.is_none()
                    && self.settings.stabilization > 0.0
                    && self.start_stabilization(state)
                {
                    // through the instability with the viscous term (module docs)
                    report.stabilized = true;
                    consecutive_cuts = 0;
                    frac = (STABILIZED_INCREMENT / dp.max(1e-300)).min(1.0 - s);
                    continue;
                }
                if consecutive_cuts > self.settings.max_cutbacks {
                    let origin = self.stab.take().map(|st| st.origin);
                    return Err(self.give_up(state, target, origin, report.cutbacks, out.residual));
                }
            }
        }
        let origin = self.stab.as_ref().map(|st| st.origin.clone());
        if origin.is_some() && !self.finish_stabilization(state, &target, &mut report)? {
            // the output level was reached only with the viscous term
            return Err(self.give_up(state, target, origin, report.cutbacks, report.residual));
        }
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        report.converged = true;
        report.factor_seconds = self.factor_seconds - f0;
        report.assembly_seconds = self.assembly_seconds - a0;
        report.factorizations = self.linear.factorizations - n0;
        Ok(report)
    }

    /// Ends a step that cannot reach `target`: back to the last undamped equilibrium
    /// (`origin`, where the stabilised continuation had moved on from it), and the error (its
    /// `completed` and `reports` are filled in by the caller).
    fn give_up(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
        origin: Option<(Vec<f64>, LoadLevel)>,
        cutbacks: usize,
        residual: f64,
    ) -> SolverError {
        if let Some(origin) = origin {
            (state.u_free, state.level) = origin;
            state.history.clear();
        }
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        SolverError::NotConverged {
            target: Box::new(target),
            reached: Box::new(state.level),
            cutbacks,
            residual,
            completed: 0,
            reports: Vec::new(),
        }
    }
}

/// Solves a model along a sequence of output levels starting from the undeformed state,
/// calling `observe` after every converged output step.
///
/// # Errors
/// [`SolverError::NotConverged`] carrying the reports of the steps that converged.
pub fn solve_path<P: NonlinearProblem>(
    model: &P,
    settings: SolverSettings,
    levels: &[LoadLevel],
    observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    let mut state = PathState::new(model);
    solve_path_from(model, settings, &mut state, levels, observe)
}

/// As [`solve_path`], continuing from a converged `state` (e.g. after a change of the
/// model's obstacles between two phases of a load path). With [`SolverKind::Minimise`] the
/// minimisation solver ([`super::minimise`]) drives the path instead.
///
/// # Errors
/// [`SolverError::NotConverged`] carrying the reports of the steps that converged.
pub fn solve_path_from<P: NonlinearProblem>(
    model: &P,
    settings: SolverSettings,
    state: &mut PathState,
    levels: &[LoadLevel],
    observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    super::warm::solve_path_guided(model, settings, state, levels, &[], observe)
}
