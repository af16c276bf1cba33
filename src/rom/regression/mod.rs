//! Regression of POD coefficients on the scaled case features.
//!
//! A regressor is a type implementing [`Regressor`] (linfa's fit / predict-into split): its
//! fit, its allocation-free prediction, its serialisation into the model file (serde, under its
//! [`Regressor::NAME`]) and, if the embedded predictor can evaluate it, its export tables
//! ([`Regressor::embedded`]). The built-ins are listed once, in [`BUILTIN`]: training fits
//! every regressor of a [`Registry`] (the built-ins by default), a model file holds each
//! fitted one under its name, and loading reads the names the registry knows. Adding a
//! regressor is one new file and one line in the list below; a regressor outside the crate
//! (a test's) is added to a registry with [`Registry::with`].
//!
//! The built-ins: [`gp::Gp`] (Gaussian process, Matérn 5/2, ARD length scales shared by all
//! outputs or per column group, predictive variance) and [`poly::Poly`] (ridge polynomial of
//! total degree ≤ 3, degree and ridge chosen by PRESS). Both are multi-output: one fit predicts
//! all POD coefficients of all blocks. Inputs are the active features scaled to `[−1, 1]` by
//! [`FeatureScaler`](crate::case::FeatureScaler).

mod registry;

use std::fmt::Debug;
use std::ops::Range;

use serde::de::DeserializeOwned;
use serde::Serialize;

pub use registry::{
    DynRegressor, EmbeddedRegressor, Entry, LinearBasis, Registry, RegressorKind, Regressors,
};

use super::train::TrainConfig;
use super::RomError;

/// Declares the built-in regressors' modules and lists them in [`BUILTIN`], in the order
/// training fits them.
macro_rules! builtin_regressors {
    ($($module:ident :: $ty:ident),* $(,)?) => {
        $(pub mod $module;)*
        /// The built-in regressors, in the order training fits them and model files hold them.
        pub const BUILTIN: &[Entry] = &[$(Entry::of::<$module::$ty>()),*];
    };
}

builtin_regressors! {
    gp::Gp,
    poly::Poly,
}

/// Training data of a regressor: `n` points, `d` inputs, `m` outputs, row-major.
#[derive(Debug, Clone, Copy)]
pub struct Data<'a> {
    /// Inputs, `n × d`.
    pub x: &'a [f64],
    /// Outputs, `n × m`.
    pub y: &'a [f64],
    /// Number of points.
    pub n: usize,
    /// Number of inputs.
    pub d: usize,
    /// Number of outputs.
    pub m: usize,
    /// Relative weight of each output column in model selection (hyperparameters, degree).
    pub weights: &'a [f64],
}

/// A multi-output regressor `ℝᵈ → ℝᵐ` (linfa-style fit / predict-into split).
///
/// Required: the name, the fit and its settings, the sizes, the prediction of a range of
/// outputs and the Jacobian. The rest has defaults: no predictive variance, no table checks
/// beyond the sizes, the general (unfolded) prediction path, and no export to the embedded
/// predictor (`surrogate export` then refuses the model).
pub trait Regressor:
    Sized + Clone + PartialEq + Debug + Serialize + DeserializeOwned + Send + Sync + 'static
{
    /// Name in the registry, in the model file (the key of the fitted tables, and each block's
    /// `regressor`) and on the command line (`train --only`).
    const NAME: &'static str;

    /// Fit settings.
    type Params;

    /// Fits the regressor.
    ///
    /// # Errors
    /// Too few points or a numerical failure.
    fn fit(data: &Data<'_>, params: &Self::Params) -> Result<Self, RomError>;

    /// The fit settings of a training run: from `cfg`, and the column boundaries of the POD
    /// blocks `[0, b₁, …, m]` (a regressor may treat blocks apart).
    fn training_params(cfg: &TrainConfig, blocks: &[usize]) -> Self::Params;

    /// Number of inputs `d`.
    fn n_inputs(&self) -> usize;

    /// Number of outputs `m`.
    fn n_outputs(&self) -> usize;

    /// Length of the scratch buffer the `*_into` methods need.
    fn scratch_len(&self) -> usize;

    /// Predicted outputs `cols` at `x` (length `d`) into `out[cols]` (other entries untouched).
    /// No allocation.
    fn predict_cols_into(
        &self,
        x: &[f64],
        cols: Range<usize>,
        out: &mut [f64],
        scratch: &mut [f64],
    );

    /// All predicted outputs at `x` into `out` (length `m`). No allocation.
    fn predict_into(&self, x: &[f64], out: &mut [f64], scratch: &mut [f64]) {
        self.predict_cols_into(x, 0..self.n_outputs(), out, scratch);
    }

    /// Outputs and their Jacobian `jac[c·d + j] = ∂out_c/∂x_j`. No allocation.
    fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]);

    /// Predictive variance of each output. No allocation. Default: none (zeros; the
    /// surrogate's standard deviations are then zero for the outputs it predicts).
    fn variance_into(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]) {
        let _ = (x, scratch);
        var[..self.n_outputs()].iter_mut().for_each(|v| *v = 0.0);
    }

    /// Consistency of the tables of a loaded regressor whose sizes match the model (`d` inputs,
    /// `m` outputs); `blocks` are the coefficient columns of the POD blocks. Default: nothing
    /// more to check.
    ///
    /// # Errors
    /// A message naming the inconsistent table.
    fn check(&self, blocks: &[Range<usize>]) -> Result<(), String> {
        let _ = blocks;
        Ok(())
    }

    /// The outputs as linear combinations of basis functions, `out_c = Σ_b φ_b(x) W[b·m + c]`
    /// per column group, with `φ` from [`Self::basis_into`]: the surrogate then folds the POD
    /// basis into `W` (its scalar fast path). Default: `None` (the general path).
    fn linear_basis(&self) -> Option<LinearBasis<'_>> {
        None
    }

    /// The basis functions of column group `group` of [`Self::linear_basis`] at `x` into `phi`
    /// (length `n_basis`). No allocation. Called only when [`Self::linear_basis`] is `Some`.
    fn basis_into(&self, group: usize, x: &[f64], phi: &mut [f64]) {
        let _ = (group, x, phi);
    }

    /// Builds tables derived from the fitted ones (not stored) ahead of the first prediction,
    /// so that no prediction allocates. Default: none.
    fn prepare(&self) {}

    /// The tables of the embedded predictor (`surrogate export`), or `None` if it cannot
    /// evaluate this regressor. Default: `None`.
    fn embedded(&self) -> Option<EmbeddedRegressor> {
        None
    }
}

/// Lower Cholesky factor in place (row-major `n × n`; the upper part is left as is).
///
/// Written here rather than taken from faer so that retraining reproduces the shipped models
/// bit for bit (faer's factor is faster but rounds differently: `docs/rom_notes.md`).
///
/// # Errors
/// The index of the first non-positive pivot.
pub(crate) fn cholesky_in_place(a: &mut [f64], n: usize) -> Result<(), usize> {
    for i in 0..n {
        let (head, tail) = a.split_at_mut(i * n);
        let row_i = &mut tail[..n];
        for j in 0..i {
            let row_j = &head[j * n..j * n + j + 1];
            let s = row_i[j] - dot(&row_i[..j], &row_j[..j]);
            row_i[j] = s / row_j[j];
        }
        let d = row_i[i] - dot(&row_i[..i], &row_i[..i]);
        if d <= 0.0 || !d.is_finite() {
            return Err(i);
        }
        row_i[i] = d.sqrt();
    }
    Ok(())
}

/// Dot product with 4 independent accumulators (vectorisable, fixed summation order).
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let chunks = a.len() / 4;
    for c in 0..chunks {
        for l in 0..4 {
            acc[l] += a[4 * c + l] * b[4 * c + l];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for k in 4 * chunks..a.len() {
        s += a[k] * b[k];
    }
    s
}

/// Solves `L v = b` in place (row-major lower `L`, `n × n`).
pub(crate) fn solve_lower(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + i];
        let mut s = b[i];
        for (k, lv) in row.iter().enumerate() {
            s -= lv * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Solves `Lᵀ v = b` in place.
pub(crate) fn solve_lower_t(l: &[f64], n: usize, b: &mut [f64]) {
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in (i + 1)..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Inverse `(LLᵀ)⁻¹` (full symmetric, row-major) from the lower factor.
///
/// Row `c` of `V = L⁻ᵀ` solves `L v = e_c` (contiguous dots), then `A⁻¹_ij = V_i · V_j`.
pub(crate) fn spd_inverse(l: &[f64], n: usize) -> Vec<f64> {
    let mut v = vec![0.0; n * n];
    for c in 0..n {
        let row = &mut v[c * n..(c + 1) * n];
        row[c] = 1.0 / l[c * n + c];
        for i in (c + 1)..n {
            let s = dot(&l[i * n + c..i * n + i], &row[c..i]);
            row[i] = -s / l[i * n + i];
        }
    }
    let mut inv = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s = dot(&v[i * n + i..(i + 1) * n], &v[j * n + i..(j + 1) * n]);
            inv[i * n + j] = s;
            inv[j * n + i] = s;
        }
    }
    inv
}
