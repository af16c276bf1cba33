//! Bounded Levenberg–Marquardt for costly evaluations: a damped Gauss–Newton step inside a
//! rectangular trust region of per-coordinate radii and the bounds, each step the minimum of
//! the quadratic model over that box.

use nalgebra::{DMatrix, DVector};

use super::settings::JointStop;

/// One evaluation of [`bounded_lm`].
// public for the tests in tests/calibrate/
#[doc(hidden)]
#[derive(Clone, Debug, PartialEq)]
pub struct LmStep {
    /// The point.
    pub x: Vec<f64>,
    /// `χ²` (`inf` where the evaluation failed).
    pub chi2: f64,
    /// `χ²` the linearisation predicted (the start's own for the first).
    pub predicted_chi2: f64,
    /// Damping of the step (0 for the start).
    pub lambda: f64,
    /// Whether it became the current point.
    pub accepted: bool,
}

/// The evaluations of [`bounded_lm`] and how it stopped.
// public for the tests in tests/calibrate/
#[doc(hidden)]
#[derive(Clone, Debug, PartialEq)]
pub struct LmTrace {
    /// Every evaluation, in order.
    pub steps: Vec<LmStep>,
    /// Index of the last accepted one (the optimum).
    pub best: usize,
    /// Why it stopped.
    pub stop: JointStop,
}

/// Bounded Levenberg–Marquardt for costly evaluations: `eval(x)` gives the residuals and their
/// Jacobian, or `None` where the model fails there (a failed step).
///
/// Each coordinate has its own trust radius `Δᵢ` (a fraction of its range, starting at
/// `radius0`): the step minimises the damped model `‖r + Jδ‖² + λ‖D δ‖²` (`D² = diag(JᵀJ)`)
/// over the box `|δᵢ| ≤ Δᵢ·rangeᵢ`, `lo ≤ x + δ ≤ hi` ([`box_step`]), a rectangular trust
/// region. When a trial fails, the radii of the coordinates the box held (at a trust face,
/// not a bound) halve, or the damping rises when the box held none; when one succeeds with
/// `ρ > 0.5`, those radii double (up to 1). One coordinate whose linearisation holds only over
/// a short distance (measured: the force rig's plate, whose step over its whole range lowered
/// every blocked force its derivative said would rise) so no longer shortens the steps of the
/// others. Nielsen's damping update; stops after `max_evals` evaluations, when `χ²` falls by
/// less than a relative 1e-3 over an accepted step the box did not hold, or when `λ > 1e8`.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn bounded_lm<E>(
    x0: &[f64],
    bnds: &[(f64, f64)],
    lambda0: f64,
    radius0: f64,
    max_evals: usize,
    min_gain: f64,
    mut eval: impl FnMut(&[f64]) -> Result<Option<(DVector<f64>, DMatrix<f64>)>, E>,
) -> Result<LmTrace, E> {
    let k = x0.len();
    let mut x = x0.to_vec();
    let first = eval(&x)?;
    let c0 = first
        .as_ref()
        .map_or(f64::INFINITY, |(r, _)| r.norm_squared());
    let mut steps = vec![LmStep {
        x: x.clone(),
        chi2: c0,
        predicted_chi2: c0,
        lambda: 0.0,
        accepted: true,
    }];
    let Some((mut r, mut j)) = first else {
        return Ok(LmTrace {
            steps,
            best: 0,
            stop: JointStop::NoDescent,
        });
    };
    let span: Vec<f64> = bnds.iter().map(|b| (b.1 - b.0).max(1e-300)).collect();
    let mut best = 0;
    let (mut lambda, mut nu) = (lambda0, 2.0);
    let mut radius = vec![radius0.clamp(1e-6, 1.0); k];
    let stop = loop {
        if steps.len() >= max_evals {
            break JointStop::Budget;
        }
        if lambda > 1e8 {
            break JointStop::NoDescent;
        }
        let mut a = j.transpose() * &j;
        let g = j.transpose() * &r;
        for i in 0..k {
            a[(i, i)] += lambda * a[(i, i)].max(1e-12);
        }
        // the box: the trust radius and the bounds, whichever is nearer
        let lo: Vec<f64> = (0..k)
            .map(|i| (-radius[i] * span[i]).max(bnds[i].0 - x[i]).min(0.0))
            .collect();
        let hi: Vec<f64> = (0..k)
            .map(|i| (radius[i] * span[i]).min(bnds[i].1 - x[i]).max(0.0))
            .collect();
        let Some(delta) = box_step(&a, &g, &lo, &hi) else {
            lambda *= nu;
            nu *= 2.0;
            continue;
        };
        // the coordinates the trust box (not a bound) held
        let held: Vec<usize> = (0..k)
            .filter(|&i| {
                let face = radius[i] * span[i];
                let tol = 1e-9 * span[i];
                (delta[i] >= face - tol && hi[i] >= face - tol)
                    || (delta[i] <= -face + tol && lo[i] <= -face + tol)
            })
            .collect();
        let trial: Vec<f64> = (0..k)
            .map(|i| (x[i] + delta[i]).clamp(bnds[i].0, bnds[i].1))
            .collect();
        let step = DVector::from_fn(k, |i, _| trial[i] - x[i]);
        let c_cur = r.norm_squared();
        let predicted = (&r + &j * &step).norm_squared();
        if min_gain > 0.0 && held.is_empty() && c_cur - predicted < min_gain {
            // the step the damping and the bounds allow, which the trust box does not hold,
            // promises less than `min_gain`: not worth another evaluation
            break JointStop::Converged;
        }
        let next = eval(&trial)?;
        let c_new = next
            .as_ref()
            .map_or(f64::INFINITY, |(r, _)| r.norm_squared());
        let rho = (c_cur - c_new) / (c_cur - predicted).max(1e-300);
        let accepted = c_new.is_finite() && c_new < c_cur;
        steps.push(LmStep {
            x: trial.clone(),
            chi2: c_new,
            predicted_chi2: predicted,
            lambda,
            accepted,
        });
        if accepted {
            let (rn, jn) = next.expect("finite χ² has residuals");
            x = trial;
            r = rn;
            j = jn;
            best = steps.len() - 1;
            lambda *= (1.0 / 3.0f64).max(1.0 - (2.0 * rho - 1.0).powi(3));
            nu = 2.0;
            if rho > 0.5 {
                for &i in &held {
                    radius[i] = (2.0 * radius[i]).min(1.0);
                }
            }
            // a step the box held is progress, not convergence
            if held.is_empty() && (c_cur - c_new) / c_cur < 1e-3 {
                break JointStop::Converged;
            }
        } else if held.is_empty() {
            lambda *= nu;
            nu *= 2.0;
        } else {
            for &i in &held {
                radius[i] *= 0.5;
            }
        }
    };
    Ok(LmTrace { steps, best, stop })
}

/// Minimises the quadratic model `½δᵀAδ + gᵀδ` (`A` positive definite) over the box
/// `lo ≤ δ ≤ hi` (`lo ≤ 0 ≤ hi`) by an active set: solve for the free coordinates, fix the
/// one that leaves the box furthest (relative to its side) on the face it crosses, repeat;
/// then free a fixed coordinate whose multiplier says the model decreases inwards, and
/// repeat, for at most `4k` rounds. `None` when `A` restricted to the free set is not positive
/// definite.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn box_step(
    a: &DMatrix<f64>,
    g: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
) -> Option<DVector<f64>> {
    let k = g.len();
    let mut fixed: Vec<Option<f64>> = vec![None; k];
    // a coordinate with an empty side towards which the gradient pushes starts fixed at 0
    for i in 0..k {
        if (hi[i] <= 0.0 && g[i] < 0.0) || (lo[i] >= 0.0 && g[i] > 0.0) {
            fixed[i] = Some(0.0);
        }
    }
    let mut delta = DVector::zeros(k);
    for _ in 0..4 * k.max(1) {
        let free: Vec<usize> = (0..k).filter(|&i| fixed[i].is_none()).collect();
        for i in 0..k {
            if let Some(v) = fixed[i] {
                delta[i] = v;
            }
        }
        if !free.is_empty() {
            let m = free.len();
            let af = DMatrix::from_fn(m, m, |p, q| a[(free[p], free[q])]);
            let bf = DVector::from_fn(m, |p, _| {
                let i = free[p];
                -g[i]
                    - (0..k)
                        .filter_map(|c| fixed[c].map(|v| a[(i, c)] * v))
                        .sum::<f64>()
            });
            let sol = af.cholesky()?.solve(&bf);
            for (p, &i) in free.iter().enumerate() {
                delta[i] = sol[p];
            }
        }
        // the free coordinate furthest outside its side of the box
        let worst = free
            .iter()
            .filter_map(|&i| {
                let d = delta[i];
                if d > hi[i] {
                    Some((i, hi[i], d / hi[i].max(1e-300)))
                } else if d < lo[i] {
                    Some((i, lo[i], d / lo[i].min(-1e-300)))
                } else {
                    None
                }
            })
            .max_by(|p, q| p.2.total_cmp(&q.2));
        if let Some((i, face, _)) = worst {
            fixed[i] = Some(face);
            continue;
        }
        // every free coordinate inside: free a fixed one the model wants to move inwards
        let grad = a * &delta + g;
        let release = (0..k).find(|&i| match fixed[i] {
            Some(v) => {
                (v >= hi[i] && v > lo[i] && grad[i] > 0.0)
                    || (v <= lo[i] && v < hi[i] && grad[i] < 0.0)
            }
            None => false,
        });
        match release {
            Some(i) => fixed[i] = None,
            None => return Some(delta),
        }
    }
    Some(delta)
}
