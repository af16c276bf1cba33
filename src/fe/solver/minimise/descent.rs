//! One load increment of the minimisation: Newton directions that descend on Π (LLᵀ, with
//! the indefinite tangent's LDLᵀ, the projected and the shifted tangents as fallbacks), a
//! step filter that keeps every contact gap positive, and a watchdog line search on Π.
//!
//! The watchdog: with κ = 1000 μ0, a Newton step along the soft bending mode is a linearised
//! rotation whose second-order violation of J = 1 raises Π although the iteration converges
//! (the Maratos effect of a penalised constraint); an Armijo search on Π then cuts such
//! steps to a few percent and needs tens of iterations per increment. So full admissible
//! steps are taken (gaps positive, no inverted element, Π finite) as long as, within
//! `WATCHDOG_STEPS` (8) steps, Π falls below its value where the watch began by the Armijo
//! decrease of the first step; otherwise the increment returns to that state and continues
//! with a backtracking Armijo line search on Π (monotone, hence convergent).

use std::time::Instant;

use super::super::problem::NonlinearProblem;
use super::super::settings::SolverError;
use super::super::state::PathState;
use super::super::{dot, norm};
use super::outcome::{Outcome, Stop};
use super::Minimiser;
use crate::fe::assembly::LoadLevel;

/// Armijo constant of the sufficient decrease `Π(u + αd) ≤ Π(u) + c α ∇Π·d`.
const ARMIJO: f64 = 1e-4;
/// Share of the estimated time of impact a step may take (the contact step filter).
const IMPACT_SHARE: f64 = 0.8;
/// Relative round-off of Π below which a decrease is not resolved.
const ENERGY_NOISE: f64 = 1e-11;
/// Full (admissible) steps the watchdog allows before Π must have decreased below its
/// reference (Chamberlain, Powell, Lemaréchal & Pedersen 1982).
const WATCHDOG_STEPS: usize = 8;

/// The watchdog of the full steps (see the module docs).
struct Watchdog {
    /// `(Π, required decrease, iteration)` at the reference state, while watching.
    reference: Option<(f64, f64, usize)>,
    /// Whether the increment has fallen back to the line search on Π.
    monotone: bool,
}

impl Watchdog {
    fn new() -> Self {
        Self {
            reference: None,
            monotone: false,
        }
    }

    /// Takes the state of iteration `it` (Π = `energy`, `∇Π·d = gd`) as the reference unless
    /// one is watched already; true if it did.
    fn watch(&mut self, energy: f64, gd: f64, it: usize) -> bool {
        if self.reference.is_some() {
            return false;
        }
        self.reference = Some((energy, ARMIJO * gd, it));
        true
    }

    /// After the step of iteration `it` to Π = `energy`: ends the watch if Π fell below the
    /// reference by the required decrease; returns the number of steps since the reference
    /// if the full steps did not decrease Π within [`WATCHDOG_STEPS`].
    fn expired(&mut self, it: usize, energy: f64) -> Option<usize> {
        let (e_ref, decrease, since) = self.reference?;
        if energy <= e_ref + decrease {
            self.reference = None;
            None
        } else if it + 1 - since >= WATCHDOG_STEPS {
            Some(it + 1 - since)
        } else {
            None
        }
    }

    /// A line search on Π from the reference state on.
    fn fall_back(&mut self) {
        self.monotone = true;
        self.reference = None;
    }
}

impl<P: NonlinearProblem> Minimiser<'_, P> {
    /// Minimises Π at `level` from `state.u_free` (changed in place).
    ///
    /// # Errors
    /// [`SolverError::NoPotential`]; [`SolverError::Factorization`] on a non-finite solve.
    pub(super) fn descend(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
    ) -> Result<Outcome, SolverError> {
        let mut u_full = std::mem::take(&mut self.u_full);
        let out = self.descend_inner(state, level, &mut u_full);
        self.u_full = u_full;
        out
    }

    fn descend_inner(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        u_full: &mut Vec<f64>,
    ) -> Result<Outcome, SolverError> {
        let mut out = Outcome {
            stop: Stop::MaxIterations,
            iterations: 0,
            residual: f64::INFINITY,
            update: f64::INFINITY,
        };
        let Some((mut energy, mut ext)) = self.start(state, level, u_full)? else {
            out.stop = Stop::Inadmissible;
            return Ok(out);
        };
        let mut watchdog = Watchdog::new();
        for it in 0..=self.settings.max_iterations {
            let (rn, scale) = self.measure(it, level, energy, ext, &mut out);
            if let Some(stop) = self.stop_before_step(it, rn, scale) {
                out.stop = stop;
                return Ok(out);
            }
            let Some(gd) = self.direction(u_full, level)? else {
                out.stop = Stop::NoDescent;
                return Ok(out);
            };
            let alpha_max = self.step_bound(&state.u_free, u_full, level);
            let step = if watchdog.monotone {
                self.line_search(&state.u_free, level, energy, gd, alpha_max, scale)?
            } else {
                if watchdog.watch(energy, gd, it) {
                    // the watchdog's reference: this state and its sufficient decrease
                    self.watch_u.clone_from(&state.u_free);
                }
                self.admissible_step(&state.u_free, level, alpha_max)?
            };
            let Some((alpha, e_new, ext_new)) = step else {
                out.stop = Stop::LineSearch;
                return Ok(out);
            };
            self.trace_step(alpha_max, alpha, energy, e_new, gd);
            self.accept_trial(state, u_full, alpha);
            (energy, ext) = (e_new, ext_new);
            if let Some(steps) = watchdog.expired(it, energy) {
                // the full steps did not decrease Π: back to the reference state, and a
                // line search on Π from there on
                let Some(back) = self.back_to_watch(state, level, u_full, steps)? else {
                    out.stop = Stop::Inadmissible;
                    return Ok(out);
                };
                (energy, ext) = back;
                watchdog.fall_back();
                continue;
            }
            let un = norm(&state.u_free).max(1e-12);
            out.update = alpha * norm(&self.du) / un;
            if out.update < 1e-13 && rn <= 1e-4 * scale {
                out.stop = Stop::Converged;
                out.iterations = it + 1;
                return Ok(out);
            }
        }
        Ok(out)
    }

    /// Π and the residual at the increment's starting state (without the mixed iteration's
    /// pressures): `(Π, external force norm)`, or `None` if it is inadmissible.
    fn start(
        &mut self,
        state: &PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
    ) -> Result<Option<(f64, f64)>, SolverError> {
        self.use_tangent_pressure = false;
        self.model.expand(&state.u_free, level, u_full);
        Ok(self
            .eval(u_full, level, false, false)?
            .filter(|&(e, _)| e.is_finite()))
    }

    /// The residual norm and the force scale it is measured against; records the iteration
    /// in `out`.
    fn measure(
        &self,
        it: usize,
        level: &LoadLevel,
        energy: f64,
        ext: f64,
        out: &mut Outcome,
    ) -> (f64, f64) {
        let reactions = self.model.reaction_norm(&self.r_full);
        let scale = ext.max(reactions).max(self.force_scale);
        let rn = norm(&self.r_free);
        out.residual = rn / scale;
        out.iterations = it;
        if self.settings.trace {
            eprintln!(
                "  minimise {it:2}  level {level}  |r|/f = {:.3e}  Π = {energy:.10e}",
                out.residual
            );
        }
        (rn, scale)
    }

    /// How iteration `it` ends the increment before a step, if it does: a non-finite
    /// residual, convergence, or the last iteration.
    fn stop_before_step(&self, it: usize, rn: f64, scale: f64) -> Option<Stop> {
        if !rn.is_finite() {
            Some(Stop::NotFinite)
        } else if rn <= self.settings.rtol * scale {
            Some(Stop::Converged)
        } else if it == self.settings.max_iterations {
            Some(Stop::MaxIterations)
        } else {
            None
        }
    }

    /// Moves to the accepted step `u + α Δu` (in `trial` / `trial_full`); with the mixed
    /// iteration, the element pressures there, linearised about `u`.
    fn accept_trial(&mut self, state: &mut PathState, u_full: &mut Vec<f64>, alpha: f64) {
        if self.settings.mixed_tangent {
            self.model
                .expand_increment(&self.du, alpha, &mut self.du_full);
            self.use_tangent_pressure = self
                .model
                .mixed_fields(u_full, &self.du_full, &mut self.tangent_pressure)
                .is_ok();
        }
        std::mem::swap(&mut state.u_free, &mut self.trial);
        std::mem::swap(u_full, &mut self.trial_full);
    }

    /// Returns to the watchdog's reference state (`steps` back), without the mixed
    /// iteration's pressures: its `(Π, external force norm)`, or `None` if it is
    /// inadmissible.
    fn back_to_watch(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
        steps: usize,
    ) -> Result<Option<(f64, f64)>, SolverError> {
        if self.settings.trace {
            eprintln!("           watchdog: Π not decreased, back {steps} steps");
        }
        state.u_free.clone_from(&self.watch_u);
        self.model.expand(&state.u_free, level, u_full);
        let back = self.eval(u_full, level, false, false)?;
        if back.is_some() {
            self.use_tangent_pressure = false;
        }
        Ok(back)
    }

    fn trace_step(&self, alpha_max: f64, alpha: f64, energy: f64, e_new: f64, gd: f64) {
        if self.settings.trace {
            eprintln!(
                "           step bound {alpha_max:.3e}, alpha = {alpha:.3e}, ΔΠ = {:.3e} (∇Π·d = {gd:.3e})",
                e_new - energy
            );
        }
    }

    /// A direction `du` with `∇Π·du < 0`: the Newton direction of the tangent by LLᵀ; if the
    /// tangent is not positive definite, the Newton direction by LDLᵀ of the same tangent
    /// (the residual Newton's, kept where it descends); then that of the tangent of projected
    /// element tangents; then of that one shifted by `μ·diag` (μ = 1e-6 … 1). Returns `∇Π·du`,
    /// or `None` if all fail.
    fn direction(&mut self, u_full: &[f64], level: &LoadLevel) -> Result<Option<f64>, SolverError> {
        for attempt in 0..6 {
            match attempt {
                0 => {
                    if self.eval(u_full, level, true, false)?.is_none() {
                        return Ok(None);
                    }
                }
                1 => {}
                2 => {
                    self.projections += 1;
                    if self.eval(u_full, level, true, true)?.is_none() {
                        return Ok(None);
                    }
                    for (c, d) in self.diag.iter_mut().enumerate() {
                        *d = self.k[self.model.pattern().col_ptr[c]];
                    }
                }
                _ => {
                    self.shifts += 1;
                    let mu = 1e-6 * 100f64.powi(attempt - 3);
                    let cp = &self.model.pattern().col_ptr;
                    let dmax = self.diag.iter().fold(0.0f64, |m, d| m.max(d.abs()));
                    for (c, d) in self.diag.iter().enumerate() {
                        self.k[cp[c]] = d + mu * d.abs().max(1e-12 * dmax);
                    }
                }
            }
            for (d, r) in self.du.iter_mut().zip(&self.r_free) {
                *d = -r;
            }
            let t = Instant::now();
            let ok = if attempt == 1 {
                // the indefinite tangent as it is (LDLᵀ); a failed solve is not fatal here
                self.linear.solve(&self.k, &mut self.du).is_ok()
                    && self.du.iter().all(|v| v.is_finite())
            } else {
                self.linear.solve_llt(&self.k, &mut self.du)?
            };
            self.factor_seconds += t.elapsed().as_secs_f64();
            if ok {
                let gd = dot(&self.r_free, &self.du);
                if gd < 0.0 {
                    if attempt == 1 {
                        self.indefinite += 1;
                    }
                    return Ok(Some(gd));
                }
            }
            if self.settings.trace {
                eprintln!(
                    "           direction attempt {attempt}: {}",
                    if ok {
                        "not a descent direction"
                    } else if attempt == 1 {
                        "LDLᵀ failed"
                    } else {
                        "tangent not positive definite"
                    }
                );
            }
        }
        Ok(None)
    }

    /// The longest step `α ≤ 1` along `du` that keeps every contact gap positive: per contact
    /// point that the full step would close, [`IMPACT_SHARE`] of its linear time of impact;
    /// halved until the gaps at the step are all positive.
    fn step_bound(&mut self, u_free: &[f64], u_full: &[f64], level: &LoadLevel) -> f64 {
        let mut gaps0 = std::mem::take(&mut self.gaps0);
        let mut gaps1 = std::mem::take(&mut self.gaps1);
        self.model.contact_gaps(u_full, &mut gaps0);
        let mut alpha = 1.0f64;
        if !gaps0.is_empty() {
            self.trial_at(u_free, 1.0, level);
            self.model.contact_gaps(&self.trial_full, &mut gaps1);
            for (&g0, &g1) in gaps0.iter().zip(&gaps1) {
                if g0 > 0.0 && g0.is_finite() && g1 <= 0.0 {
                    alpha = alpha.min(IMPACT_SHARE * g0 / (g0 - g1));
                }
            }
            for _ in 0..40 {
                self.trial_at(u_free, alpha, level);
                self.model.contact_gaps(&self.trial_full, &mut gaps1);
                let closed = gaps0
                    .iter()
                    .zip(&gaps1)
                    .any(|(&g0, &g1)| g0 > 0.0 && g1 <= 0.0);
                if !closed {
                    break;
                }
                alpha *= 0.5;
            }
        }
        self.gaps0 = gaps0;
        self.gaps1 = gaps1;
        alpha
    }

    /// The longest admissible step from `alpha_max` (halved until no element is inverted and
    /// Π is finite), without a decrease condition: the watchdog's full steps. Leaves the state
    /// as [`Self::line_search`] does.
    fn admissible_step(
        &mut self,
        u_free: &[f64],
        level: &LoadLevel,
        alpha_max: f64,
    ) -> Result<Option<(f64, f64, f64)>, SolverError> {
        let mut alpha = alpha_max;
        for _ in 0..40 {
            self.trial_at(u_free, alpha, level);
            let full = std::mem::take(&mut self.trial_full);
            let res = self.eval(&full, level, false, false)?;
            self.trial_full = full;
            if let Some((e, ext)) = res {
                if e.is_finite() {
                    return Ok(Some((alpha, e, ext)));
                }
            }
            alpha *= 0.5;
        }
        Ok(None)
    }

    /// `trial = u_free + α du` and its full vector at `level`.
    fn trial_at(&mut self, u_free: &[f64], alpha: f64, level: &LoadLevel) {
        for ((t, u), d) in self.trial.iter_mut().zip(u_free).zip(&self.du) {
            *t = u + alpha * d;
        }
        self.model.expand(&self.trial, level, &mut self.trial_full);
    }

    /// Backtracking from `alpha_max` until `Π(u + αd) ≤ Π(u) + c α ∇Π·d` (Armijo), or until
    /// the decrease is below the round-off of Π and Π has not grown beyond it; the next α is
    /// the minimiser of the quadratic through Π(0), ∇Π·d and Π(α), kept in [α/10, α/2].
    /// Leaves the accepted state in `trial` / `trial_full` and its residual in `r_full` /
    /// `r_free`; returns `(α, Π, external force norm)` or `None`.
    fn line_search(
        &mut self,
        u_free: &[f64],
        level: &LoadLevel,
        e0: f64,
        gd: f64,
        alpha_max: f64,
        scale: f64,
    ) -> Result<Option<(f64, f64, f64)>, SolverError> {
        let noise = ENERGY_NOISE * (e0.abs() + scale);
        let mut alpha = alpha_max;
        for _ in 0..40 {
            self.trial_at(u_free, alpha, level);
            let full = std::mem::take(&mut self.trial_full);
            let res = self.eval(&full, level, false, false)?;
            self.trial_full = full;
            match res {
                Some((e, ext)) if e.is_finite() => {
                    let armijo = e <= e0 + ARMIJO * alpha * gd;
                    let in_noise = -alpha * gd <= noise && e - e0 <= noise;
                    if armijo || in_noise {
                        return Ok(Some((alpha, e, ext)));
                    }
                    let curvature = e - e0 - gd * alpha;
                    let quad = if curvature > 0.0 {
                        -gd * alpha * alpha / (2.0 * curvature)
                    } else {
                        0.5 * alpha
                    };
                    alpha = quad.clamp(0.1 * alpha, 0.5 * alpha);
                }
                _ => alpha *= 0.5,
            }
            if alpha < 1e-12 {
                break;
            }
        }
        Ok(None)
    }
}
