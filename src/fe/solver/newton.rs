//! Newton–Raphson on the free unknowns at one load level: `K Δu = −r`, an admissibility
//! guard (no inverted element), an optional line search on the directional residual, the
//! mixed iteration's carried pressures, and the tests that end a hopeless attempt early so
//! that the increment is cut back.

use super::problem::NonlinearProblem;
use super::settings::{SolverError, REUSE_CONTRACTION};
use super::state::{level_is_zero_increment, PathState};
use super::{dot, norm, Solver};
use crate::fe::assembly::LoadLevel;

/// How one Newton solve ended.
pub(super) struct NewtonOutcome {
    pub(super) converged: bool,
    pub(super) iterations: usize,
    pub(super) residual: f64,
    pub(super) update: f64,
}

/// A Newton iteration that keeps more than this share of the residual makes no progress.
const STALL_RATIO: f64 = 0.9;

impl<P: NonlinearProblem> Solver<'_, P> {
    pub(super) fn newton(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        reuse: bool,
    ) -> Result<NewtonOutcome, SolverError> {
        let mut u_full = std::mem::take(&mut state.u_full);
        let out = self.newton_inner(state, level, &mut u_full, reuse);
        state.u_full = u_full;
        out
    }

    fn newton_inner(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
        reuse: bool,
    ) -> Result<NewtonOutcome, SolverError> {
        let mut out = NewtonOutcome {
            converged: false,
            iterations: 0,
            residual: f64::INFINITY,
            update: f64::INFINITY,
        };
        let mut best_residual = f64::INFINITY;
        let mut previous_residual = f64::INFINITY;
        let mut stalled = 0;
        self.use_tangent_pressure = false;
        // modified Newton (the last factor) while it contracts fast enough
        let mut modified = reuse && self.linear.has_factor();
        self.guard_residual = None;
        for it in 0..=self.settings.max_iterations {
            self.model.expand(&state.u_free, level, u_full);
            // the step guard already assembled the residual at this state: if it meets the
            // tolerance, the tangent is not needed (same residual, same decision)
            if let Some(ext) = self.guard_residual.take() {
                let scale = ext.max(self.reaction_norm()).max(self.force_scale);
                let rn = norm(&self.r_free);
                if rn <= self.settings.rtol * scale
                    && (it > 0 || level_is_zero_increment(state, level))
                {
                    out.residual = rn / scale;
                    out.iterations = it;
                    out.converged = true;
                    if self.settings.trace {
                        eprintln!(
                            "  newton {it:2}  level p={:.4} g={:.2}  |r|/f = {:.3e}  (|r| = {rn:.3e}, f = {scale:.3e})",
                            level.pressure, level.gravity, out.residual
                        );
                    }
                    return Ok(out);
                }
            }
            let mut ext = match self.assemble(&state.u_free, u_full, level, !modified) {
                Ok(external) => external,
                Err(_) => return Ok(out),
            };
            if modified && it >= 1 && norm(&self.r_free) > REUSE_CONTRACTION * previous_residual {
                // too slow: the tangent of this state from here on
                modified = false;
                ext = match self.assemble(&state.u_free, u_full, level, true) {
                    Ok(external) => external,
                    Err(_) => return Ok(out),
                };
            }
            let reactions = self.reaction_norm();
            let scale = ext.max(reactions).max(self.force_scale);
            self.last_force_scale = scale;
            let rn = norm(&self.r_free);
            out.residual = rn / scale;
            out.iterations = it;
            if self.settings.trace {
                eprintln!(
                    "  newton {it:2}{}  level p={:.4} g={:.2}  |r|/f = {:.3e}  (|r| = {rn:.3e}, f = {scale:.3e})",
                    if modified { " (reused factor)" } else { "" },
                    level.pressure, level.gravity, out.residual
                );
            }
            if !rn.is_finite() {
                return Ok(out);
            }
            if rn <= self.settings.rtol * scale && (it > 0 || level_is_zero_increment(state, level))
            {
                out.converged = true;
                return Ok(out);
            }
            if it == self.settings.max_iterations {
                return Ok(out);
            }
            // the first Newton step may raise the residual by orders of magnitude (the
            // linearised rotations violate J = 1 at second order, see the module docs); from
            // then on the residual must come down
            if it >= 1 {
                best_residual = best_residual.min(rn);
            }
            if it >= 3 && rn > 10.0 * best_residual {
                // diverging: give up early and let the step be cut back
                return Ok(out);
            }
            // stagnating far from the solution (two iterations in a row that barely reduce
            // the residual): Newton will not recover in the iterations left
            stalled = if it >= 2 && rn > STALL_RATIO * previous_residual {
                stalled + 1
            } else {
                0
            };
            if stalled >= 2 && out.residual > 1e-3 {
                return Ok(out);
            }
            previous_residual = rn;
            for (d, r) in self.du.iter_mut().zip(&self.r_free) {
                *d = -r;
            }
            let t = std::time::Instant::now();
            let solved = if modified {
                self.linear.solve_factored(&mut self.du)
            } else {
                self.linear.solve(&self.k, &mut self.du)
            };
            self.factor_seconds += t.elapsed().as_secs_f64();
            if let Err(e) = solved {
                if self.settings.trace {
                    eprintln!("           {e}: cutting back");
                }
                return Ok(out);
            }
            let alpha = self.line_search(state, level, u_full);
            if self.settings.trace {
                // where the largest component of the step is (reference position of its node)
                let (imax, dmax) = self.du.iter().enumerate().fold((0, 0.0f64), |m, (i, v)| {
                    if v.abs() > m.1 {
                        (i, v.abs())
                    } else {
                        m
                    }
                });
                let at = self.model.describe_unknown(imax);
                eprintln!("           step |du|max = {dmax:.3e} at {at}, alpha = {alpha:.3}");
            }
            let un = norm(&state.u_free).max(1e-12);
            out.update = alpha * norm(&self.du) / un;
            if alpha == 0.0 {
                return Ok(out);
            }
            if self.settings.mixed_tangent {
                self.carry_pressures(state, level, u_full, alpha);
            }
            for (u, d) in state.u_free.iter_mut().zip(&self.du) {
                *u += alpha * d;
            }
            // converged on a tiny update after a full Newton step with a small residual
            if out.update < 1e-13 && rn <= 1e-4 * scale {
                out.converged = true;
                out.iterations = it + 1;
                self.model.expand(&state.u_free, level, u_full);
                return Ok(out);
            }
        }
        Ok(out)
    }

    /// Element pressures of the mixed iteration at `u + α Δu`, linearised about `u`.
    fn carry_pressures(
        &mut self,
        state: &PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
        alpha: f64,
    ) {
        self.model.expand(&state.u_free, level, u_full);
        self.model
            .expand_increment(&self.du, alpha, &mut self.du_full);
        self.use_tangent_pressure = self
            .model
            .mixed_fields(u_full, &self.du_full, &mut self.tangent_pressure)
            .is_ok();
    }

    fn reaction_norm(&self) -> f64 {
        self.model.reaction_norm(&self.r_full)
    }

    /// Returns the step length α ∈ (0, 1] (0 if no admissible step was found).
    ///
    /// `s(α) = Δu · r(u + αΔu)` is the directional derivative of the total potential; it is
    /// negative at α = 0. The full step is accepted while the potential still decreases there
    /// (`s(1) ≤ 0`) or has its minimum nearby (`|s| ≤ ½|s₀|`); otherwise regula falsi on `s`.
    fn line_search(&mut self, state: &PathState, level: &LoadLevel, u_full: &mut [f64]) -> f64 {
        self.guard_residual = None;
        let s0 = dot(&self.du, &self.r_free);
        let mut alpha = 1.0;
        let lo = (0.0, s0);
        let mut admissible = false;
        for _ in 0..16 {
            for ((t, u), d) in self.trial.iter_mut().zip(&state.u_free).zip(&self.du) {
                *t = u + alpha * d;
            }
            let trial = std::mem::take(&mut self.trial);
            self.model.expand(&trial, level, u_full);
            self.guard_residual = None;
            let assembled = self.assemble(&trial, u_full, level, false);
            self.trial = trial;
            let Ok(external) = assembled else {
                // det F guard: shorten the step until every element is admissible
                if admissible {
                    return lo.0;
                }
                alpha *= 0.5;
                continue;
            };
            admissible = true;
            let s = dot(&self.du, &self.r_free);
            if !self.settings.line_search || s0 >= 0.0 || s <= 0.0 || s.abs() <= 0.5 * s0.abs() {
                // the residual at the state the step moves to is in `r_full` / `r_free`
                self.guard_residual = Some(external);
                return alpha;
            }
            // overshoot: minimum between lo.0 and alpha
            let hi = (alpha, s);
            let a = lo.0 + (hi.0 - lo.0) * (-lo.1) / (hi.1 - lo.1);
            alpha = a.clamp(lo.0 + 0.1 * (hi.0 - lo.0), lo.0 + 0.9 * (hi.0 - lo.0));
            if alpha < 1e-3 {
                return alpha;
            }
        }
        if admissible {
            alpha
        } else {
            0.0
        }
    }
}
