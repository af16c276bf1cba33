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

/// The residual over the iterations of one solve, for the tests that end a hopeless attempt.
struct Progress {
    /// Smallest residual from the second iteration on.
    best: f64,
    /// Residual of the previous iteration.
    previous: f64,
    /// Iterations in a row that barely reduced the residual.
    stalled: usize,
}

impl Progress {
    fn new() -> Self {
        Self {
            best: f64::INFINITY,
            previous: f64::INFINITY,
            stalled: 0,
        }
    }

    /// Records the residual norm `rn` (`normalised` by the force scale) of iteration `it`;
    /// true if the iteration diverges or stagnates far from the solution.
    fn hopeless(&mut self, it: usize, rn: f64, normalised: f64) -> bool {
        // the first Newton step may raise the residual by orders of magnitude (the
        // linearised rotations violate J = 1 at second order, see the module docs); from
        // then on the residual must come down
        if it >= 1 {
            self.best = self.best.min(rn);
        }
        if it >= 3 && rn > 10.0 * self.best {
            // diverging: give up early and let the step be cut back
            return true;
        }
        // stagnating far from the solution (two iterations in a row that barely reduce
        // the residual): Newton will not recover in the iterations left
        self.stalled = if it >= 2 && rn > STALL_RATIO * self.previous {
            self.stalled + 1
        } else {
            0
        };
        if self.stalled >= 2 && normalised > 1e-3 {
            return true;
        }
        self.previous = rn;
        false
    }
}

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
        let mut progress = Progress::new();
        self.use_tangent_pressure = false;
        // modified Newton (the last factor) while it contracts fast enough
        let mut modified = reuse && self.linear.has_factor();
        self.guard_residual = None;
        for it in 0..=self.settings.max_iterations {
            self.model.expand(&state.u_free, level, u_full);
            if self.converged_at_guard(state, level, it, &mut out) {
                return Ok(out);
            }
            let previous = progress.previous;
            let Some(ext) =
                self.assemble_iteration(state, level, u_full, it, &mut modified, previous)
            else {
                return Ok(out);
            };
            let (rn, scale) = self.measure(it, level, modified, ext, &mut out);
            if !rn.is_finite() {
                return Ok(out);
            }
            if self.meets_tolerance(state, level, it, rn, scale) {
                out.converged = true;
                return Ok(out);
            }
            if it == self.settings.max_iterations || progress.hopeless(it, rn, out.residual) {
                return Ok(out);
            }
            if !self.solve_step(modified) {
                return Ok(out);
            }
            let alpha = self.line_search(state, level, u_full);
            self.trace_step(alpha);
            let un = norm(&state.u_free).max(1e-12);
            out.update = alpha * norm(&self.du) / un;
            if alpha == 0.0 {
                return Ok(out);
            }
            self.take_step(state, level, u_full, alpha);
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

    /// The step guard already assembled the residual at this state: if it meets the
    /// tolerance, the tangent is not needed (same residual, same decision). Records the
    /// converged iteration in `out` and returns true then.
    fn converged_at_guard(
        &mut self,
        state: &PathState,
        level: &LoadLevel,
        it: usize,
        out: &mut NewtonOutcome,
    ) -> bool {
        let Some(ext) = self.guard_residual.take() else {
            return false;
        };
        let scale = ext.max(self.reaction_norm()).max(self.force_scale);
        let rn = norm(&self.r_free);
        if !self.meets_tolerance(state, level, it, rn, scale) {
            return false;
        }
        out.residual = rn / scale;
        out.iterations = it;
        out.converged = true;
        self.trace_residual(it, level, false, rn, scale, out.residual);
        true
    }

    /// The residual at the current state, with the tangent unless the last factor is reused
    /// (`modified`); if the modified iteration contracts too slowly (against the `previous`
    /// residual), the tangent of this state from here on. Returns the external force norm,
    /// `None` if an element is inverted.
    fn assemble_iteration(
        &mut self,
        state: &PathState,
        level: &LoadLevel,
        u_full: &[f64],
        it: usize,
        modified: &mut bool,
        previous: f64,
    ) -> Option<f64> {
        let mut ext = self
            .assemble(&state.u_free, u_full, level, !*modified)
            .ok()?;
        if *modified && it >= 1 && norm(&self.r_free) > REUSE_CONTRACTION * previous {
            // too slow: the tangent of this state from here on
            *modified = false;
            ext = self.assemble(&state.u_free, u_full, level, true).ok()?;
        }
        Some(ext)
    }

    /// The residual norm and the force scale it is measured against (kept for the
    /// convergence test of the caller); records the iteration in `out`.
    fn measure(
        &mut self,
        it: usize,
        level: &LoadLevel,
        modified: bool,
        ext: f64,
        out: &mut NewtonOutcome,
    ) -> (f64, f64) {
        let reactions = self.reaction_norm();
        let scale = ext.max(reactions).max(self.force_scale);
        self.last_force_scale = scale;
        let rn = norm(&self.r_free);
        out.residual = rn / scale;
        out.iterations = it;
        self.trace_residual(it, level, modified, rn, scale, out.residual);
        (rn, scale)
    }

    /// `|r| ≤ rtol · scale`, at iteration `it` > 0 unless the level is the state's own.
    fn meets_tolerance(
        &self,
        state: &PathState,
        level: &LoadLevel,
        it: usize,
        rn: f64,
        scale: f64,
    ) -> bool {
        rn <= self.settings.rtol * scale && (it > 0 || level_is_zero_increment(state, level))
    }

    /// Solves `K Δu = −r` into `du`, with the last factor if `modified`; false if the solve
    /// failed (the increment is then cut back).
    fn solve_step(&mut self, modified: bool) -> bool {
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
            return false;
        }
        true
    }

    /// `u ← u + α Δu`, with the mixed iteration's pressures carried to the new state.
    fn take_step(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
        alpha: f64,
    ) {
        if self.settings.mixed_tangent {
            self.carry_pressures(state, level, u_full, alpha);
        }
        for (u, d) in state.u_free.iter_mut().zip(&self.du) {
            *u += alpha * d;
        }
    }

    fn trace_residual(
        &self,
        it: usize,
        level: &LoadLevel,
        modified: bool,
        rn: f64,
        scale: f64,
        normalised: f64,
    ) {
        if self.settings.trace {
            eprintln!(
                "  newton {it:2}{}  level {level}  |r|/f = {normalised:.3e}  (|r| = {rn:.3e}, f = {scale:.3e})",
                if modified { " (reused factor)" } else { "" },
            );
        }
    }

    /// Traces where the largest component of the step is (reference position of its node).
    fn trace_step(&self, alpha: f64) {
        if !self.settings.trace {
            return;
        }
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
