//! The predictor: each increment starts from the path extrapolated in the load parameter,
//! quadratic through the last three converged states (linear through two), unless that would
//! push a contact point into penetration.

use super::problem::NonlinearProblem;
use super::state::PathState;
use super::Solver;
use crate::fe::assembly::LoadLevel;

impl<P: NonlinearProblem> Solver<'_, P> {
    /// Predictor: moves `state.u_free` to the extrapolated path at `level` and returns
    /// whether it did ([`SolverSettings::predictor`]).
    pub(super) fn predict(&mut self, state: &mut PathState, level: &LoadLevel) -> bool {
        let mut u_pred = std::mem::take(&mut self.u_pred);
        let Some(points) = extrapolate(state, level, &mut u_pred) else {
            self.u_pred = u_pred;
            return false;
        };
        // reject a prediction that pushes a contact point deeper than the smoothing zone
        // below where the last state had it (a contact that the extrapolation does not know
        // about: Newton would start from a deep penetration); one that inverts an element
        // fails at Newton's first assembly and is retried from the last state
        let mut u_full = std::mem::take(&mut state.u_full);
        self.model.expand(&state.u_free, &state.level, &mut u_full);
        let (g_last, delta) = self.model.min_shifted_gap(&u_full);
        self.model.expand(&u_pred, level, &mut u_full);
        let (g_pred, _) = self.model.min_shifted_gap(&u_full);
        let accept = g_pred >= g_last.min(0.0) - delta;
        if self.settings.trace {
            eprintln!(
                "  predictor ({} points): smallest gap {g_pred:.3e} mm (last {g_last:.3e}): {}",
                points,
                if accept { "used" } else { "rejected" }
            );
        }
        if accept {
            state.u_free.copy_from_slice(&u_pred);
        }
        state.u_full = u_full;
        self.u_pred = u_pred;
        accept
    }
}

/// The free unknowns extrapolated along the path to `level` into `out`: quadratic through the
/// last three converged states, linear through two, in the one load factor that varies (the
/// states used are those that differ from `level` in that factor alone); the number of states
/// used (3 or 2), `None` if the history does not allow it.
pub(super) fn extrapolate(
    state: &PathState,
    level: &LoadLevel,
    out: &mut Vec<f64>,
) -> Option<usize> {
    let mut varying = state.level.changing(level);
    let (Some(c), None) = (varying.next(), varying.next()) else {
        return None;
    };
    let same_path = |l: &LoadLevel| l.changing(level).all(|f| f == c);
    let param = |l: &LoadLevel| l[c];
    let k = state.history.len();
    let usable = state
        .history
        .iter()
        .rev()
        .take_while(|(_, l)| same_path(l))
        .count();
    let (t, t2) = (param(level), param(&state.level));
    out.clear();
    if usable >= 2 {
        let (u0, l0) = &state.history[k - 2];
        let (u1, l1) = &state.history[k - 1];
        let (t0, t1) = (param(l0), param(l1));
        if t0 == t1 || t1 == t2 || t0 == t2 {
            return None;
        }
        let w0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2));
        let w1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2));
        let w2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1));
        out.extend(
            u0.iter()
                .zip(u1)
                .zip(&state.u_free)
                .map(|((a, b), c)| w0 * a + w1 * b + w2 * c),
        );
        Some(3)
    } else if usable == 1 {
        let (u1, l1) = &state.history[k - 1];
        let t1 = param(l1);
        if t1 == t2 {
            return None;
        }
        let w = (t - t2) / (t2 - t1);
        out.extend(u1.iter().zip(&state.u_free).map(|(a, c)| c + w * (c - a)));
        Some(2)
    } else {
        None
    }
}
