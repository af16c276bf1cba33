//! Augmented-Lagrangian contact: Uzawa updates of the contact gap shifts at a converged
//! output level, each followed by a Newton solve at the same load, so that the penalty's
//! contact surface moves onto the true one.

use super::problem::NonlinearProblem;
use super::settings::{SolverError, StepReport, AUGMENTED_GAP_TOL};
use super::state::PathState;
use super::Solver;
use crate::fe::assembly::LoadLevel;

impl<P: NonlinearProblem> Solver<'_, P> {
    /// Uzawa updates of the contact gap shifts at the converged `level`, each followed by a
    /// Newton solve at the same load (see [`super::settings::SolverSettings::augmented_updates`]).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] / [`SolverError::Element`] from the Newton solves. A
    /// solve that does not converge is not an error: the step keeps the state converged with
    /// the shifts before that update ([`StepReport::augmented_failed`]).
    pub fn augment(
        &mut self,
        state: &mut PathState,
        level: LoadLevel,
        report: &mut StepReport,
    ) -> Result<(), SolverError> {
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        for _ in 0..self.settings.augmented_updates {
            let saved = self.model.contact_shifts();
            let update = self
                .model
                .update_contact_shifts(&state.u_full, AUGMENTED_GAP_TOL);
            if self.settings.trace {
                eprintln!(
                    "  augmented update: {} points in contact, largest change {:.3e} mm",
                    update.active_points, update.max_change
                );
            }
            if !update.applied {
                break;
            }
            report.augmented_updates += 1;
            // one Newton solve at the same load (cutting back a zero load increment would
            // only repeat it)
            let saved_u = state.u_free.clone();
            let out = self.newton(state, &level, self.settings.reuse_factor)?;
            report.newton_iterations += out.iterations;
            if out.converged {
                report.residual = out.residual;
                report.update = out.update;
                self.model
                    .expand(&state.u_free, &state.level, &mut state.u_full);
                // the predictor's earlier states move with the correction (they were
                // converged with the previous shifts)
                for (h, _) in &mut state.history {
                    for ((hv, now), before) in h.iter_mut().zip(&state.u_free).zip(&saved_u) {
                        *hv += now - before;
                    }
                }
            } else {
                // the jump of contact pressures was too large for Newton: keep the state
                // converged with the previous shifts
                state.u_free = saved_u;
                self.model
                    .expand(&state.u_free, &state.level, &mut state.u_full);
                self.model.set_contact_shifts(&saved);
                report.augmented_failed = true;
                break;
            }
        }
        report.factor_seconds += self.factor_seconds - f0;
        report.assembly_seconds += self.assembly_seconds - a0;
        report.factorizations += self.linear.factorizations - n0;
        Ok(())
    }
}
