//! The trained surrogate: queries, predictions, standard deviations and gradients.
//!
//! A query `(N, T, P, μ₁, α₁, μ₂, α₂)` is mapped to the scaled features `x`, the regressors
//! give the POD coefficients `a(x)`, and each quantity `q` is read from its block at the
//! pressure stencil nodes: `y_q(P) = Σ_s w_s(P) (ȳ_e + s_e Σ_k Φ_ek a_k)`, `e = j_s·|Q| + slot_q`.
//! Gradients follow by the chain rule through `x(z(T, μ, α))`, `a(x)` and `w(P)`.
//! Standard deviations assume independent coefficient errors,
//! `Var y_q = Σ_k (Σ_s w_s s_e Φ_ek)² Var a_k`, rescaled per quantity by the held-out RMS of
//! the standardised errors (`std_scale`, from cross-validation).

use serde::{Deserialize, Serialize};

use super::fast::{Derived, ScalarPath, Source, SCALARS};
use super::metrics::Validation;
use super::pod::PodBasis;
pub use super::provenance::TrainingInfo;
use super::regression::{RegressorKind, Regressors};
use super::RomError;
use crate::case::{
    raw_features, BoundSnap, CaseInputs, Domain, DomainViolation, FeatureScaler, OgdenSet, Query,
};
use crate::schema;
use surrogate_predict::{marker_uy, marker_uz, stencil, N_FEATURES};

/// Number of differentiable inputs: `T, P, μ₁, α₁, μ₂, α₂` (N is discrete).
pub const N_GRAD_INPUTS: usize = 6;
/// Names of the differentiable inputs.
pub const GRAD_INPUT_NAMES: [&str; N_GRAD_INPUTS] = [
    schema::WALL_THICKNESS.name,
    schema::PRESSURE.name,
    schema::MU1.name,
    schema::ALPHA1.name,
    schema::MU2.name,
    schema::ALPHA2.name,
];

/// Why a number of bellows outside the model's list is refused, whatever the caller allows:
/// `N` is never extrapolated, and interpolated only by a model trained with `N` as an ordinal
/// input.
pub const N_NOT_EXTRAPOLATED: &str =
    "N is never extrapolated, not even with --allow-extrapolation, and interpolated only by a \
     model trained with --ordinal-n: train a model that includes it";

/// Buffers reused across predictions (so that `*_into` calls do not allocate).
///
/// One coefficient, variance and Jacobian buffer per regressor of the model.
#[derive(Debug, Clone, Default)]
struct Workspace {
    x: Vec<f64>,
    coef: Vec<Vec<f64>>,
    var: Vec<Vec<f64>>,
    jac: Vec<Vec<f64>>,
    scratch: Vec<f64>,
}

/// The outputs of a prediction, with optional standard deviations.
#[derive(Debug, Clone, Default)]
pub struct Prediction {
    /// The 22 quantities in [`QUANTITY_NAMES`](super::QUANTITY_NAMES) order.
    pub values: [f64; 22],
    /// Their standard deviations (filled by [`Surrogate::predict_with_std_into`]): the
    /// surrogate against the FE model only, not the model against real actuators
    /// ([`Surrogate::model_form_error`]).
    pub std: [f64; 22],
    /// Whether `std` is filled.
    pub has_std: bool,
    work: Workspace,
}

impl Prediction {
    /// Tip Uz, mm.
    pub fn tip_uz_mm(&self) -> f64 {
        self.values[super::Q_TIP_UZ]
    }
    /// Tip Uy, mm.
    pub fn tip_uy_mm(&self) -> f64 {
        self.values[super::Q_TIP_UY]
    }
    /// Bending angle, degrees.
    pub fn angle_deg(&self) -> f64 {
        self.values[super::Q_ANGLE]
    }
    /// Blocked force, N.
    pub fn force_n(&self) -> f64 {
        self.values[super::Q_FORCE]
    }
    /// Marker `k` as `(Uz, Uy)`, mm; `k = 1 … 9` as in the columns `m1` … `m9` (9 is the tip).
    ///
    /// # Panics
    /// `k` outside `1 … 9`.
    pub fn marker(&self, k: usize) -> (f64, f64) {
        let (z, y) = (marker_uz(k), marker_uy(k));
        (self.values[z], self.values[y])
    }
    /// Standard deviation of tip Uz, mm: the surrogate's error against the FE values only
    /// (filled by [`Surrogate::predict_with_std_into`]). How far the model misses real
    /// actuators is the model-form error, [`Surrogate::model_form_error`].
    pub fn std_tip_uz_mm(&self) -> f64 {
        self.std[super::Q_TIP_UZ]
    }
    /// Standard deviation of tip Uy, mm.
    pub fn std_tip_uy_mm(&self) -> f64 {
        self.std[super::Q_TIP_UY]
    }
    /// Standard deviation of the bending angle, degrees.
    pub fn std_angle_deg(&self) -> f64 {
        self.std[super::Q_ANGLE]
    }
    /// Standard deviation of the blocked force, N.
    pub fn std_force_n(&self) -> f64 {
        self.std[super::Q_FORCE]
    }
    /// Standard deviations of marker `k`'s `(Uz, Uy)`, mm, `k = 1 … 9`.
    ///
    /// # Panics
    /// `k` outside `1 … 9`.
    pub fn std_marker(&self, k: usize) -> (f64, f64) {
        let (z, y) = (marker_uz(k), marker_uy(k));
        (self.std[z], self.std[y])
    }
}

/// Derivatives `d[q][i] = ∂y_q/∂u_i`, `u = (T, P, μ₁, α₁, μ₂, α₂)` ([`GRAD_INPUT_NAMES`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jacobian {
    /// Row per quantity, column per differentiable input.
    pub d: [[f64; N_GRAD_INPUTS]; 22],
}

/// The derivatives of one output with respect to each differentiable input, by name.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Gradient {
    /// ∂/∂T (per mm).
    pub wall_thickness: f64,
    /// ∂/∂P (per bar; 0 outside the pressure grid, where the prediction is clamped).
    pub pressure: f64,
    /// ∂/∂μ₁ (per MPa).
    pub mu1: f64,
    /// ∂/∂α₁.
    pub alpha1: f64,
    /// ∂/∂μ₂ (per MPa).
    pub mu2: f64,
    /// ∂/∂α₂.
    pub alpha2: f64,
}

impl Gradient {
    /// The material part `[∂/∂μ₁, ∂/∂α₁, ∂/∂μ₂, ∂/∂α₂]`.
    pub fn material(&self) -> [f64; 4] {
        [self.mu1, self.alpha1, self.mu2, self.alpha2]
    }
}

impl Jacobian {
    /// The gradient of quantity `q` (index in [`QUANTITY_NAMES`](super::QUANTITY_NAMES)).
    ///
    /// # Panics
    /// `q ≥ 22`.
    pub fn of(&self, q: usize) -> Gradient {
        let d = &self.d[q];
        Gradient {
            wall_thickness: d[0],
            pressure: d[1],
            mu1: d[2],
            alpha1: d[3],
            mu2: d[4],
            alpha2: d[5],
        }
    }
    /// Gradient of tip Uz.
    pub fn tip_uz(&self) -> Gradient {
        self.of(super::Q_TIP_UZ)
    }
    /// Gradient of tip Uy.
    pub fn tip_uy(&self) -> Gradient {
        self.of(super::Q_TIP_UY)
    }
    /// Gradient of the bending angle.
    pub fn angle(&self) -> Gradient {
        self.of(super::Q_ANGLE)
    }
    /// Gradient of the blocked force.
    pub fn force(&self) -> Gradient {
        self.of(super::Q_FORCE)
    }
    /// Gradients of marker `k` as `(Uz, Uy)`, `k = 1 … 9` as in the columns `m1` … `m9`.
    ///
    /// # Panics
    /// `k` outside `1 … 9`.
    pub fn marker(&self, k: usize) -> (Gradient, Gradient) {
        (self.of(marker_uz(k)), self.of(marker_uy(k)))
    }
}

impl Default for Jacobian {
    fn default() -> Self {
        Jacobian {
            d: [[0.0; N_GRAD_INPUTS]; 22],
        }
    }
}

/// Name, unit and training range of an input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InputSpec {
    /// Name.
    pub name: String,
    /// Unit (`1` for dimensionless).
    pub unit: String,
    /// Smallest training value.
    pub min: f64,
    /// Largest training value.
    pub max: f64,
}

/// One POD block and the regressor that predicts its coefficients.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Block {
    /// `field` or the scalar's name.
    pub name: String,
    /// The basis.
    pub pod: PodBasis,
    /// Offset of the block's coefficients among the regression outputs.
    pub coef_offset: usize,
    /// Regressor used for this block.
    pub regressor: RegressorKind,
}

/// The reduced-order surrogate (see the [module docs](super)).
///
/// Read a model file with [`Surrogate::load`] or [`Surrogate::from_json`]: the regressors are
/// read through a [`Registry`](super::regression::Registry) (deserialising the struct alone
/// leaves them empty).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Surrogate {
    /// Inputs with units and training bounds (N, T, P, μ₁, α₁, μ₂, α₂).
    pub inputs: Vec<InputSpec>,
    /// Output names and units.
    pub outputs: Vec<String>,
    /// Numbers of bellows the model predicts: the trained ones or, with `N` as an ordinal
    /// input ([`TrainConfig::ordinal_n`](super::TrainConfig::ordinal_n)), every integer
    /// between the trained ends.
    pub n_allowed: Vec<u32>,
    /// Numbers of bellows present in training, where they differ from [`Self::n_allowed`]
    /// (ordinal `N`); empty otherwise ([`Self::n_trained`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub n_trained: Vec<u32>,
    /// Pressure grid, bar.
    pub pressures: Vec<f64>,
    /// Feature scaling.
    pub features: FeatureScaler,
    /// POD blocks.
    pub blocks: Vec<Block>,
    /// The fitted regressors, each over all blocks' coefficients (in the model file: one
    /// entry per regressor under its name, `"gp": {…}, "poly": {…}`).
    #[serde(flatten, skip_deserializing)]
    pub regressors: Regressors,
    /// Block predicting each quantity.
    pub output_block: Vec<usize>,
    /// Index of each quantity among its block's quantities.
    pub output_slot: Vec<usize>,
    /// Factor applied to each quantity's predictive std: the held-out `z_rms` of its chosen
    /// predictor (post-hoc calibration, so that standardised held-out errors have RMS ≈ 1).
    pub std_scale: Vec<f64>,
    /// Held-out validation computed at training time.
    pub validation: Validation,
    /// Provenance.
    pub training: TrainingInfo,
    /// The model-form error learned from a calibration through this model
    /// ([`super::model_form`]); stored in the model file beside the model, outside its
    /// checksum (attaching it does not change the model's identity).
    #[serde(skip)]
    pub model_form: Option<super::model_form::ModelFormError>,
    /// Tables derived from the above on first use (the scalar fast path); not stored.
    #[serde(skip)]
    pub derived: Derived,
}

impl Surrogate {
    /// Numbers of bellows present in training (a subset of [`Self::n_allowed`]).
    pub fn n_trained(&self) -> &[u32] {
        if self.n_trained.is_empty() {
            &self.n_allowed
        } else {
            &self.n_trained
        }
    }

    /// A prediction buffer sized for this model.
    pub fn new_prediction(&self) -> Prediction {
        let mut p = Prediction::default();
        self.ensure_workspace(&mut p.work);
        p
    }

    /// The folded tables of the scalar fast path (built on first call).
    fn scalar_path(&self) -> &ScalarPath {
        self.derived.get_or_build(|| {
            // a block whose regressor the model lacks fails the consistency check
            let block_regressor: Vec<usize> = self
                .blocks
                .iter()
                .map(|b| self.regressors.position(&b.regressor).unwrap_or(usize::MAX))
                .collect();
            let sources: Vec<Source<'_>> = SCALARS
                .map(|q| {
                    let b = &self.blocks[self.output_block[q]];
                    Source {
                        quantity: q,
                        pod: &b.pod,
                        regressor: block_regressor[self.output_block[q]],
                        coef_offset: b.coef_offset,
                        slot: self.output_slot[q],
                    }
                })
                .collect();
            ScalarPath::build(
                &self.regressors,
                &sources,
                self.pressures.len(),
                block_regressor,
            )
        })
    }

    /// Number of regression outputs (the POD coefficients of all blocks).
    pub fn n_coefs(&self) -> usize {
        self.regressors.iter().next().map_or(0, |r| r.n_outputs())
    }

    fn ensure_workspace(&self, w: &mut Workspace) {
        let (d, m, nr) = (self.features.dim(), self.n_coefs(), self.regressors.len());
        let s = self
            .regressors
            .iter()
            .map(|r| r.scratch_len())
            .fold(self.scalar_path().scratch_len(), usize::max);
        let sized = |v: &[Vec<f64>], len: usize| v.len() == nr && v.iter().all(|c| c.len() == len);
        if w.x.len() != d || !sized(&w.coef, m) || w.scratch.len() != s || !sized(&w.jac, m * d) {
            w.x = vec![0.0; d];
            w.coef = vec![vec![0.0; m]; nr];
            w.var = vec![vec![0.0; m]; nr];
            w.jac = vec![vec![0.0; m * d]; nr];
            w.scratch = vec![0.0; s];
        }
    }

    /// Checks a query: finite inputs, trained `N`, admissible material.
    ///
    /// # Errors
    /// [`RomError::InvalidInput`] naming the field.
    pub fn check_query(&self, q: &Query) -> Result<(), RomError> {
        let names = ["n", "t_mm", "p_bar", "mu1", "alpha1", "mu2", "alpha2"];
        for (name, v) in names.iter().zip(q.as_array()) {
            if !v.is_finite() {
                return Err(RomError::invalid(name, v, "a finite number"));
            }
        }
        if !self.n_allowed.contains(&q.n) {
            return Err(RomError::invalid(
                "n",
                q.n,
                &format!(
                    "one of the numbers of bellows the model predicts {:?} ({N_NOT_EXTRAPOLATED})",
                    self.n_allowed
                ),
            ));
        }
        if q.material.mu1_mpa * q.material.alpha1 <= 0.0 {
            return Err(RomError::invalid(
                "mu1*alpha1",
                q.material.mu1_mpa * q.material.alpha1,
                "> 0 (admissible Ogden term)",
            ));
        }
        if q.material.mu2_mpa * q.material.alpha2 <= 0.0 {
            return Err(RomError::invalid(
                "mu2*alpha2",
                q.material.mu2_mpa * q.material.alpha2,
                "> 0 (admissible Ogden term)",
            ));
        }
        Ok(())
    }

    /// The training domain: the ranges the model file states from its snapshot plan
    /// ([`TrainingInfo::plan_domain`]: the plan's nominal ends where its cases cover them),
    /// else the box of the training cases ([`Self::sampled_domain`]); the trained numbers of
    /// bellows and the pressure grid ([`crate::case::domain`]).
    pub fn domain(&self) -> Domain {
        let sampled = self.sampled_domain();
        match &self.training.plan_domain {
            Some(plan) => sampled.with_stated(&plan.ranges),
            None => sampled,
        }
    }

    /// The box of the training cases in the regression's coordinates (`T, μ0, s, α₁, α₂`),
    /// the trained numbers of bellows and the pressure grid.
    pub fn sampled_domain(&self) -> Domain {
        // a feature constant over the training cases is not in the scaler: its value follows
        // from the inputs' (equal) bounds, when the inputs it depends on are all constant
        let fixed = |i: usize| {
            let s = &self.inputs[i];
            (s.min == s.max).then_some(s.min)
        };
        let constant = |f: usize| -> Option<f64> {
            match f {
                1 => fixed(1),
                3 => fixed(4),
                5 => fixed(6),
                _ => Some(
                    raw_features(&CaseInputs {
                        n_bellows: 0,
                        wall_thickness_mm: 0.0,
                        material: OgdenSet {
                            mu1_mpa: fixed(3)?,
                            alpha1: fixed(4)?,
                            mu2_mpa: fixed(5)?,
                            alpha2: fixed(6)?,
                        },
                    })[f],
                ),
            }
        };
        Domain::from_features(&self.n_allowed, &self.pressures, &self.features, constant)
    }

    /// The inputs of `q` outside the training domain ([`Domain::violations`]): an empty list
    /// means the prediction interpolates. Outside the pressure grid the prediction is clamped
    /// to the grid's nearer end; outside the feature box it extrapolates.
    pub fn domain_violations(&self, q: &Query) -> Vec<DomainViolation> {
        self.domain().violations(q)
    }

    /// `q` with every input beyond an end of the domain by at most
    /// [`BOUND_TOLERANCE`](crate::case::BOUND_TOLERANCE) of its range moved onto the end,
    /// and a note for each ([`Domain::snap`]).
    pub fn snap_to_domain(&self, q: &Query) -> (Query, Vec<BoundSnap>) {
        self.domain().snap(q)
    }

    /// The domain violations of `q`, refused unless `allow_extrapolation`.
    ///
    /// # Errors
    /// [`RomError::OutsideDomain`] naming every input outside, with its value and range.
    pub fn check_domain(
        &self,
        q: &Query,
        allow_extrapolation: bool,
    ) -> Result<Vec<DomainViolation>, RomError> {
        let v = self.domain_violations(q);
        if !v.is_empty() && !allow_extrapolation {
            let text: Vec<String> = v.iter().map(DomainViolation::to_string).collect();
            return Err(RomError::OutsideDomain(text.join("; ")));
        }
        Ok(v)
    }

    fn features_into(&self, q: &Query, w: &mut Workspace) -> [f64; N_FEATURES] {
        let z = raw_features(&q.case());
        self.features.scale_into(&z, &mut w.x);
        z
    }

    /// The coefficient columns of regressor `r` the quantities `range` need (empty if none).
    fn needed_cols(&self, range: std::ops::Range<usize>, r: usize) -> std::ops::Range<usize> {
        let path = self.scalar_path();
        let (mut lo, mut hi) = (usize::MAX, 0usize);
        for q in range {
            let bi = self.output_block[q];
            if path.block_regressor(bi) == r {
                let b = &self.blocks[bi];
                lo = lo.min(b.coef_offset);
                hi = hi.max(b.coef_offset + b.pod.n_modes);
            }
        }
        lo.min(hi)..hi
    }

    /// Predicts all 22 quantities into `pred` (no allocation once `pred` is sized).
    ///
    /// The query is not checked against the training domain (a controller's hot path):
    /// outside the pressure grid the values at its nearer end are returned, outside the
    /// feature box the regression extrapolates. [`Self::domain_violations`] says which.
    ///
    /// # Errors
    /// Invalid query (see [`Self::check_query`]).
    pub fn predict_into(&self, q: &Query, pred: &mut Prediction) -> Result<(), RomError> {
        self.predict_range_into(q, pred, 0..22)
    }

    /// Predicts only tip Uz, tip Uy, angle and force (the other values are left as they were).
    ///
    /// # Errors
    /// Invalid query.
    pub fn predict_scalars_into(&self, q: &Query, pred: &mut Prediction) -> Result<(), RomError> {
        if !self.scalar_path().is_complete() {
            return self.predict_range_into(q, pred, SCALARS);
        }
        self.check_query(q)?;
        self.ensure_workspace(&mut pred.work);
        let w = &mut pred.work;
        self.features_into(q, w);
        let st = stencil(&self.pressures, q.p_bar);
        self.scalar_path().predict_into(
            &self.regressors,
            &w.x,
            &st,
            &mut pred.values,
            &mut w.scratch,
        );
        pred.has_std = false;
        Ok(())
    }

    /// [`Self::predict_scalars_into`] through the general path (all modes of the scalar
    /// blocks, no folding): the reference the fast path is tested against.
    ///
    /// # Errors
    /// Invalid query.
    pub fn predict_scalars_unfolded_into(
        &self,
        q: &Query,
        pred: &mut Prediction,
    ) -> Result<(), RomError> {
        self.predict_range_into(q, pred, SCALARS)
    }

    /// Allocating convenience wrapper of [`Self::predict_into`].
    ///
    /// # Errors
    /// Invalid query.
    pub fn predict(&self, q: &Query) -> Result<Prediction, RomError> {
        let mut p = self.new_prediction();
        self.predict_into(q, &mut p)?;
        Ok(p)
    }

    fn predict_range_into(
        &self,
        q: &Query,
        pred: &mut Prediction,
        range: std::ops::Range<usize>,
    ) -> Result<(), RomError> {
        self.check_query(q)?;
        self.ensure_workspace(&mut pred.work);
        let w = &mut pred.work;
        self.features_into(q, w);
        for (r, reg) in self.regressors.iter().enumerate() {
            let cols = self.needed_cols(range.clone(), r);
            if cols.start < cols.end {
                reg.predict_cols_into(&w.x, cols, &mut w.coef[r], &mut w.scratch);
            }
        }
        let path = self.scalar_path();
        let st = stencil(&self.pressures, q.p_bar);
        for qi in range {
            let bi = self.output_block[qi];
            let b = &self.blocks[bi];
            let coef =
                &w.coef[path.block_regressor(bi)][b.coef_offset..b.coef_offset + b.pod.n_modes];
            let nq = b.pod.quantities.len();
            let mut v = 0.0;
            for s in 0..st.len {
                v += st.w[s]
                    * b.pod
                        .entry((st.start + s) * nq + self.output_slot[qi], coef);
            }
            pred.values[qi] = v;
        }
        pred.has_std = false;
        Ok(())
    }

    /// Predicts all quantities and their standard deviations.
    ///
    /// # Errors
    /// Invalid query.
    pub fn predict_with_std_into(&self, q: &Query, pred: &mut Prediction) -> Result<(), RomError> {
        self.predict_into(q, pred)?;
        let w = &mut pred.work;
        for (r, reg) in self.regressors.iter().enumerate() {
            if !self.needed_cols(0..22, r).is_empty() {
                reg.variance_into(&w.x, &mut w.var[r], &mut w.scratch);
            }
        }
        let path = self.scalar_path();
        let st = stencil(&self.pressures, q.p_bar);
        for qi in 0..22 {
            let bi = self.output_block[qi];
            let b = &self.blocks[bi];
            let var =
                &w.var[path.block_regressor(bi)][b.coef_offset..b.coef_offset + b.pod.n_modes];
            let (nq, r) = (b.pod.quantities.len(), b.pod.n_modes);
            let mut total = 0.0;
            for (k, vk) in var.iter().enumerate() {
                let mut dk = 0.0;
                for s in 0..st.len {
                    let e = (st.start + s) * nq + self.output_slot[qi];
                    dk += st.w[s] * b.pod.scale[e] * b.pod.modes[e * r + k];
                }
                total += dk * dk * vk;
            }
            pred.std[qi] = total.sqrt() * self.std_scale[qi];
        }
        pred.has_std = true;
        Ok(())
    }

    /// Predicts all quantities and their derivatives with respect to `T, P, μ₁, α₁, μ₂, α₂`.
    ///
    /// Outside the pressure grid the prediction is clamped to the grid's nearer end, so the
    /// derivative with respect to `P` is **zero** there (not the slope at the end); outside the
    /// feature box the derivatives are those of the extrapolating regression. Check
    /// [`Self::domain_violations`] before trusting either.
    ///
    /// # Errors
    /// Invalid query.
    pub fn gradient_into(
        &self,
        q: &Query,
        pred: &mut Prediction,
        jac: &mut Jacobian,
    ) -> Result<(), RomError> {
        self.gradient_range_into(q, 0..22, pred, jac)
    }

    /// [`Self::gradient_into`] for the quantities `range` only (their values and Jacobian
    /// rows; the others are left as they were): a fit to tip, angle and force needs only
    /// `Q_TIP_UZ..=Q_FORCE`, and skips the coefficients of blocks it does not read.
    ///
    /// # Errors
    /// Invalid query, or a range outside `0..22`.
    pub fn gradient_range_into(
        &self,
        q: &Query,
        range: std::ops::Range<usize>,
        pred: &mut Prediction,
        jac: &mut Jacobian,
    ) -> Result<(), RomError> {
        if range.end > 22 || range.start >= range.end {
            return Err(RomError::invalid(
                "quantity range",
                format!("{range:?}"),
                "a non-empty range inside 0..22",
            ));
        }
        self.check_query(q)?;
        self.ensure_workspace(&mut pred.work);
        let w = &mut pred.work;
        self.features_into(q, w);
        for (r, reg) in self.regressors.iter().enumerate() {
            if !self.needed_cols(range.clone(), r).is_empty() {
                reg.jacobian_into(&w.x, &mut w.coef[r], &mut w.jac[r], &mut w.scratch);
            }
        }
        let path = self.scalar_path();
        // dz_f/du_i for u = (T, P, μ1, α1, μ2, α2), z = (N, T, ln μ0, α1, s, α2) with
        // k_i = μ_i α_i, μ0 = (k1 + k2)/2, s = k1/(k1 + k2)
        let (k1, k2) = (
            q.material.mu1_mpa * q.material.alpha1,
            q.material.mu2_mpa * q.material.alpha2,
        );
        let ks = k1 + k2;
        // d/dk1 and d/dk2 of ln μ0 and of s
        let (dl1, dl2) = (1.0 / ks, 1.0 / ks);
        let (ds1, ds2) = (k2 / (ks * ks), -k1 / (ks * ks));
        let mut dz = [[0.0; N_GRAD_INPUTS]; N_FEATURES];
        dz[1][0] = 1.0;
        dz[2][2] = dl1 * q.material.alpha1;
        dz[2][3] = dl1 * q.material.mu1_mpa;
        dz[2][4] = dl2 * q.material.alpha2;
        dz[2][5] = dl2 * q.material.mu2_mpa;
        dz[3][3] = 1.0;
        dz[4][2] = ds1 * q.material.alpha1;
        dz[4][3] = ds1 * q.material.mu1_mpa;
        dz[4][4] = ds2 * q.material.alpha2;
        dz[4][5] = ds2 * q.material.mu2_mpa;
        dz[5][5] = 1.0;
        let d = self.features.dim();
        let st = stencil(&self.pressures, q.p_bar);
        for qi in range {
            let b = &self.blocks[self.output_block[qi]];
            let ki = path.block_regressor(self.output_block[qi]);
            let off = b.coef_offset;
            let coef = &w.coef[ki][off..off + b.pod.n_modes];
            let (nq, r) = (b.pod.quantities.len(), b.pod.n_modes);
            let mut v = 0.0;
            let mut dv_dp = 0.0;
            let mut dv_dx = [0.0; N_FEATURES];
            for s in 0..st.len {
                let e = (st.start + s) * nq + self.output_slot[qi];
                let y = b.pod.entry(e, coef);
                v += st.w[s] * y;
                dv_dp += st.dw[s] * y;
                for k in 0..r {
                    let c = st.w[s] * b.pod.scale[e] * b.pod.modes[e * r + k];
                    for (j, dx) in dv_dx.iter_mut().enumerate().take(d) {
                        *dx += c * w.jac[ki][(off + k) * d + j];
                    }
                }
            }
            pred.values[qi] = v;
            let row = &mut jac.d[qi];
            *row = [0.0; N_GRAD_INPUTS];
            row[1] = dv_dp;
            for (j, &f) in self.features.index.iter().enumerate() {
                let g = dv_dx[j] * self.features.inv_half[j];
                for (i, r) in row.iter_mut().enumerate() {
                    *r += g * dz[f][i];
                }
            }
        }
        pred.has_std = false;
        Ok(())
    }
}

impl Surrogate {
    /// The model-form error the model file carries (`None`: none was attached,
    /// `surrogate model-form`).
    pub fn model_form(&self) -> Option<&super::model_form::ModelFormError> {
        self.model_form.as_ref()
    }

    /// The model-form error at `q`'s pressure, per output ([`ModelFormEstimate`](super::model_form::ModelFormEstimate)); `None` when
    /// the model carries none. The surrogate's own error is [`Surrogate::predict_with_std_into`].
    pub fn model_form_error(&self, q: &Query) -> Option<super::model_form::ModelFormEstimate> {
        self.model_form.as_ref().map(|m| m.at(q.p_bar))
    }
}
