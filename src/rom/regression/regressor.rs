//! The regressor trait, its training data and what a training run passes to a fit.

use std::any::Any;
use std::fmt::Debug;
use std::ops::Range;

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::rom::RomError;

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

    /// The fit settings of a training run ([`TrainingSettings`]).
    fn training_params(settings: &TrainingSettings<'_>) -> Self::Params;

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

/// What a training run passes to each regressor's [`Regressor::training_params`].
#[derive(Clone, Copy)]
pub struct TrainingSettings<'a> {
    /// Column boundaries of the POD blocks `[0, b₁, …, m]` (a regressor may treat blocks apart).
    pub blocks: &'a [usize],
    /// One Gaussian-process kernel per POD block
    /// ([`TrainConfig::kernel_per_block`](crate::rom::TrainConfig::kernel_per_block)).
    pub kernel_per_block: bool,
    /// Fit settings by regressor name (`"gp"`: a `GpParams`, `"poly"`: a `PolyParams`).
    pub params: &'a [(&'static str, &'a (dyn Any + Send + Sync))],
}

impl TrainingSettings<'_> {
    /// The settings given for regressor `name`, if they are a `P`.
    pub fn params_of<P: 'static>(&self, name: &str) -> Option<&P> {
        self.params
            .iter()
            .find(|(n, _)| *n == name)
            .and_then(|(_, p)| p.downcast_ref::<P>())
    }

    /// The settings given for regressor `R` (under its [`Regressor::NAME`]), else its default
    /// settings.
    pub fn params_or_default<R: Regressor>(&self) -> R::Params
    where
        R::Params: Clone + Default + 'static,
    {
        self.params_of::<R::Params>(R::NAME)
            .cloned()
            .unwrap_or_default()
    }
}

/// A regressor's outputs as linear combinations of basis functions (see
/// [`Regressor::linear_basis`]).
#[derive(Debug, Clone)]
pub struct LinearBasis<'a> {
    /// Weights `W`, `n_basis × m` (row `b` holds basis function `b`'s weight of every output).
    pub weights: &'a [f64],
    /// Number of basis functions of each column group.
    pub n_basis: usize,
    /// The column groups, each with basis functions of its own (one group: `0..m`).
    pub groups: Vec<Range<usize>>,
}

/// The tables of a regressor the embedded predictor (`surrogate-predict`) evaluates: its
/// [`surrogate_predict::GpTables`] or [`surrogate_predict::PolyTables`].
#[derive(Debug, Clone, PartialEq)]
pub enum EmbeddedRegressor {
    /// A Gaussian process.
    Gp {
        /// Column-group boundaries (empty: one group).
        groups: Vec<u16>,
        /// Inverse length scales, `d` per group.
        inv_len: Vec<f64>,
        /// Training inputs over the length scales, `n × d` per group.
        xs: Vec<f64>,
        /// Weights, `n × m`.
        alpha: Vec<f64>,
    },
    /// A polynomial.
    Poly {
        /// Exponents, `n_terms × d`.
        exponents: Vec<u8>,
        /// Coefficients, `n_terms × m`.
        coef: Vec<f64>,
    },
}

impl EmbeddedRegressor {
    /// The embedded predictor's code of the regressor of a block
    /// ([`surrogate_predict::BlockTables::regressor`]).
    pub fn code(&self) -> u8 {
        match self {
            EmbeddedRegressor::Gp { .. } => 0,
            EmbeddedRegressor::Poly { .. } => 1,
        }
    }
}
