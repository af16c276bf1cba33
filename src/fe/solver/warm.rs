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
//! **Same answers.** The guess only starts the iteration: Newton at the output level converges
//! to the same residual tolerance as the path does, and the augmented-Lagrangian updates then
//! run as after any step (starting from the neighbour's contact gap shifts, which are already
//! close to the multipliers of this case). If Newton fails from the guess (too far, or an
//! element inverts), the state goes back to the previous level of this case and the level is
//! taken along the path as if no guess had been given; its iterations are counted in the
//! step's report either way.
//!
//! The guess carries the neighbour's contact gap shifts: a guess from another model (another
//! number of unknowns or contact points) is not used ([`LevelGuess::fits`]).

use super::problem::NonlinearProblem;
use super::settings::{SolverError, SolverKind, SolverSettings, StepReport};
use super::state::PathState;
use super::Solver;
use crate::fe::assembly::LoadLevel;

/// A starting point for one output level: a converged state of a neighbouring case.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelGuess {
    /// Full displacement vector.
    pub u_full: Vec<f64>,
    /// The contact gap shifts (augmented-Lagrangian multipliers) to start with.
    pub shifts: Vec<f64>,
    /// A second start tried if Newton fails from `u_full` (the neighbour's state as it is,
    /// when `u_full` was extrapolated from it), before the load path.
    pub fallback: Option<Vec<f64>>,
}

impl LevelGuess {
    /// Whether this guess belongs to a model of `model`'s size: the same number of unknowns
    /// and of contact points.
    pub fn fits(&self, model: &impl NonlinearProblem) -> bool {
        self.u_full.len() == model.n_full() && self.shifts.len() == model.contact_shifts().len()
    }
}

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
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        let saved_u = state.u_free.clone();
        let saved_shifts = self.model.contact_shifts();
        self.model.restrict(&guess.u_full, &mut state.u_free);
        self.model.set_contact_shifts(&guess.shifts);
        self.stab = None;
        let out = self.newton(state, &target, false)?;
        if self.settings.trace {
            eprintln!(
                "  warm start at p={:.4}: {} after {} iterations",
                target.pressure,
                if out.converged {
                    "converged"
                } else {
                    "failed, along the path instead"
                },
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
        if state.history.len() == 2 {
            state.history.remove(0);
        }
        state.history.push((saved_u, state.level));
        state.level = target;
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        Ok(Ok(StepReport {
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
        }))
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
            let mut spent = 0;
            if let Some(g) = guess {
                match solver.jump(state, *level, g)? {
                    Ok(rep) => return Ok(rep),
                    Err(iterations) => spent = iterations,
                }
                if let Some(u) = &g.fallback {
                    let second = LevelGuess {
                        u_full: u.clone(),
                        shifts: g.shifts.clone(),
                        fallback: None,
                    };
                    match solver.jump(state, *level, &second)? {
                        Ok(mut rep) => {
                            rep.newton_iterations += spent;
                            return Ok(rep);
                        }
                        Err(iterations) => spent += iterations,
                    }
                }
            }
            let mut rep = solver.advance(state, *level)?;
            rep.newton_iterations += spent;
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
                observe(i, state, &rep);
                reports.push(rep);
            }
            Err(e) => return Err(e.after(reports)),
        }
    }
    Ok(reports)
}
