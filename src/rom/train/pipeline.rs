//! One fit of the training pipeline: features → POD blocks (the field and one per scalar) →
//! coefficients → a fit of every regressor of the registry; and the settings of training.

use crate::case::{raw_features, FeatureScaler};
use crate::rom::data::{CaseRamp, PartialRamp};
use crate::rom::pod::PodBasis;
use crate::rom::regression::gp::{Gp, GpParams};
use crate::rom::regression::poly::{Poly, PolyParams};
use crate::rom::regression::{
    Data, DynRegressor, Registry, Regressor, RegressorKind, TrainingSettings,
};
use crate::rom::{RomError, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::schema;
use surrogate_predict::N_FEATURES;

/// Training settings.
#[derive(Debug, Clone)]
pub struct TrainConfig {
    /// Number of cross-validation folds (by case); clamped to the number of cases.
    pub folds: usize,
    /// Seed of the fold assignment.
    pub seed: u64,
    /// Number of fold assignments (repeated k-fold): the held-out errors pool every
    /// repeat's folds, which steadies the estimate when a few cases dominate it (costs
    /// `repeats × folds` fits). Repeat `r` draws its folds with seed `seed + r`.
    pub repeats: usize,
    /// POD energy tolerance (discarded fraction).
    pub pod_tol: f64,
    /// Largest number of modes of the field block.
    pub max_field_modes: usize,
    /// Largest number of modes of each direct block.
    pub max_direct_modes: usize,
    /// Gaussian-process settings, among them the inducing points of a sparse fit
    /// ([`GpParams::inducing`]; recorded in the model's
    /// [`TrainingInfo::gp_inducing`](crate::rom::provenance::TrainingInfo::gp_inducing)).
    pub gp: GpParams,
    /// One GP kernel (hyperparameters and correlation matrix) per POD block instead of one
    /// shared by all: each output gets its own length scales, at the cost of one kernel
    /// vector per block in a prediction.
    pub kernel_per_block: bool,
    /// Polynomial settings.
    pub poly: PolyParams,
    /// The regressors fitted (every one, in order) and chosen among.
    pub regressors: Registry,
    /// Restrict the choice to one regressor of the registry (tests, export checks).
    pub only: Option<RegressorKind>,
    /// Latency preference: the polynomial (≈ 1–2 µs) is kept unless another regressor's
    /// held-out RMSE is smaller by more than this relative margin (0: pure accuracy).
    pub prefer_poly_within: f64,
    /// Use truncated ramps (covering ≥ half the grid) for the regression, their coefficients
    /// fitted to the converged entries by gappy POD (they never enter the POD bases nor the
    /// held-out sets).
    pub fill_truncated: bool,
    /// `N` as an ordinal input: the model predicts every integer `N` between the smallest
    /// and the largest trained one (the regression already treats `N` as a number), not
    /// only the trained ones. Off: only the trained `N` are predicted. Whether the
    /// interpolation in `N` is accurate enough is measured by holding `N` values out
    /// ([`crate::rom::held_out_n`]).
    pub ordinal_n: bool,
}

impl Default for TrainConfig {
    fn default() -> Self {
        TrainConfig {
            folds: 5,
            seed: 2024,
            repeats: 1,
            pod_tol: 1e-7,
            max_field_modes: 24,
            max_direct_modes: 8,
            gp: GpParams::default(),
            kernel_per_block: false,
            poly: PolyParams::default(),
            regressors: Registry::builtin(),
            only: None,
            prefer_poly_within: 0.0,
            fill_truncated: false,
            ordinal_n: false,
        }
    }
}

impl TrainConfig {
    /// These settings, with what a model records of how it was trained taken from its
    /// training information `info`: `N` as an ordinal input and the sparse GP's inducing
    /// points. A surrogate retrained on a grown set (an adaptive refinement, a box
    /// extension) is then trained like the one it replaces.
    pub fn like(self, info: &crate::rom::provenance::TrainingInfo) -> Self {
        TrainConfig {
            ordinal_n: info.ordinal_n(),
            gp: GpParams {
                inducing: info.gp_inducing,
                ..self.gp
            },
            ..self
        }
    }
}

/// A fitted pipeline (one fold or the final model).
pub struct Fitted {
    pub(super) features: FeatureScaler,
    pub(super) blocks: Vec<(String, PodBasis, usize)>,
    /// One per registry entry, in its order.
    pub(super) regressors: Vec<Box<dyn DynRegressor>>,
}

/// The scalar outputs: name and quantity index, in the order of the direct blocks.
pub(super) const SCALARS: [(&str, usize); 4] = [
    (schema::TIP_UZ.name, Q_TIP_UZ),
    (schema::TIP_UY.name, Q_TIP_UY),
    (schema::ANGLE.name, Q_ANGLE),
    (schema::FORCE.name, Q_FORCE),
];

/// Fits features, POD blocks and every regressor of `cfg.regressors` to `cases`.
///
/// # Errors
/// Too few cases or a numerical failure.
pub fn fit_pipeline(
    cases: &[CaseRamp],
    partial: &[PartialRamp],
    cfg: &TrainConfig,
) -> Result<Fitted, RomError> {
    let z: Vec<[f64; N_FEATURES]> = cases
        .iter()
        .map(|c| raw_features(&c.inputs))
        .chain(partial.iter().map(|c| raw_features(&c.inputs)))
        .collect();
    let features = FeatureScaler::fit(&z);
    let d = features.dim();
    if d == 0 {
        return Err(RomError::InsufficientData(
            "every input is constant over the cases".into(),
        ));
    }
    let n_complete = cases.len();
    let n = z.len();
    let mut x = vec![0.0; n * d];
    for (i, zi) in z.iter().enumerate() {
        features.scale_into(zi, &mut x[i * d..(i + 1) * d]);
    }
    let max_modes = |m: usize| m.min(n_complete - 1).max(1);
    let mut blocks = Vec::new();
    let field: Vec<usize> = (0..22).collect();
    let mut offset = 0;
    let pod = PodBasis::fit(cases, &field, cfg.pod_tol, max_modes(cfg.max_field_modes))?;
    offset += pod.n_modes;
    blocks.push(("field".to_string(), pod, 0));
    for (name, q) in SCALARS {
        let pod = PodBasis::fit(cases, &[q], cfg.pod_tol, max_modes(cfg.max_direct_modes))?;
        let r = pod.n_modes;
        blocks.push((name.to_string(), pod, offset));
        offset += r;
    }
    let m = offset;
    let mut y = vec![0.0; n * m];
    let mut weights = vec![0.0; m];
    for (_, pod, off) in &blocks {
        let energy: f64 =
            pod.singular_values.iter().map(|s| s * s).sum::<f64>() / n_complete as f64;
        for k in 0..pod.n_modes {
            weights[off + k] = 1.0 / energy.max(1e-300).sqrt();
        }
        let r = pod.n_modes;
        for (i, c) in cases.iter().enumerate() {
            let snap = PodBasis::snapshot_of(&pod.quantities, c);
            pod.project_into(&snap, &mut y[i * m + off..i * m + off + r]);
        }
        for (i, c) in partial.iter().enumerate() {
            let (snap, observed) = partial_snapshot(&pod.quantities, c);
            let row = (n_complete + i) * m + off;
            pod.gappy_project_into(&snap, &observed, n_complete, &mut y[row..row + r])?;
        }
    }
    let data = Data {
        x: &x,
        y: &y,
        n,
        d,
        m,
        weights: &weights,
    };
    let mut bounds: Vec<usize> = blocks.iter().map(|(_, _, off)| *off).collect();
    bounds.push(m);
    let params: [(&str, &(dyn std::any::Any + Send + Sync)); 2] =
        [(Gp::NAME, &cfg.gp), (Poly::NAME, &cfg.poly)];
    let settings = TrainingSettings {
        blocks: &bounds,
        kernel_per_block: cfg.kernel_per_block,
        params: &params,
    };
    let regressors = cfg
        .regressors
        .entries()
        .iter()
        .map(|e| e.fit(&data, &settings))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Fitted {
        features,
        blocks,
        regressors,
    })
}

/// Block snapshot of a partial ramp (zeros where unobserved) and the observed mask.
fn partial_snapshot(quantities: &[usize], c: &PartialRamp) -> (Vec<f64>, Vec<bool>) {
    let mut y = Vec::new();
    let mut obs = Vec::new();
    for v in &c.values {
        for &q in quantities {
            y.push(v.map_or(0.0, |v| v[q]));
            obs.push(v.is_some());
        }
    }
    (y, obs)
}
