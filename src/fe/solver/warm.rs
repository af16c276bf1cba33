//! Warm starts across cases: an output level solved by Newton directly from a guess (the
//! converged state of a neighbouring case at the same level, on the same mesh, moved by its
//! first-order sensitivities where they are known), instead of the path from the previous
//! level in adaptive increments.
//!
//! In a campaign (a calibration's iterations, a material or design sweep) the solution at a
//! neighbouring parameter point is already known. From the undeformed state each level costs
//! a load path whose first iterations are slow (the linearised rotations of the soft bending
//! mode violate J = 1 at second order, see [`super`]); from a neighbour's converged state,
//! shifted by `(∂u/∂θ) Δθ`, Newton starts close to the quadratic phase.
//!
//! **Where Newton fails from the guess** (the neighbour too far away in the parameters, or an
//! element inverts), the level is tried in this order ([`solve_path_guided`]):
//!
//! 1. Newton from the guess's second start ([`LevelGuess::fallback`], the neighbour's state
//!    as it is where the first start was moved by the sensitivities), if it has one;
//! 2. a Newton homotopy ([`Solver::homotopy`]), a continuation in the parameter that needs
//!    nothing from the model but its residual: with `u₀` the start with the smaller residual
//!    and `r₀ = r(u₀)` that residual on the free unknowns (this case's model, the target
//!    level, the guess's contact gap shifts), `r(u) = (1 − t) r₀` is solved for `t` from 0
//!    (where `u₀` is the solution) to 1 (the problem itself). Each step is a Newton solve from
//!    the solution of the step before; the first step is a quarter of the way, a step
//!    that converged in at most four iterations is followed by one twice as long, a step that
//!    failed is retried at half the length from the state before it, and after four halvings
//!    the homotopy gives up. Steps before `t = 1` are solved to a normalised residual of
//!    1e-3 (they only carry the state along); `t = 1` to the settings' tolerance;
//! 3. the load path from this case's previous level, as if no guess had been given.
//!
//! Whatever was tried before the level was reached, its Newton iterations are counted in
//! the step's report ([`StepReport::newton_iterations`]), the homotopy's solves in
//! [`StepReport::homotopy_steps`].
//!
//! **Same answers.** The guess only starts the iteration: Newton at the output level converges
//! to the same residual tolerance as the path does (the homotopy's last step included), and
//! the augmented-Lagrangian updates then run as after any step (starting from the neighbour's
//! contact gap shifts, which are already close to the multipliers of this case). A start that
//! fails leaves the state and the contact gap shifts as they were.
//!
//! The guess carries the neighbour's contact gap shifts: a guess from another model (another
//! number of unknowns or contact points) is not used ([`LevelGuess::fits`]). A guess carried
//! from another mesh whose contact faces do not correspond has no shifts, and starts from the
//! model's own ([`LevelGuess::shifts`]).

use super::newton::NewtonOutcome;
use super::problem::NonlinearProblem;
use super::settings::{SolverError, SolverKind, SolverSettings, StepReport};
use super::state::PathState;
use super::{norm, Solver};
use crate::fe::assembly::LoadLevel;

/// A starting point for one output level: a converged state of a neighbouring case.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelGuess {
    /// Full displacement vector.
    pub u_full: Vec<f64>,
    /// The contact gap shifts (augmented-Lagrangian multipliers) to start with; empty: the
    /// model's shifts as they are when the level is reached (those the load path starts it
    /// from), for a guess carried from another mesh whose contact faces do not correspond
    /// ([`crate::fe::warm_start::transfer`]).
    pub shifts: Vec<f64>,
    /// A second start tried if Newton fails from `u_full` (the neighbour's state as it is,
    /// when `u_full` was extrapolated from it), before the homotopy and the load path.
    pub fallback: Option<Vec<f64>>,
}

impl LevelGuess {
    /// Whether this guess belongs to a model of `model`'s size: the same number of unknowns
    /// and of contact points (or no shifts, [`Self::shifts`]).
    pub fn fits(&self, model: &impl NonlinearProblem) -> bool {
        self.u_full.len() == model.n_full()
            && (self.shifts.is_empty() || self.shifts.len() == model.contact_shifts().len())
    }
}

/// What a warm start that did not reach its level spent: the Newton iterations and the
/// homotopy's solves (0 for a direct jump).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Spent {
    /// Newton iterations.
    pub iterations: usize,
    /// Newton solves of the homotopy, the halved ones included.
    pub homotopy_steps: usize,
}

/// The homotopy's first step of `t`.
const HOMOTOPY_FIRST_STEP: f64 = 0.25;

/// A homotopy step that converged in at most this many Newton iterations is followed by one
/// [`HOMOTOPY_GROWTH`] times as long.
const HOMOTOPY_EASY_ITERATIONS: usize = 4;

/// Growth of the homotopy's step after an easy one.
const HOMOTOPY_GROWTH: f64 = 2.0;

/// Halvings of the homotopy's step after which it gives up.
// public for the tests in tests/fe/
#[doc(hidden)]
pub const HOMOTOPY_MAX_HALVINGS: usize = 4;

/// Normalised residual tolerance of the homotopy's steps before `t = 1` (the settings'
/// `rtol` where that is looser); `t = 1` is solved to the settings' `rtol`.
const HOMOTOPY_INTERMEDIATE_RTOL: f64 = 1e-3;

impl<P: NonlinearProblem> Solver<'_, P> {
    /// Solves `target` by Newton from `guess`. On success `state` is at `target` (the state it
    /// left is kept for the predictor) and the report is returned; otherwise `state` and the
    /// contact shifts are as before and `None` is returned with the iterations spent.
    ///
    /// # Errors
    /// A failed factorisation.
    pub fn jump(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
        guess: &LevelGuess,
    ) -> Result<Result<StepReport, usize>, SolverError> {
        self.jump_from(state, target, &guess.u_full, &guess.shifts)
    }

    /// [`Self::jump`] from the full displacement `u_full` with the contact gap shifts `shifts`.
    fn jump_from(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
        u_full: &[f64],
        shifts: &[f64],
    ) -> Result<Result<StepReport, usize>, SolverError> {
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        let saved_u = state.u_free.clone();
        let saved_shifts = self.model.contact_shifts();
        self.model.restrict(u_full, &mut state.u_free);
        if !shifts.is_empty() {
            self.model.set_contact_shifts(shifts);
        }
        self.stab = None;
        let out = self.newton(state, &target, false)?;
        if self.settings.trace {
            eprintln!(
                "  warm start at {target}: {} after {} iterations",
                if out.converged { "converged" } else { "failed" },
                out.iterations
            );
        }
        if !out.converged {
            state.u_free = saved_u;
            self.model.set_contact_shifts(&saved_shifts);
            self.model
                .expand(&state.u_free, &state.level, &mut state.u_full);
            return Ok(Err(out.iterations));
        }
        Ok(Ok(self.arrive(
            state,
            target,
            saved_u,
            out,
            (f0, a0, n0),
            0,
        )))
    }

    /// Solves `target` by a Newton homotopy from the start among `starts` (full displacements)
    /// with the smallest residual, with the contact gap shifts `shifts`: with `r₀` the
    /// residual there, `r(u) = (1 − t) r₀` is solved for `t` stepping from 0 to 1, each step
    /// by Newton from the solution of the step before; a step that fails is halved (from the
    /// state before it), one that converges quickly is followed by a larger one. `t = 1` is
    /// the problem itself, solved to the settings' tolerance. On success `state` is at
    /// `target` as after [`Self::jump`]; after too many halvings `state` and the contact
    /// shifts are as before and what was spent is returned.
    ///
    /// # Errors
    /// A failed factorisation.
    pub fn homotopy(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
        starts: &[&[f64]],
        shifts: &[f64],
    ) -> Result<Result<StepReport, Spent>, SolverError> {
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        let saved_u = state.u_free.clone();
        let saved_shifts = self.model.contact_shifts();
        if !shifts.is_empty() {
            self.model.set_contact_shifts(shifts);
        }
        self.stab = None;
        self.homotopy_weight = 0.0;
        self.homotopy_r0.resize(self.model.n_free(), 0.0);
        // r₀ at the start with the smallest residual
        let mut u_full = std::mem::take(&mut state.u_full);
        let mut best: Option<(usize, f64)> = None;
        for (k, u0) in starts.iter().enumerate() {
            self.model.restrict(u0, &mut state.u_free);
            self.model.expand(&state.u_free, &target, &mut u_full);
            if self
                .assemble(&state.u_free, &u_full, &target, false)
                .is_err()
            {
                continue;
            }
            let rn = norm(&self.r_free);
            if rn.is_finite() && best.is_none_or(|(_, b)| rn < b) {
                self.homotopy_r0.copy_from_slice(&self.r_free);
                best = Some((k, rn));
            }
        }
        state.u_full = u_full;
        let outcome = match best {
            Some((k, _)) => {
                self.model.restrict(starts[k], &mut state.u_free);
                let walked = self.homotopy_walk(state, &target);
                self.homotopy_weight = 0.0;
                walked?
            }
            None => (None, Spent::default()),
        };
        let (out, spent) = outcome;
        if self.settings.trace {
            eprintln!(
                "  homotopy at {target}: {} after {} steps, {} iterations",
                if out.is_some() {
                    "converged"
                } else {
                    "failed, along the path instead"
                },
                spent.homotopy_steps,
                spent.iterations
            );
        }
        let Some(mut out) = out else {
            state.u_free = saved_u;
            self.model.set_contact_shifts(&saved_shifts);
            self.model
                .expand(&state.u_free, &state.level, &mut state.u_full);
            return Ok(Err(spent));
        };
        out.iterations = spent.iterations;
        Ok(Ok(self.arrive(
            state,
            target,
            saved_u,
            out,
            (f0, a0, n0),
            spent.homotopy_steps,
        )))
    }

    /// The homotopy's steps from `state.u_free` (its start, `r₀` in `homotopy_r0`): the last
    /// Newton outcome if `t = 1` was reached, and what was spent.
    fn homotopy_walk(
        &mut self,
        state: &mut PathState,
        target: &LoadLevel,
    ) -> Result<(Option<NewtonOutcome>, Spent), SolverError> {
        let rtol = self.settings.rtol;
        let mut spent = Spent::default();
        let (mut t, mut dt, mut halvings) = (0.0, HOMOTOPY_FIRST_STEP, 0);
        // the solution at t, restored when a step fails
        let mut at_t = state.u_free.clone();
        loop {
            let mut t_next = t + dt;
            if t_next > 1.0 - 1e-9 {
                t_next = 1.0;
            }
            self.homotopy_weight = 1.0 - t_next;
            if t_next < 1.0 {
                self.settings.rtol = rtol.max(HOMOTOPY_INTERMEDIATE_RTOL);
            }
            let out = self.newton(state, target, false);
            self.settings.rtol = rtol;
            let out = out?;
            spent.iterations += out.iterations;
            spent.homotopy_steps += 1;
            if self.settings.trace {
                eprintln!(
                    "  homotopy t = {t_next:.4}: {} after {} iterations",
                    if out.converged { "converged" } else { "failed" },
                    out.iterations
                );
            }
            if out.converged {
                if t_next == 1.0 {
                    return Ok((Some(out), spent));
                }
                at_t.copy_from_slice(&state.u_free);
                let taken = t_next - t;
                t = t_next;
                dt = if out.iterations <= HOMOTOPY_EASY_ITERATIONS {
                    HOMOTOPY_GROWTH * taken
                } else {
                    taken
                };
            } else {
                state.u_free.copy_from_slice(&at_t);
                halvings += 1;
                if halvings > HOMOTOPY_MAX_HALVINGS {
                    return Ok((None, spent));
                }
                dt = 0.5 * (t_next - t);
            }
        }
    }

    /// `state` moves to `target`, where Newton (`out`) converged from another start than the
    /// previous level (`saved_u`); the step's report.
    fn arrive(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
        saved_u: Vec<f64>,
        out: NewtonOutcome,
        (f0, a0, n0): (f64, f64, usize),
        homotopy_steps: usize,
    ) -> StepReport {
        if state.history.len() == 2 {
            state.history.remove(0);
        }
        state.history.push((saved_u, state.level));
        state.level = target;
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        StepReport {
            level: target,
            newton_iterations: out.iterations,
            substeps: 1,
            cutbacks: 0,
            residual: out.residual,
            update: out.update,
            converged: true,
            factor_seconds: self.factor_seconds - f0,
            assembly_seconds: self.assembly_seconds - a0,
            augmented_updates: 0,
            augmented_failed: false,
            factorizations: self.linear.factorizations - n0,
            stabilized: false,
            warm_start: true,
            homotopy_steps,
        }
    }
}

/// As [`super::solve_path_from`], with an optional guess per level (`guesses[i]` for
/// `levels[i]`; missing or unfitting entries: the path). The minimisation solver
/// ([`SolverKind::Minimise`]) ignores the guesses.
///
/// # Errors
/// [`SolverError::NotConverged`] carrying the reports of the steps that converged.
pub fn solve_path_guided<P: NonlinearProblem>(
    model: &P,
    settings: SolverSettings,
    state: &mut PathState,
    levels: &[LoadLevel],
    guesses: &[Option<&LevelGuess>],
    mut observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    if let SolverKind::Minimise(_) = settings.kind {
        return super::minimise::solve_path_from(model, settings, state, levels, observe);
    }
    let augmented = settings.augmented_updates > 0;
    let mut solver = Solver::new(model, settings)?;
    let mut reports = Vec::with_capacity(levels.len());
    for (i, level) in levels.iter().enumerate() {
        let guess = guesses.get(i).copied().flatten().filter(|g| g.fits(model));
        let step = (|| -> Result<StepReport, SolverError> {
            let mut spent = Spent::default();
            if let Some(g) = guess {
                let starts: Vec<&[f64]> = std::iter::once(&g.u_full[..])
                    .chain(g.fallback.as_deref())
                    .collect();
                for u in &starts {
                    match solver.jump_from(state, *level, u, &g.shifts)? {
                        Ok(mut rep) => {
                            rep.newton_iterations += spent.iterations;
                            return Ok(rep);
                        }
                        Err(iterations) => spent.iterations += iterations,
                    }
                }
                match solver.homotopy(state, *level, &starts, &g.shifts)? {
                    Ok(mut rep) => {
                        rep.newton_iterations += spent.iterations;
                        return Ok(rep);
                    }
                    Err(h) => {
                        spent.iterations += h.iterations;
                        spent.homotopy_steps = h.homotopy_steps;
                    }
                }
            }
            let mut rep = solver.advance(state, *level)?;
            rep.newton_iterations += spent.iterations;
            rep.homotopy_steps = spent.homotopy_steps;
            Ok(rep)
        })()
        .and_then(|mut rep| {
            if augmented {
                solver.augment(state, *level, &mut rep)?;
            }
            Ok(rep)
        });
        match step {
            Ok(rep) => {
                if solver.settings.trace {
                    eprintln!(
                        "  level {level}: {} Newton iterations{}{}",
                        rep.newton_iterations,
                        if rep.warm_start { ", warm start" } else { "" },
                        if rep.homotopy_steps > 0 {
                            format!(", {} homotopy steps", rep.homotopy_steps)
                        } else {
                            String::new()
                        }
                    );
                }
                observe(i, state, &rep);
                reports.push(rep);
            }
            Err(e) => return Err(e.after(reports)),
        }
    }
    Ok(reports)
}
