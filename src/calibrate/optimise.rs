//! Bounded Levenberg–Marquardt with multistart.
//!
//! ## Local stage
//!
//! Minimises `χ²(u) = Σ rᵢ(u)²` over the unit box `u ∈ [0, 1]⁴` (a subset of the coordinates
//! may be held fixed, for profiles). Each iteration takes the analytic Jacobian `J = ∂r/∂u`
//! (the surrogate's, chained through the parametrisation), the gradient `g = Jᵀr`, and the
//! *free* set: coordinates not at a bound, or at a bound with `g` pointing into the box. On the
//! free set it solves
//!
//! ```text
//!   (JᵀJ + λ diag(JᵀJ)) δ = −g,      u ← Π_box(u + δ)
//! ```
//!
//! (Marquardt's scaling, Cholesky of the 4 × 4 system) and accepts the projected step when
//! `χ²` decreases, halving `λ` (×⅓); otherwise `λ` grows ×4 and the step is retried. It stops
//! when the projected gradient is below `gtol`, when the relative decrease of `χ²` is below
//! `ftol` twice in a row, when the step is below `xtol`, or after `max_iterations`; the reason
//! is reported ([`Stop`]) and so are the coordinates that end on a bound with the gradient
//! pushing outwards ([`LocalFit::active`]).
//!
//! argmin 0.11 has a Gauss–Newton solver but neither bounds nor Levenberg–Marquardt; the
//! `levenberg-marquardt` crate (MINPACK) is unbounded. Box constraints through a change of
//! variables (`u = sin²φ`) would hide an active bound, which the calibration must report: hence
//! this small projected solver.
//!
//! ## Global stage
//!
//! Starts: a maximin Latin hypercube of `n` points in the unit box (egobox-doe, seeded), plus
//! any given points (the literature set). Every start runs in parallel (rayon; each start is
//! deterministic, so the result does not depend on the thread count), every end point is
//! reported, and end points closer than 1e-3 in `u` with the same `χ²` (to 1e-6 relative) are
//! grouped into one minimum.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::objective::Evaluator;
use super::CalibrateError;

/// Settings of the local stage.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LmSettings {
    /// Iteration limit.
    pub max_iterations: usize,
    /// Projected-gradient tolerance (on `‖Π g‖∞`, unit-box coordinates).
    pub gtol: f64,
    /// Relative decrease of `χ²` below which the fit has stalled.
    pub ftol: f64,
    /// Step tolerance (unit-box coordinates).
    pub xtol: f64,
}

impl Default for LmSettings {
    fn default() -> Self {
        LmSettings {
            max_iterations: 200,
            gtol: 1e-8,
            ftol: 1e-12,
            xtol: 1e-10,
        }
    }
}

/// Why a local fit stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// Projected gradient below `gtol`.
    Gradient,
    /// `χ²` no longer decreases (relative change below `ftol`).
    CostStalled,
    /// Step below `xtol`.
    Step,
    /// `λ` grew beyond 1e16 without a decrease.
    NoDescent,
    /// Iteration limit reached.
    MaxIterations,
}

/// Which bound a coordinate ends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Bound {
    /// Lower bound of the box.
    Lower,
    /// Upper bound of the box.
    Upper,
}

/// The end of one local fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalFit {
    /// Start (unit box).
    pub start: [f64; 4],
    /// End point (unit box).
    pub u: [f64; 4],
    /// `χ²` at the end point.
    pub chi2: f64,
    /// Iterations.
    pub iterations: usize,
    /// Why it stopped.
    pub stop: Stop,
    /// Coordinates on a bound with the gradient pushing out of the box.
    pub active: [Option<Bound>; 4],
    /// Index of the minimum this end point belongs to (after grouping).
    pub minimum: usize,
}

/// Workspace of the local stage (sized once per observation count).
struct Work {
    r: Vec<f64>,
    j: Vec<[f64; 4]>,
    r_trial: Vec<f64>,
}

fn chi2(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Solves the `free` part of `a δ = b` (4 × 4, symmetric positive definite on the free set);
/// fixed coordinates get `δ = 0`. `None` when not positive definite.
// public for the tests in tests/calibrate/
#[doc(hidden)]
#[allow(clippy::needless_range_loop)] // the Cholesky loops mirror the formulas
pub fn solve_free(a: &[[f64; 4]; 4], b: &[f64; 4], free: &[bool; 4]) -> Option<[f64; 4]> {
    let idx: Vec<usize> = (0..4).filter(|&i| free[i]).collect();
    let n = idx.len();
    let mut l = [[0.0; 4]; 4];
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[idx[i]][idx[j]];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            if i == j {
                if s <= 0.0 || !s.is_finite() {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    let mut y = [0.0; 4];
    for i in 0..n {
        let mut s = b[idx[i]];
        for k in 0..i {
            s -= l[i][k] * y[k];
        }
        y[i] = s / l[i][i];
    }
    let mut x = [0.0; 4];
    for i in (0..n).rev() {
        let mut s = y[i];
        for k in i + 1..n {
            s -= l[k][i] * x[k];
        }
        x[i] = s / l[i][i];
    }
    let mut out = [0.0; 4];
    for (k, &i) in idx.iter().enumerate() {
        out[i] = x[k];
    }
    Some(out)
}

const ON_BOUND: f64 = 1e-12;

fn free_set(u: &[f64; 4], g: &[f64; 4], fixed: &[bool; 4]) -> [bool; 4] {
    std::array::from_fn(|i| {
        let pushed_out = (u[i] <= ON_BOUND && g[i] > 0.0) || (u[i] >= 1.0 - ON_BOUND && g[i] < 0.0);
        !(fixed[i] || pushed_out)
    })
}

/// One bounded Levenberg–Marquardt fit from `start`; coordinates with `fixed[i]` keep their
/// start value.
///
/// # Errors
/// A surrogate evaluation error.
pub fn local_fit(
    ev: &mut Evaluator<'_>,
    start: [f64; 4],
    fixed: [bool; 4],
    s: &LmSettings,
) -> Result<LocalFit, CalibrateError> {
    let m = ev.set().len();
    let mut w = Work {
        r: vec![0.0; m],
        j: vec![[0.0; 4]; m],
        r_trial: vec![0.0; m],
    };
    let mut u: [f64; 4] = std::array::from_fn(|i| start[i].clamp(0.0, 1.0));
    ev.residuals(&u, &mut w.r, Some(&mut w.j))?;
    let mut cost = chi2(&w.r);
    let mut lambda = 1e-3;
    let mut stalls = 0;
    let mut stop = Stop::MaxIterations;
    let mut it = 0;
    while it < s.max_iterations {
        it += 1;
        let mut a = [[0.0; 4]; 4];
        let mut g = [0.0; 4];
        for (ri, ji) in w.r.iter().zip(&w.j) {
            for p in 0..4 {
                g[p] += ji[p] * ri;
                for q in 0..4 {
                    a[p][q] += ji[p] * ji[q];
                }
            }
        }
        let free = free_set(&u, &g, &fixed);
        let pg = (0..4)
            .filter(|&i| free[i])
            .map(|i| g[i].abs())
            .fold(0.0, f64::max);
        if pg < s.gtol * (1.0 + cost) {
            stop = Stop::Gradient;
            break;
        }
        let b: [f64; 4] = std::array::from_fn(|i| -g[i]);
        let mut accepted = false;
        while lambda < 1e16 {
            let mut ad = a;
            for i in 0..4 {
                ad[i][i] += lambda * a[i][i].max(1e-12);
            }
            let Some(d) = solve_free(&ad, &b, &free) else {
                lambda *= 4.0;
                continue;
            };
            let trial: [f64; 4] = std::array::from_fn(|i| {
                if free[i] {
                    (u[i] + d[i]).clamp(0.0, 1.0)
                } else {
                    u[i]
                }
            });
            let step = (0..4).map(|i| (trial[i] - u[i]).abs()).fold(0.0, f64::max);
            if step < s.xtol {
                stop = Stop::Step;
                break;
            }
            ev.residuals(&trial, &mut w.r_trial, None)?;
            let c_trial = chi2(&w.r_trial);
            if c_trial < cost {
                let rel = (cost - c_trial) / cost.max(1e-300);
                stalls = if rel < s.ftol { stalls + 1 } else { 0 };
                u = trial;
                cost = c_trial;
                lambda = (lambda / 3.0).max(1e-12);
                accepted = true;
                break;
            }
            lambda *= 4.0;
        }
        if stop == Stop::Step {
            break;
        }
        if !accepted {
            stop = Stop::NoDescent;
            break;
        }
        ev.residuals(&u, &mut w.r, Some(&mut w.j))?;
        if stalls >= 2 {
            stop = Stop::CostStalled;
            break;
        }
    }
    // gradient at the end point, for the active bounds
    ev.residuals(&u, &mut w.r, Some(&mut w.j))?;
    let mut g = [0.0; 4];
    for (ri, ji) in w.r.iter().zip(&w.j) {
        for p in 0..4 {
            g[p] += ji[p] * ri;
        }
    }
    let active = std::array::from_fn(|i| {
        if fixed[i] {
            None
        } else if u[i] <= ON_BOUND && g[i] > 0.0 {
            Some(Bound::Lower)
        } else if u[i] >= 1.0 - ON_BOUND && g[i] < 0.0 {
            Some(Bound::Upper)
        } else {
            None
        }
    });
    Ok(LocalFit {
        start,
        u,
        chi2: chi2(&w.r),
        iterations: it,
        stop,
        active,
        minimum: 0,
    })
}

/// Settings of the global stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MultistartSettings {
    /// Latin-hypercube starts.
    pub starts: usize,
    /// Seed of the Latin hypercube.
    pub seed: u64,
    /// Local settings.
    pub local: LmSettings,
}

impl Default for MultistartSettings {
    fn default() -> Self {
        MultistartSettings {
            starts: 24,
            seed: 2024,
            local: LmSettings::default(),
        }
    }
}

/// Runs every start (Latin hypercube plus `extra`), sorted by `χ²`, each tagged with its
/// minimum (0 = best).
///
/// # Errors
/// No start at all, or a surrogate evaluation error.
pub fn multistart(
    ev: &Evaluator<'_>,
    extra: &[[f64; 4]],
    s: &MultistartSettings,
) -> Result<Vec<LocalFit>, CalibrateError> {
    let mut starts: Vec<[f64; 4]> = extra.to_vec();
    if s.starts > 0 {
        let lhs = crate::snapshots::plan::unit_lhs(s.starts, 4, s.seed);
        for row in lhs.rows() {
            starts.push([row[0], row[1], row[2], row[3]]);
        }
    }
    if starts.is_empty() {
        return Err(CalibrateError::input("starts", 0, "at least one start"));
    }
    let fits: Vec<Result<LocalFit, CalibrateError>> = starts
        .par_iter()
        .map(|&u0| {
            let mut e = ev.clone();
            local_fit(&mut e, u0, [false; 4], &s.local)
        })
        .collect();
    let mut fits = fits.into_iter().collect::<Result<Vec<_>, _>>()?;
    fits.sort_by(|a, b| a.chi2.total_cmp(&b.chi2));
    group_minima(&mut fits);
    Ok(fits)
}

/// Tags each fit (sorted by `χ²`) with the index of its minimum.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn group_minima(fits: &mut [LocalFit]) {
    let mut reps: Vec<([f64; 4], f64)> = Vec::new();
    for f in fits.iter_mut() {
        let k = reps.iter().position(|(u, c)| {
            let d = (0..4).map(|i| (u[i] - f.u[i]).abs()).fold(0.0, f64::max);
            d < 1e-3 && (c - f.chi2).abs() <= 1e-6 * c.abs().max(1e-12)
        });
        f.minimum = match k {
            Some(k) => k,
            None => {
                reps.push((f.u, f.chi2));
                reps.len() - 1
            }
        };
    }
}
