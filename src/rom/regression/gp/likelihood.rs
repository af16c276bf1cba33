//! The hyperparameter search of the Gaussian process: the negative profiled log-likelihood,
//! its gradient, and the projected Barzilai–Borwein descent (see the [parent module](super)).

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::super::linalg::{
    cholesky_in_place, dot, solve_lower_multi, solve_lower_t_multi, spd_inverse,
};
use super::super::regressor::Data;
use super::kernel::{kernel, kernel_and_g};
use crate::rom::RomError;

const LN_LEN_BOUNDS: (f64, f64) = (-3.5, 3.5);
const LN_NUGGET_BOUNDS: (f64, f64) = (-18.4, -2.3);

// public for the tests in tests/rom/
#[doc(hidden)]
pub struct Eval {
    nll: f64,
    grad: Vec<f64>,
}

impl Eval {
    /// The negative profiled log-likelihood.
    // public for the tests in tests/rom/
    #[doc(hidden)]
    pub fn nll(&self) -> f64 {
        self.nll
    }

    /// Its gradient with respect to `θ`.
    // public for the tests in tests/rom/
    #[doc(hidden)]
    pub fn grad(&self) -> &[f64] {
        &self.grad
    }
}

/// Correlation matrix `R = K + ηI` (row-major) for hyperparameters `theta`.
pub(super) fn correlation(x: &[f64], n: usize, d: usize, theta: &[f64]) -> Vec<f64> {
    let inv_len: Vec<f64> = theta[..d].iter().map(|t| (-t).exp()).collect();
    let eta = theta[d].exp();
    let mut r = vec![0.0; n * n];
    for i in 0..n {
        r[i * n + i] = 1.0 + eta;
        for j in 0..i {
            let k = kernel(scaled_dist(
                &x[i * d..(i + 1) * d],
                &x[j * d..(j + 1) * d],
                &inv_len,
            ));
            r[i * n + j] = k;
            r[j * n + i] = k;
        }
    }
    r
}

/// Distance `‖(a − b) ⊙ ℓ⁻¹‖` in the length scales.
#[inline]
pub(super) fn scaled_dist(a: &[f64], b: &[f64], inv_len: &[f64]) -> f64 {
    let mut r2 = 0.0;
    for j in 0..a.len() {
        let t = (a[j] - b[j]) * inv_len[j];
        r2 += t * t;
    }
    r2.sqrt()
}

/// Negative profiled log-likelihood and its gradient; `None` if `R` is not positive definite.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn neg_log_likelihood(data: &Data<'_>, yw: &[f64], theta: &[f64]) -> Option<Eval> {
    let (n, d, m) = (data.n, data.d, data.m);
    let mut l = correlation(data.x, n, d, theta);
    cholesky_in_place(&mut l, n).ok()?;
    // a = R⁻¹ Y, all columns at once (each column bit for bit as its own solve)
    let mut a = yw[..n * m].to_vec();
    let mut scratch = vec![0.0; m];
    solve_lower_multi(&l, n, &mut a, m, &mut scratch);
    let mut col = vec![0.0; n];
    let mut s = 0.0;
    for c in 0..m {
        for i in 0..n {
            col[i] = a[i * m + c];
        }
        s += dot(&col, &col);
    }
    solve_lower_t_multi(&l, n, &mut a, m, &mut scratch);
    let sigma2 = (s / (n * m) as f64).max(1e-300);
    let logdet: f64 = 2.0 * (0..n).map(|i| l[i * n + i].ln()).sum::<f64>();
    let nll = 0.5 * (n * m) as f64 * sigma2.ln() + 0.5 * m as f64 * logdet;
    let rinv = spd_inverse(&l, n);
    let inv_len: Vec<f64> = theta[..d].iter().map(|t| (-t).exp()).collect();
    let mut grad = vec![0.0; d + 1];
    for i in 0..n {
        let xi = &data.x[i * d..(i + 1) * d];
        let wii = dot(&a[i * m..(i + 1) * m], &a[i * m..(i + 1) * m]) / sigma2
            - m as f64 * rinv[i * n + i];
        grad[d] -= 0.5 * wii * theta[d].exp();
        for j in 0..i {
            // symmetric pair (i, j) and (j, i)
            let w = dot(&a[i * m..(i + 1) * m], &a[j * m..(j + 1) * m]) / sigma2
                - m as f64 * rinv[i * n + j];
            let xj = &data.x[j * d..(j + 1) * d];
            let (_, g) = kernel_and_g(scaled_dist(xi, xj, &inv_len));
            for k in 0..d {
                let t = (xi[k] - xj[k]) * inv_len[k];
                grad[k] -= w * g * t * t;
            }
        }
    }
    Some(Eval { nll, grad })
}

fn project(theta: &mut [f64]) {
    let d = theta.len() - 1;
    for t in theta[..d].iter_mut() {
        *t = t.clamp(LN_LEN_BOUNDS.0, LN_LEN_BOUNDS.1);
    }
    theta[d] = theta[d].clamp(LN_NUGGET_BOUNDS.0, LN_NUGGET_BOUNDS.1);
}

/// Projected Barzilai–Borwein descent with Armijo backtracking from `theta0`.
fn minimise(
    data: &Data<'_>,
    yw: &[f64],
    theta0: Vec<f64>,
    max_iter: usize,
) -> Option<(Vec<f64>, f64)> {
    let mut theta = theta0;
    project(&mut theta);
    let mut cur = neg_log_likelihood(data, yw, &theta)?;
    let gmax = cur.grad.iter().fold(0.0f64, |a, g| a.max(g.abs()));
    let mut step = 0.5 / gmax.max(1e-12);
    for _ in 0..max_iter {
        let mut accepted = None;
        let mut trial_step = step;
        for _ in 0..12 {
            let mut t: Vec<f64> = theta
                .iter()
                .zip(&cur.grad)
                .map(|(t, g)| t - trial_step * g)
                .collect();
            project(&mut t);
            let decrease: f64 = theta
                .iter()
                .zip(&t)
                .zip(&cur.grad)
                .map(|((a, b), g)| g * (a - b))
                .sum();
            if let Some(e) = neg_log_likelihood(data, yw, &t) {
                if e.nll <= cur.nll - 1e-4 * decrease {
                    accepted = Some((t, e));
                    break;
                }
            }
            trial_step *= 0.25;
        }
        let Some((t, e)) = accepted else { break };
        let s: Vec<f64> = t.iter().zip(&theta).map(|(a, b)| a - b).collect();
        let yv: Vec<f64> = e.grad.iter().zip(&cur.grad).map(|(a, b)| a - b).collect();
        let sy = dot(&s, &yv);
        let ss = dot(&s, &s);
        let small = s.iter().fold(0.0f64, |a, v| a.max(v.abs())) < 1e-5
            || (cur.nll - e.nll).abs() < 1e-9 * (1.0 + cur.nll.abs());
        step = if sy > 0.0 {
            (ss / sy).clamp(1e-8, 1e4)
        } else {
            trial_step * 2.0
        };
        theta = t;
        cur = e;
        if small {
            break;
        }
    }
    Some((theta, cur.nll))
}

/// The hyperparameters of the best of `n_start` seeded starts (`GpParams`' fields of the same
/// names).
pub(super) fn optimise(
    data: &Data<'_>,
    seed: u64,
    n_start: usize,
    max_iter: usize,
    max_points: usize,
) -> Result<Vec<f64>, RomError> {
    let (n, d, m) = (data.n, data.d, data.m);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    // the likelihood costs O(n³) per step: above `max_points`, search on a seeded subset
    let mut rows: Vec<usize> = (0..n).collect();
    if n > max_points {
        rows.shuffle(&mut rng);
        rows.truncate(max_points);
        rows.sort_unstable();
    }
    let ns = rows.len();
    let xs: Vec<f64> = rows
        .iter()
        .flat_map(|&i| data.x[i * d..(i + 1) * d].iter().copied())
        .collect();
    let ys: Vec<f64> = rows
        .iter()
        .flat_map(|&i| data.y[i * m..(i + 1) * m].iter().copied())
        .collect();
    let mut yw = ys.clone();
    for i in 0..ns {
        for c in 0..m {
            yw[i * m + c] *= data.weights.get(c).copied().unwrap_or(1.0);
        }
    }
    let data = &Data {
        x: &xs,
        y: &ys,
        n: ns,
        ..*data
    };
    let mut best: Option<(Vec<f64>, f64)> = None;
    for s in 0..n_start.max(1) {
        let mut t0 = vec![(0.7f64).ln(); d + 1];
        t0[d] = (1e-6f64).ln();
        if s > 0 {
            for t in t0[..d].iter_mut() {
                *t = rng.gen_range(-1.6..1.1);
            }
            t0[d] = rng.gen_range(-18.0..-7.0);
        }
        if let Some((t, f)) = minimise(data, &yw, t0, max_iter) {
            if best.as_ref().is_none_or(|b| f < b.1) {
                best = Some((t, f));
            }
        }
    }
    best.map(|b| b.0).ok_or_else(|| RomError::Numerical {
        stage: "GP hyperparameters".into(),
        message: "correlation matrix not positive definite at every start".into(),
    })
}
