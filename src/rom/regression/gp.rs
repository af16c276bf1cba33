//! Gaussian-process regression with a shared Matérn-5/2 ARD kernel.
//!
//! Prior: each output column `y_c ~ GP(0, σ_c² (k(x, x') + η δ))` with
//! `k = (1 + √5 r + 5r²/3) e^{−√5 r}`, `r² = Σ_d (x_d − x'_d)²/ℓ_d²`. The correlation matrix
//! `R = K + ηI` is shared by all columns. Hyperparameters `θ = (ln ℓ, ln η)` maximise the
//! profiled log-likelihood with one variance for all (weighted) columns,
//! `ℓ(θ) = −(nm/2) ln σ̂² − (m/2) ln|R|`, `σ̂² = Σ_c y_cᵀR⁻¹y_c/(nm)`, whose gradient is
//! `∂ℓ/∂θ = ½ tr((AAᵀ/σ̂² − mR⁻¹) ∂R/∂θ)`, `A = R⁻¹Y`. It is maximised by projected
//! Barzilai–Borwein gradient steps with Armijo backtracking inside a box, from `n_start ≥ 2`
//! seeded starting points (the first is `ℓ = 0.7, η = 10⁻⁶`).
//!
//! Prediction: mean `μ_c(x) = k(x)ᵀα_c`, `α_c = R⁻¹y_c`; variance
//! `σ_c²(1 − k(x)ᵀR⁻¹k(x))` with `σ_c² = y_cᵀR⁻¹y_c/n` (latent, no nugget).
//!
//! Column groups ([`GpParams::groups`]): the output columns may be split into contiguous
//! groups, each with its own hyperparameters and correlation matrix (a kernel per POD block:
//! outputs of different smoothness get their own length scales); a prediction computes one
//! kernel vector per group it needs. Without groups (the default) one kernel serves all
//! columns, as above.

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use std::ops::Range;

use super::{cholesky_in_place, dot, solve_lower, solve_lower_t, spd_inverse, Data, Regressor};
use crate::rom::RomError;

/// Fit settings of the Gaussian process.
#[derive(Debug, Clone)]
pub struct GpParams {
    /// Number of optimiser starts (≥ 2 for robustness; all seeded).
    pub n_start: usize,
    /// Seed of the random starts.
    pub seed: u64,
    /// Iterations per start.
    pub max_iter: usize,
    /// Fixed hyperparameters `(ln ℓ_1..ln ℓ_d, ln η)`: skips the optimisation when given.
    pub theta: Option<Vec<f64>>,
    /// Largest number of points used in the hyperparameter search (a seeded subset above it;
    /// the weights always use every point).
    pub max_points: usize,
    /// Column groups with a kernel each, as boundaries `[0, b₁, …, m]` (strictly increasing);
    /// empty: one kernel for all columns.
    pub groups: Vec<usize>,
}

impl Default for GpParams {
    fn default() -> Self {
        GpParams {
            n_start: 2,
            seed: 11,
            max_iter: 200,
            theta: None,
            max_points: 400,
            groups: Vec::new(),
        }
    }
}

const LN_LEN_BOUNDS: (f64, f64) = (-3.5, 3.5);

/// Largest number of inputs (the hot paths scale the query in fixed arrays of this size).
pub const MAX_INPUTS: usize = 8;
const LN_NUGGET_BOUNDS: (f64, f64) = (-18.4, -2.3);

/// A fitted Gaussian process.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gp {
    /// Number of inputs.
    pub d: usize,
    /// Number of training points.
    pub n: usize,
    /// Number of outputs.
    pub m: usize,
    /// Training inputs, `n × d`.
    pub x: Vec<f64>,
    /// Column groups with a kernel each, as boundaries `[0, b₁, …, m]`; empty: one group.
    /// The per-group tables below are stored group after group.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub groups: Vec<usize>,
    /// Training inputs divided by the length scales, `n × d` per group (prediction hot path).
    pub xs: Vec<f64>,
    /// Hyperparameters `(ln ℓ, ln η)`, `d + 1` per group.
    pub theta: Vec<f64>,
    /// Inverse length scales, `d` per group.
    pub inv_len: Vec<f64>,
    /// Weights `α = R⁻¹Y`, `n × m` (column `c` with the factor of its group).
    pub alpha: Vec<f64>,
    /// Per-output process variance `σ_c²`.
    pub sigma2: Vec<f64>,
    /// Lower Cholesky factor of each group's `R`, packed by rows (`n(n+1)/2` values per group).
    pub chol: Vec<f64>,
}

struct Eval {
    nll: f64,
    grad: Vec<f64>,
}

/// Correlation matrix `R = K + ηI` (row-major) for hyperparameters `theta`.
fn correlation(x: &[f64], n: usize, d: usize, theta: &[f64]) -> Vec<f64> {
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

/// Matérn-5/2 value with the branch-free [`surrogate_predict::exp_nonpos`] (shared with the
/// embedded predictor) and `std`'s square root.
#[inline]
fn kernel(r: f64) -> f64 {
    kernel_and_g(r).0
}

/// Matérn-5/2 value and `g = −(1/r) dk/dr` (see [`surrogate_predict::matern52`]).
#[inline]
fn kernel_and_g(r: f64) -> (f64, f64) {
    const S5: f64 = 2.236_067_977_499_79;
    let e = surrogate_predict::exp_nonpos(-S5 * r);
    (
        (1.0 + S5 * r + 5.0 / 3.0 * r * r) * e,
        5.0 / 3.0 * (1.0 + S5 * r) * e,
    )
}

#[inline]
fn scaled_dist(a: &[f64], b: &[f64], inv_len: &[f64]) -> f64 {
    let mut r2 = 0.0;
    for j in 0..a.len() {
        let t = (a[j] - b[j]) * inv_len[j];
        r2 += t * t;
    }
    r2.sqrt()
}

/// Negative profiled log-likelihood and its gradient; `None` if `R` is not positive definite.
fn neg_log_likelihood(data: &Data<'_>, yw: &[f64], theta: &[f64]) -> Option<Eval> {
    let (n, d, m) = (data.n, data.d, data.m);
    let mut l = correlation(data.x, n, d, theta);
    cholesky_in_place(&mut l, n).ok()?;
    let mut a = vec![0.0; n * m];
    let mut col = vec![0.0; n];
    let mut s = 0.0;
    for c in 0..m {
        for i in 0..n {
            col[i] = yw[i * m + c];
        }
        solve_lower(&l, n, &mut col);
        s += dot(&col, &col);
        solve_lower_t(&l, n, &mut col);
        for i in 0..n {
            a[i * m + c] = col[i];
        }
    }
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

fn optimise(data: &Data<'_>, params: &GpParams) -> Result<Vec<f64>, RomError> {
    let (n, d, m) = (data.n, data.d, data.m);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(params.seed);
    // the likelihood costs O(n³) per step: above `max_points`, search on a seeded subset
    let mut rows: Vec<usize> = (0..n).collect();
    if n > params.max_points {
        rows.shuffle(&mut rng);
        rows.truncate(params.max_points);
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
    for s in 0..params.n_start.max(1) {
        let mut t0 = vec![(0.7f64).ln(); d + 1];
        t0[d] = (1e-6f64).ln();
        if s > 0 {
            for t in t0[..d].iter_mut() {
                *t = rng.gen_range(-1.6..1.1);
            }
            t0[d] = rng.gen_range(-18.0..-7.0);
        }
        if let Some((t, f)) = minimise(data, &yw, t0, params.max_iter) {
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

impl Gp {
    /// `out[cols] = αᵀ k(x)`; the same code for every instruction set (no fused
    /// multiply-adds are formed, so the results are bit-identical).
    #[inline(always)]
    fn predict_cols_body(
        &self,
        x: &[f64],
        cols: Range<usize>,
        out: &mut [f64],
        scratch: &mut [f64],
    ) {
        let k = &mut scratch[..self.n];
        for g in 0..self.n_groups() {
            let r = self.group_columns(g);
            let (lo, hi) = (cols.start.max(r.start), cols.end.min(r.end));
            if lo < hi {
                self.kernel_vector_into(g, x, k);
                self.combine_body(k, lo..hi, out);
            }
        }
    }

    simd_method! {
        Gp;
        /// `out[cols] = αᵀ k` for a kernel vector `k` (length `n`). No allocation.
        pub fn combine_into(&self, k: &[f64], cols: Range<usize>, out: &mut [f64]) => combine_body
    }

    #[inline(always)]
    fn combine_body(&self, k: &[f64], cols: Range<usize>, out: &mut [f64]) {
        let m = self.m;
        out[cols.clone()].iter_mut().for_each(|o| *o = 0.0);
        for (i, ki) in k.iter().enumerate() {
            let a = &self.alpha[i * m + cols.start..i * m + cols.end];
            for (o, ac) in out[cols.clone()].iter_mut().zip(a) {
                *o += ki * ac;
            }
        }
    }

    /// Outputs and `jac[c·d + j] = ∂out_c/∂x_j`: kernel values and `g = −k′/r` first, over the
    /// contiguous vector of training points; then the Jacobian is accumulated transposed
    /// (`d × m`) so that the inner loop runs over the contiguous weights. `scratch` holds
    /// `2n + d·m` values.
    #[inline(always)]
    fn jacobian_body(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]) {
        let (d, m, n) = (self.d, self.m, self.n);
        let (kv, rest) = scratch.split_at_mut(n);
        let (gv, rest) = rest.split_at_mut(n);
        let jt = &mut rest[..d * m];
        jt.iter_mut().for_each(|v| *v = 0.0);
        out[..m].iter_mut().for_each(|o| *o = 0.0);
        for g in 0..self.n_groups() {
            let cols = self.group_columns(g);
            let inv_len = self.group_inv_len(g);
            let mut il2 = [0.0; MAX_INPUTS];
            for j in 0..d {
                il2[j] = inv_len[j] * inv_len[j];
            }
            self.squared_distances_into(g, x, kv);
            for (ki, gi) in kv.iter_mut().zip(gv.iter_mut()) {
                let (k, g) = kernel_and_g(ki.sqrt());
                *ki = k;
                *gi = g;
            }
            for i in 0..n {
                let xi = &self.x[i * d..(i + 1) * d];
                let a = &self.alpha[i * m + cols.start..i * m + cols.end];
                let k = kv[i];
                for (o, ac) in out[cols.clone()].iter_mut().zip(a) {
                    *o += k * ac;
                }
                for j in 0..d {
                    let v = gv[i] * (x[j] - xi[j]) * il2[j];
                    let row = &mut jt[j * m + cols.start..j * m + cols.end];
                    for (r, ac) in row.iter_mut().zip(a) {
                        *r -= v * ac;
                    }
                }
            }
        }
        for c in 0..m {
            for j in 0..d {
                jac[c * d + j] = jt[j * m + c];
            }
        }
    }

    /// Predictive variance `σ_c² (1 − kᵀR⁻¹k)`: the kernel vector, then a forward substitution
    /// with the packed factor (16 partial sums per row, so that the additions do not wait
    /// for each other).
    #[inline(always)]
    fn variance_body(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]) {
        let n = self.n;
        let v = &mut scratch[..n];
        let packed = n * (n + 1) / 2;
        for g in 0..self.n_groups() {
            self.kernel_vector_into(g, x, v);
            let f = self.explained_complement(&self.chol[g * packed..(g + 1) * packed], v);
            for c in self.group_columns(g) {
                var[c] = self.sigma2[c] * f;
            }
        }
    }

    /// `1 − kᵀR⁻¹k` (at least 0) by forward substitution of the kernel vector `v` with the
    /// packed factor `chol` (overwrites `v`).
    #[inline(always)]
    fn explained_complement(&self, chol: &[f64], v: &mut [f64]) -> f64 {
        let n = self.n;
        for i in 0..n {
            let row = &chol[i * (i + 1) / 2..(i + 1) * (i + 2) / 2];
            let (head, tail) = v.split_at_mut(i);
            let mut acc = [0.0; 16];
            let mut rc = row[..i].chunks_exact(16);
            let mut vc = head.chunks_exact(16);
            for (r, w) in rc.by_ref().zip(vc.by_ref()) {
                for l in 0..16 {
                    acc[l] += r[l] * w[l];
                }
            }
            let mut s = 0.0;
            for (r, w) in rc.remainder().iter().zip(vc.remainder()) {
                s += r * w;
            }
            for a in acc {
                s += a;
            }
            tail[0] = (tail[0] - s) / row[i];
        }
        let mut explained = 0.0;
        for vi in v.iter() {
            explained += vi * vi;
        }
        (1.0 - explained).max(0.0)
    }

    /// Number of column groups (kernels).
    pub fn n_groups(&self) -> usize {
        self.groups.len().saturating_sub(1).max(1)
    }

    /// Output columns of group `g`.
    pub fn group_columns(&self, g: usize) -> Range<usize> {
        if self.groups.is_empty() {
            0..self.m
        } else {
            self.groups[g]..self.groups[g + 1]
        }
    }

    /// Inverse length scales of group `g`.
    pub fn group_inv_len(&self, g: usize) -> &[f64] {
        &self.inv_len[g * self.d..(g + 1) * self.d]
    }

    /// Scaled training inputs of group `g`, `n × d`.
    pub fn group_xs(&self, g: usize) -> &[f64] {
        let nd = self.n * self.d;
        &self.xs[g * nd..(g + 1) * nd]
    }

    /// The kernel vector of group `g`, `k_i = k(x, x_i)`, at the scaled features `x` into `k`
    /// (length `n`): squared distances, then the branch-free Matérn over the contiguous vector
    /// (this loop vectorises).
    #[inline(always)]
    pub fn kernel_vector_into(&self, g: usize, x: &[f64], k: &mut [f64]) {
        self.squared_distances_into(g, x, k);
        for ki in k.iter_mut() {
            *ki = kernel(ki.sqrt());
        }
    }

    /// Squared scaled distances `r_i² = Σ_j (x_j/ℓ_j − x_ij/ℓ_j)²` to the training points in
    /// group `g`'s length scales, into `r2` (length `n`).
    #[inline(always)]
    fn squared_distances_into(&self, g: usize, x: &[f64], r2: &mut [f64]) {
        let d = self.d;
        let (inv_len, xs) = (self.group_inv_len(g), self.group_xs(g));
        let mut xq = [0.0; MAX_INPUTS];
        for j in 0..d {
            xq[j] = x[j] * inv_len[j];
        }
        for (i, ri) in r2.iter_mut().enumerate() {
            let xi = &xs[i * d..(i + 1) * d];
            let mut s = 0.0;
            for j in 0..d {
                let t = xq[j] - xi[j];
                s += t * t;
            }
            *ri = s;
        }
    }
}

impl Regressor for Gp {
    type Params = GpParams;

    fn fit(data: &Data<'_>, params: &GpParams) -> Result<Self, RomError> {
        let (n, d, m) = (data.n, data.d, data.m);
        if n < 2 {
            return Err(RomError::InsufficientData(format!(
                "GP needs ≥ 2 points, got {n}"
            )));
        }
        if d == 0 || d > MAX_INPUTS {
            return Err(RomError::invalid(
                "GP inputs",
                d,
                &format!("1 ..= {MAX_INPUTS} (the prediction paths use fixed-size arrays)"),
            ));
        }
        let bounds: Vec<usize> = if params.groups.is_empty() {
            vec![0, m]
        } else {
            params.groups.clone()
        };
        if !valid_group_bounds(&bounds, m) {
            return Err(RomError::invalid(
                "GP column groups",
                format!("{bounds:?}"),
                &format!("strictly increasing boundaries from 0 to the {m} outputs"),
            ));
        }
        let n_groups = bounds.len() - 1;
        if let Some(t) = &params.theta {
            if t.len() != n_groups * (d + 1) {
                return Err(RomError::invalid(
                    "GP theta length",
                    t.len(),
                    &format!("{} ((inputs + 1) per column group)", n_groups * (d + 1)),
                ));
            }
        }
        let mut theta = Vec::with_capacity(n_groups * (d + 1));
        let mut inv_len = Vec::with_capacity(n_groups * d);
        let mut xs = Vec::with_capacity(n_groups * n * d);
        let mut chol = Vec::with_capacity(n_groups * n * (n + 1) / 2);
        let mut alpha = vec![0.0; n * m];
        let mut sigma2 = vec![0.0; m];
        for (g, w) in bounds.windows(2).enumerate() {
            let cols = w[0]..w[1];
            let mg = cols.len();
            // the group's columns as a data set of their own
            let y: Vec<f64> = (0..n)
                .flat_map(|i| data.y[i * m + cols.start..i * m + cols.end].iter().copied())
                .collect();
            let weights = data.weights.get(cols.clone()).unwrap_or(&[]);
            let sub = Data {
                y: &y,
                m: mg,
                weights,
                ..*data
            };
            let t = match &params.theta {
                Some(t) => t[g * (d + 1)..(g + 1) * (d + 1)].to_vec(),
                None => optimise(&sub, params)?,
            };
            let mut l = correlation(data.x, n, d, &t);
            cholesky_in_place(&mut l, n).map_err(|i| RomError::Numerical {
                stage: "GP fit".into(),
                message: format!("correlation matrix not positive definite (pivot {i})"),
            })?;
            let mut col = vec![0.0; n];
            for (c, out_c) in cols.clone().enumerate() {
                for i in 0..n {
                    col[i] = y[i * mg + c];
                }
                solve_lower(&l, n, &mut col);
                sigma2[out_c] = dot(&col, &col) / n as f64;
                solve_lower_t(&l, n, &mut col);
                for i in 0..n {
                    alpha[i * m + out_c] = col[i];
                }
            }
            // packed lower triangle: row i holds L[i][0..=i] at offset i(i+1)/2
            chol.extend((0..n).flat_map(|i| l[i * n..i * n + i + 1].to_vec()));
            let il: Vec<f64> = t[..d].iter().map(|t| (-t).exp()).collect();
            xs.extend((0..n * d).map(|e| data.x[e] * il[e % d]));
            inv_len.extend(il);
            theta.extend(t);
        }
        Ok(Gp {
            d,
            n,
            m,
            x: data.x.to_vec(),
            groups: if n_groups > 1 { bounds } else { Vec::new() },
            xs,
            theta,
            inv_len,
            alpha,
            sigma2,
            chol,
        })
    }

    fn n_outputs(&self) -> usize {
        self.m
    }

    fn scratch_len(&self) -> usize {
        // the kernel vector, or kernel values, `g` and the transposed Jacobian of
        // `jacobian_into`
        2 * self.n + self.m * self.d
    }

    simd_method! {
        Gp;
        fn predict_cols_into(
            &self,
            x: &[f64],
            cols: Range<usize>,
            out: &mut [f64],
            scratch: &mut [f64],
        ) => predict_cols_body
    }

    simd_method! {
        Gp;
        fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]) => jacobian_body
    }

    simd_method! {
        Gp;
        fn variance_into(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]) => variance_body
    }
}

impl Gp {
    /// Hyperparameters found by maximising the likelihood, `d + 1` per column group (for
    /// reuse with [`GpParams::theta`]).
    pub fn hyperparameters(&self) -> &[f64] {
        &self.theta
    }
}

/// Whether `bounds` are valid column-group boundaries for `m` outputs: at least two values,
/// strictly increasing from 0 to `m` (one group per consecutive pair).
pub fn valid_group_bounds(bounds: &[usize], m: usize) -> bool {
    bounds.len() >= 2
        && bounds[0] == 0
        && bounds[bounds.len() - 1] == m
        && bounds.windows(2).all(|w| w[0] < w[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn group_bounds_must_cover_all_columns_in_order() {
        assert!(valid_group_bounds(&[0, 5], 5));
        assert!(valid_group_bounds(&[0, 2, 5], 5));
        assert!(!valid_group_bounds(&[0], 5));
        assert!(!valid_group_bounds(&[1, 5], 5));
        assert!(!valid_group_bounds(&[0, 4], 5));
        assert!(!valid_group_bounds(&[0, 3, 3, 5], 5));
        assert!(!valid_group_bounds(&[0, 4, 2, 5], 5));
    }

    #[test]
    fn likelihood_gradient_matches_finite_differences() {
        let n = 12;
        let d = 2;
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let x: Vec<f64> = (0..n * d).map(|_| rng.gen_range(-1.0..1.0)).collect();
        let y: Vec<f64> = (0..n)
            .flat_map(|i| {
                [
                    (2.0 * x[2 * i]).sin() + x[2 * i + 1],
                    x[2 * i] * x[2 * i + 1],
                ]
            })
            .collect();
        let data = Data {
            x: &x,
            y: &y,
            n,
            d,
            m: 2,
            weights: &[],
        };
        let theta = vec![-0.3, 0.2, -6.0];
        let e = neg_log_likelihood(&data, &y, &theta).unwrap();
        for k in 0..3 {
            let h = 1e-5;
            let mut tp = theta.clone();
            tp[k] += h;
            let mut tm = theta.clone();
            tm[k] -= h;
            let fd = (neg_log_likelihood(&data, &y, &tp).unwrap().nll
                - neg_log_likelihood(&data, &y, &tm).unwrap().nll)
                / (2.0 * h);
            assert!(
                (fd - e.grad[k]).abs() < 1e-4 * (1.0 + fd.abs()),
                "k={k} fd={fd} an={}",
                e.grad[k]
            );
        }
    }
}
