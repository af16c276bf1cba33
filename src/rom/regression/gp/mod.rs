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
//!
//! Sparse fit ([`GpParams::inducing`], `gp/sparse.rs`): the weights sit on `k < n` inducing
//! points `Z` chosen among the training inputs by pivoted Cholesky of `R`, with the
//! subset-of-regressors mean of all `n` points, `α = (K_Zn K_nZ + η K_ZZ)⁻¹ K_Zn Y`; the result
//! is a process of the same form with `n = k` (same prediction paths, model file and export).

mod fit;
mod kernel;
// public for the tests in tests/rom/
#[doc(hidden)]
pub mod likelihood;
mod sparse;

use serde::{Deserialize, Serialize};

use std::ops::Range;
use std::sync::OnceLock;

use super::regressor::{Data, EmbeddedRegressor, LinearBasis, Regressor, TrainingSettings};
use crate::rom::RomError;
pub use kernel::kernel_vector;
// public for the tests in tests/rom/
#[doc(hidden)]
pub use fit::{assemble, checked_bounds, fit, group_outputs};
// public for the tests in tests/rom/
use kernel::{kernel, kernel_and_g};
#[doc(hidden)]
pub use sparse::select_inducing;

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
    /// Inducing points of a sparse fit (`gp/sparse.rs`): `None`, the exact process; `Some(k)`
    /// with `k` below the number of points `n`, the weights sit on `k` training inputs chosen
    /// by pivoted Cholesky (the subset-of-regressors mean of all `n` points), and the fitted
    /// process is an ordinary one with `n = k`: a prediction costs `k` kernel values. The
    /// hyperparameters are fitted as without it. `k ≥ n`: the exact process (a fold or a
    /// set smaller than `k` is fitted exactly). `k` must be at least twice the inputs.
    pub inducing: Option<usize>,
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
            inducing: None,
        }
    }
}

/// Largest number of inputs (the hot paths scale the query in fixed arrays of this size).
pub const MAX_INPUTS: usize = 8;

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
    /// `xs` stored by feature, `d × n` per group (built on first use, not stored).
    #[serde(skip)]
    by_feature: ByFeature,
}

/// The training inputs over the length scales stored by feature, so that the kernel vector's
/// distance loop runs over contiguous vectors ([`kernel_vector`]); derived from `xs`, equal for
/// equal processes (comparisons ignore it).
#[derive(Debug, Clone, Default)]
struct ByFeature(OnceLock<Vec<f64>>);

impl PartialEq for ByFeature {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Gp {
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

    /// Scaled training inputs of group `g` by feature, `d × n` (built on first call).
    pub fn group_xs_by_feature(&self, g: usize) -> &[f64] {
        let (n, d) = (self.n, self.d);
        let t = self.by_feature.0.get_or_init(|| {
            let mut t = vec![0.0; self.n_groups() * d * n];
            for g in 0..self.n_groups() {
                let xs = self.group_xs(g);
                for i in 0..n {
                    for j in 0..d {
                        t[(g * d + j) * n + i] = xs[i * d + j];
                    }
                }
            }
            t
        });
        &t[g * d * n..(g + 1) * d * n]
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
    const NAME: &'static str = "gp";

    type Params = GpParams;

    /// The settings given under `"gp"` (else the defaults); with `kernel_per_block`, one
    /// kernel per POD block.
    fn training_params(settings: &TrainingSettings<'_>) -> GpParams {
        let base = settings.params_or_default::<Self>();
        if settings.kernel_per_block {
            GpParams {
                groups: settings.blocks.to_vec(),
                ..base
            }
        } else {
            base
        }
    }

    /// Exact, or sparse on [`GpParams::inducing`] points.
    fn fit(data: &Data<'_>, params: &GpParams) -> Result<Self, RomError> {
        Gp::fit_process(data, params)
    }

    fn n_inputs(&self) -> usize {
        self.d
    }

    fn n_outputs(&self) -> usize {
        self.m
    }

    fn scratch_len(&self) -> usize {
        // the kernel vector, or kernel values, `g` and the transposed Jacobian of
        // `jacobian_into`
        2 * self.n + self.m * self.d
    }

    /// `out[cols] = αᵀ k(x)`, a kernel vector per column group the columns meet (by feature:
    /// [`kernel_vector`]).
    fn predict_cols_into(
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
                self.basis_into(g, x, k);
                self.combine_into(k, lo..hi, out);
            }
        }
    }

    simd_method! {
        Gp;
        fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]) => jacobian_body
    }

    simd_method! {
        Gp;
        fn variance_into(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]) => variance_body
    }

    /// Column groups that cover the outputs without splitting a block, and tables of the
    /// sizes the groups and dimensions give.
    fn check(&self, blocks: &[Range<usize>]) -> Result<(), String> {
        let (d, m, n) = (self.d, self.m, self.n);
        let b = &self.groups;
        if !b.is_empty()
            && (b.len() < 3
                || !valid_group_bounds(b, m)
                || blocks
                    .iter()
                    .any(|blk| b.iter().any(|&e| e > blk.start && e < blk.end)))
        {
            return Err(format!(
                "Gaussian-process column groups {b:?}: expected increasing boundaries from 0 to {m} that do not split a block"
            ));
        }
        let g = self.n_groups();
        if self.x.len() != n * d
            || self.xs.len() != g * n * d
            || self.inv_len.len() != g * d
            || self.theta.len() != g * (d + 1)
            || d > MAX_INPUTS
            || self.alpha.len() != n * m
            || self.sigma2.len() != m
            || self.chol.len() != g * n * (n + 1) / 2
        {
            return Err("Gaussian-process tables have inconsistent sizes".into());
        }
        Ok(())
    }

    /// The kernel vector of each column group, weighted by `α`.
    fn linear_basis(&self) -> Option<LinearBasis<'_>> {
        Some(LinearBasis {
            weights: &self.alpha,
            n_basis: self.n,
            groups: (0..self.n_groups())
                .map(|g| self.group_columns(g))
                .collect(),
        })
    }

    /// The kernel vector of group `group` from the inputs stored by feature.
    #[inline]
    fn basis_into(&self, group: usize, x: &[f64], phi: &mut [f64]) {
        kernel_vector(
            self.group_xs_by_feature(group),
            self.group_inv_len(group),
            x,
            phi,
        );
    }

    /// The inputs stored by feature.
    fn prepare(&self) {
        let _ = self.group_xs_by_feature(0);
    }

    fn embedded(&self) -> Option<EmbeddedRegressor> {
        Some(EmbeddedRegressor::Gp {
            groups: self.groups.iter().map(|&b| b as u16).collect(),
            inv_len: self.inv_len.clone(),
            xs: self.xs.clone(),
            alpha: self.alpha.clone(),
        })
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
