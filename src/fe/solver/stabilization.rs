//! Stabilised continuation through an instability: where an output step has been cut back
//! [`SolverSettings::max_cutbacks`](super::SolverSettings::max_cutbacks) times in a row, the
//! rest of it is taken with a viscous term `β · diag(K₀) · (u − u_prev)` (pseudo-time
//! stepping), and the output level is then relaxed at constant load until an undamped
//! equilibrium is found: only undamped equilibria are reported.

use super::problem::NonlinearProblem;
use super::settings::{SolverError, StepReport};
use super::state::{PathState, Stabilization};
use super::Solver;
use crate::fe::assembly::LoadLevel;

/// Stabilised relaxation steps at the output level, each followed by an undamped solve,
/// before the stabilised continuation gives up.
const MAX_RELAXATIONS: usize = 40;

impl<P: NonlinearProblem> Solver<'_, P> {
    /// Switches the stabilised continuation on at the converged `state`: the viscous
    /// coefficients from the diagonal of the tangent there. Returns false if that tangent
    /// cannot be assembled.
    pub(super) fn start_stabilization(&mut self, state: &mut PathState) -> bool {
        self.stab = None;
        self.use_tangent_pressure = false;
        let mut u_full = std::mem::take(&mut state.u_full);
        self.model.expand(&state.u_free, &state.level, &mut u_full);
        let ok = self
            .assemble(&state.u_free, &u_full, &state.level, true)
            .is_ok();
        state.u_full = u_full;
        if !ok {
            return false;
        }
        let pattern = self.model.pattern();
        let beta = self.settings.stabilization;
        let mut damping: Vec<f64> = (0..self.model.n_free())
            .map(|j| {
                let p = pattern.col_ptr[j];
                // rows are sorted and ≥ the column: the diagonal comes first
                debug_assert_eq!(pattern.row_idx[p], j);
                beta * self.k[p].abs()
            })
            .collect();
        let mean = damping.iter().sum::<f64>() / damping.len().max(1) as f64;
        for c in &mut damping {
            if *c <= 0.0 || !c.is_finite() {
                *c = mean;
            }
        }
        if self.settings.trace {
            eprintln!(
                "  stabilised continuation from {} (β = {beta:.1e})",
                state.level
            );
        }
        self.stab = Some(Stabilization {
            damping,
            u_ref: state.u_free.clone(),
            origin: (state.u_free.clone(), state.level),
            scale: 1.0,
        });
        true
    }

    /// End of a stabilised output step at `level`: pseudo-transient relaxation at the same
    /// load. Each relaxation step solves with the viscous term against the state before it;
    /// the term is then weakened fourfold (a longer pseudo-time step), or strengthened if the
    /// step failed. Once the viscous force of a step is below 1 % of the force scale, an
    /// undamped Newton solve is tried from there. Returns whether an undamped equilibrium was
    /// reached; the viscous term is off afterwards.
    pub(super) fn finish_stabilization(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        report: &mut StepReport,
    ) -> Result<bool, SolverError> {
        let Some(mut st) = self.stab.take() else {
            return Ok(true);
        };
        let mut try_undamped = true;
        for relaxation in 0..MAX_RELAXATIONS {
            if try_undamped {
                let saved = state.u_free.clone();
                let out = self.newton(state, level, false)?;
                report.newton_iterations += out.iterations;
                if self.settings.trace {
                    eprintln!(
                        "  undamped solve after {relaxation} relaxations (viscous scale {:.1e}): {}",
                        st.scale,
                        if out.converged { "converged" } else { "not converged" }
                    );
                }
                if out.converged {
                    report.residual = out.residual;
                    report.update = out.update;
                    return Ok(true);
                }
                state.u_free = saved;
            }
            st.u_ref.copy_from_slice(&state.u_free);
            self.stab = Some(st);
            let out = self.newton(state, level, false);
            st = self.stab.take().expect("set above");
            let out = out?;
            report.newton_iterations += out.iterations;
            if !out.converged {
                state.u_free.copy_from_slice(&st.u_ref);
                st.scale *= 4.0;
                try_undamped = false;
                if st.scale > 1e3 {
                    break;
                }
                continue;
            }
            // the viscous force of this step is what the undamped residual now is
            let viscous = st
                .damping
                .iter()
                .zip(&state.u_free)
                .zip(&st.u_ref)
                .map(|((c, u), u0)| (st.scale * c * (u - u0)).powi(2))
                .sum::<f64>()
                .sqrt();
            try_undamped = viscous <= 1e-2 * self.last_force_scale;
            st.scale *= 0.25;
        }
        Ok(false)
    }
}
