//! Ridge polynomial regression: the cheap alternative to the Gaussian process.
//!
//! `y_c(x) = Σ_p β_pc φ_p(x)`, `φ_p(x) = Π_j x_j^{e_pj}` over all monomials of total degree
//! `≤ D`. Coefficients solve `(ΦᵀΦ + λ tr(ΦᵀΦ)/P · I′) β = Φᵀy` (`I′` leaves the constant
//! unpenalised). The degree `D ∈ {1, 2, 3}` and `λ` are chosen by the weighted PRESS statistic
//! (exact leave-one-out residuals `e_i/(1 − h_ii)` of the linear smoother), shared by all outputs.
//! Predictive variance (approximate): `s_c² (1 + φᵀA⁻¹φ)/(1 + P/n)`, `s_c²` the LOO mean square.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use super::linalg::{cholesky_in_place, dot, solve_lower, solve_lower_t, spd_inverse};
use super::regressor::{Data, EmbeddedRegressor, LinearBasis, Regressor, TrainingSettings};
use crate::rom::RomError;

/// Fit settings of the polynomial.
#[derive(Debug, Clone)]
pub struct PolyParams {
    /// Largest total degree tried (1..=3).
    pub max_degree: usize,
    /// Relative ridge values tried.
    pub ridges: Vec<f64>,
}

impl Default for PolyParams {
    fn default() -> Self {
        PolyParams {
            max_degree: 3,
            ridges: vec![1e-10, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2],
        }
    }
}

/// A fitted ridge polynomial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Poly {
    /// Number of inputs.
    pub d: usize,
    /// Number of outputs.
    pub m: usize,
    /// Total degree.
    pub degree: usize,
    /// Relative ridge.
    pub ridge: f64,
    /// Exponents, `n_terms × d`.
    pub exponents: Vec<u8>,
    /// Coefficients, `n_terms × m`.
    pub coef: Vec<f64>,
    /// `A⁻¹ = (ΦᵀΦ + λI′)⁻¹`, `n_terms × n_terms` (for the variance).
    pub a_inv: Vec<f64>,
    /// LOO mean square per output.
    pub s2: Vec<f64>,
    /// `1 + P/n` normalisation of the variance.
    pub var_norm: f64,
}

/// All exponent tuples of `d` variables with total degree `≤ degree` (graded order).
pub fn monomials(d: usize, degree: usize) -> Vec<u8> {
    let mut out = Vec::new();
    for total in 0..=degree {
        let mut e = vec![0u8; d];
        push_degree(&mut out, &mut e, 0, total);
    }
    out
}

fn push_degree(out: &mut Vec<u8>, e: &mut Vec<u8>, j: usize, left: usize) {
    if j + 1 == e.len() || e.is_empty() {
        if let Some(last) = e.last_mut() {
            *last = left as u8;
        }
        out.extend_from_slice(e);
        return;
    }
    for k in (0..=left).rev() {
        e[j] = k as u8;
        for t in e[j + 1..].iter_mut() {
            *t = 0;
        }
        push_degree(out, e, j + 1, left - k);
    }
}

/// Values of all monomials at `x` into `phi` (powers from a table, degree ≤ 3).
fn basis_into(exps: &[u8], x: &[f64], phi: &mut [f64]) {
    let d = x.len();
    let mut pw = [[1.0f64; 4]; 8];
    for (j, &xj) in x.iter().enumerate() {
        pw[j] = [1.0, xj, xj * xj, xj * xj * xj];
    }
    for (p, ph) in phi.iter_mut().enumerate() {
        let e = &exps[p * d..(p + 1) * d];
        let mut v = 1.0;
        for j in 0..d {
            v *= pw[j][e[j] as usize];
        }
        *ph = v;
    }
}

struct Candidate {
    press: f64,
    degree: usize,
    ridge: f64,
}

fn design(data: &Data<'_>, exps: &[u8], n_terms: usize) -> Vec<f64> {
    let mut phi = vec![0.0; data.n * n_terms];
    for i in 0..data.n {
        basis_into(
            exps,
            &data.x[i * data.d..(i + 1) * data.d],
            &mut phi[i * n_terms..(i + 1) * n_terms],
        );
    }
    phi
}

/// Normal matrix `ΦᵀΦ + λ̃ I′` with `λ̃ = λ tr(ΦᵀΦ)/P`.
fn normal_matrix(phi: &[f64], n: usize, p: usize, ridge: f64) -> Vec<f64> {
    let mut a = vec![0.0; p * p];
    for i in 0..n {
        let row = &phi[i * p..(i + 1) * p];
        for r in 0..p {
            for c in 0..=r {
                a[r * p + c] += row[r] * row[c];
            }
        }
    }
    let tr: f64 = (0..p).map(|k| a[k * p + k]).sum::<f64>() / p as f64;
    for k in 1..p {
        a[k * p + k] += ridge * tr;
    }
    for r in 0..p {
        for c in 0..r {
            a[c * p + r] = a[r * p + c];
        }
    }
    a
}

/// Solves for the coefficients; returns `(β, A⁻¹, LOO residual mean squares)`.
fn solve(
    data: &Data<'_>,
    phi: &[f64],
    p: usize,
    ridge: f64,
) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let (n, m) = (data.n, data.m);
    let mut l = normal_matrix(phi, n, p, ridge);
    cholesky_in_place(&mut l, p).ok()?;
    let mut beta = vec![0.0; p * m];
    let mut rhs = vec![0.0; p];
    for c in 0..m {
        rhs.iter_mut().for_each(|r| *r = 0.0);
        for i in 0..n {
            let yi = data.y[i * m + c];
            for k in 0..p {
                rhs[k] += phi[i * p + k] * yi;
            }
        }
        solve_lower(&l, p, &mut rhs);
        solve_lower_t(&l, p, &mut rhs);
        for k in 0..p {
            beta[k * m + c] = rhs[k];
        }
    }
    let a_inv = spd_inverse(&l, p);
    let mut s2 = vec![0.0; m];
    let mut tmp = vec![0.0; p];
    for i in 0..n {
        let row = &phi[i * p..(i + 1) * p];
        for r in 0..p {
            tmp[r] = dot(&a_inv[r * p..(r + 1) * p], row);
        }
        let h = dot(&tmp, row);
        if h >= 1.0 - 1e-10 {
            return None;
        }
        for c in 0..m {
            let pred: f64 = (0..p).map(|k| row[k] * beta[k * m + c]).sum();
            let e = (data.y[i * m + c] - pred) / (1.0 - h);
            s2[c] += e * e / n as f64;
        }
    }
    Some((beta, a_inv, s2))
}

impl Regressor for Poly {
    const NAME: &'static str = "poly";

    type Params = PolyParams;

    /// The settings given under `"poly"`, else the defaults.
    fn training_params(settings: &TrainingSettings<'_>) -> PolyParams {
        settings.params_or_default::<Self>()
    }

    fn fit(data: &Data<'_>, params: &PolyParams) -> Result<Self, RomError> {
        let weight = |c: usize| data.weights.get(c).copied().unwrap_or(1.0);
        let mut best: Option<Candidate> = None;
        for degree in 1..=params.max_degree.clamp(1, 3) {
            let exps = monomials(data.d, degree);
            let p = exps.len() / data.d.max(1);
            // degree 1 is always tried (the ridge makes it solvable); higher ones need n ≥ P
            if p > data.n && degree > 1 {
                break;
            }
            let phi = design(data, &exps, p);
            for &ridge in &params.ridges {
                if let Some((_, _, s2)) = solve(data, &phi, p, ridge) {
                    let press: f64 = s2
                        .iter()
                        .enumerate()
                        .map(|(c, s)| s * weight(c).powi(2))
                        .sum();
                    if best.as_ref().is_none_or(|b| press < b.press) {
                        best = Some(Candidate {
                            press,
                            degree,
                            ridge,
                        });
                    }
                }
            }
        }
        let best = best.ok_or_else(|| {
            RomError::InsufficientData(format!(
                "polynomial regression: no solvable fit with {} points",
                data.n
            ))
        })?;
        let exps = monomials(data.d, best.degree);
        let p = exps.len() / data.d.max(1);
        let phi = design(data, &exps, p);
        let (coef, a_inv, s2) =
            solve(data, &phi, p, best.ridge).ok_or_else(|| RomError::Numerical {
                stage: "polynomial fit".into(),
                message: "normal matrix not positive definite".into(),
            })?;
        Ok(Poly {
            d: data.d,
            m: data.m,
            degree: best.degree,
            ridge: best.ridge,
            exponents: exps,
            coef,
            a_inv,
            s2,
            var_norm: 1.0 + p as f64 / data.n as f64,
        })
    }

    fn n_inputs(&self) -> usize {
        self.d
    }

    fn n_outputs(&self) -> usize {
        self.m
    }

    fn scratch_len(&self) -> usize {
        2 * self.n_terms()
    }

    fn predict_cols_into(
        &self,
        x: &[f64],
        cols: Range<usize>,
        out: &mut [f64],
        scratch: &mut [f64],
    ) {
        let p = self.n_terms();
        let m = self.m;
        let phi = &mut scratch[..p];
        basis_into(&self.exponents, x, phi);
        out[cols.clone()].iter_mut().for_each(|o| *o = 0.0);
        for (k, ph) in phi.iter().enumerate() {
            let c = &self.coef[k * m + cols.start..k * m + cols.end];
            for (o, cj) in out[cols.clone()].iter_mut().zip(c) {
                *o += ph * cj;
            }
        }
    }

    fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]) {
        let (p, m, d) = (self.n_terms(), self.m, self.d);
        self.predict_into(x, out, scratch);
        jac[..m * d].iter_mut().for_each(|o| *o = 0.0);
        let mut pw = [[1.0f64; 4]; 8];
        for (j, &xj) in x.iter().enumerate() {
            pw[j] = [1.0, xj, xj * xj, xj * xj * xj];
        }
        for k in 0..p {
            let e = &self.exponents[k * d..(k + 1) * d];
            for j in 0..d {
                if e[j] == 0 {
                    continue;
                }
                let mut dv = e[j] as f64 * pw[j][e[j] as usize - 1];
                for (jj, &ej) in e.iter().enumerate() {
                    if jj != j {
                        dv *= pw[jj][ej as usize];
                    }
                }
                let c = &self.coef[k * m..(k + 1) * m];
                for o in 0..m {
                    jac[o * d + j] += dv * c[o];
                }
            }
        }
    }

    fn variance_into(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]) {
        let p = self.n_terms();
        let (phi, tmp) = scratch[..2 * p].split_at_mut(p);
        basis_into(&self.exponents, x, phi);
        for r in 0..p {
            tmp[r] = dot(&self.a_inv[r * p..(r + 1) * p], phi);
        }
        let h = dot(tmp, phi);
        for (c, v) in var[..self.m].iter_mut().enumerate() {
            *v = self.s2[c] * (1.0 + h) / self.var_norm;
        }
    }

    fn check(&self, _blocks: &[Range<usize>]) -> Result<(), String> {
        if self.coef.len() != self.n_terms() * self.m {
            return Err("polynomial tables have inconsistent sizes".into());
        }
        Ok(())
    }

    /// The monomials, weighted by the coefficients.
    fn linear_basis(&self) -> Option<LinearBasis<'_>> {
        Some(LinearBasis {
            weights: &self.coef,
            n_basis: self.n_terms(),
            groups: std::iter::once(0..self.m).collect(),
        })
    }

    #[inline]
    fn basis_into(&self, _group: usize, x: &[f64], phi: &mut [f64]) {
        basis_into(&self.exponents, x, phi);
    }

    fn embedded(&self) -> Option<EmbeddedRegressor> {
        Some(EmbeddedRegressor::Poly {
            exponents: self.exponents.clone(),
            coef: self.coef.clone(),
        })
    }
}

impl Poly {
    /// Number of monomials.
    pub fn n_terms(&self) -> usize {
        self.exponents.len().checked_div(self.d).unwrap_or(1)
    }

    /// The monomials at `x` into `phi` (length [`Self::n_terms`]): the outputs are
    /// `out_c = Σ_k φ_k coef[k·m + c]`.
    pub fn basis_values_into(&self, x: &[f64], phi: &mut [f64]) {
        basis_into(&self.exponents, x, phi);
    }
}
