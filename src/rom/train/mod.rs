//! Training: fit the pipeline, cross-validate by case, choose the predictor of each output.
//!
//! Stages: features → POD blocks → coefficients → a fit of every regressor of the registry
//! ([`TrainConfig::regressors`]; the GP and the polynomial by default) ([`fit_pipeline`]);
//! k-fold cross-validation by case runs the same pipeline per fold (folds in parallel; each
//! fold is deterministic, so results do not depend on the thread count); the held-out errors
//! choose the regressor of the field block (by marker RMSE) and the source of each scalar
//! (field or direct block, and its regressor, by its RMSE); the final model is fitted on all
//! cases.
//!
//! The settings and the fit of one pipeline are in `pipeline`, the cross-validation and the
//! choice in `cross_validation`; this module runs them and assembles the model.

mod cross_validation;
mod pipeline;

pub use pipeline::{fit_pipeline, Fitted, TrainConfig};

use cross_validation::{cand_index, choose, cross_validate_and_fit, repeat_folds};
use pipeline::SCALARS;

use super::data::CaseSet;
use super::metrics::{ErrorAccumulator, InterpolationCheck, Validation};
use super::provenance::{TrainingInfo, N_ORDINAL};
use super::regression::{Registry, Regressors};
use super::surrogate::{Block, InputSpec, Surrogate};
use super::{RomError, N_MARKER_COMPONENTS, QUANTITY_NAMES, Q_TIP_UZ};
use crate::case::CaseInputs;
use crate::schema::{self, Quantity};

/// What training produced, besides the model.
#[derive(Debug, Clone)]
pub struct TrainReport {
    /// The trained surrogate.
    pub surrogate: Surrogate,
    /// Cases dropped (id, reason).
    pub dropped: Vec<(String, String)>,
    /// Wall time, seconds.
    pub seconds: f64,
    /// Wall time of the final fit alone (POD, hyperparameter search, weights), seconds; it ran
    /// beside the validation fits, so on a machine with fewer cores than fits it is an upper
    /// bound of the fit's own time.
    pub final_fit_seconds: f64,
    /// Pipeline fits made: one per fold and fold assignment, plus the final fit.
    pub fits: usize,
    /// The held-out predictions of the scalar outputs by their chosen source (one per case,
    /// grid pressure and scalar, cases in set order), for parity plots and error maps.
    pub held_out: Vec<HeldOutPoint>,
}

/// One held-out prediction of a scalar output in the cross-validation: the case was in the
/// fold left out of the fit that predicted it.
#[derive(Debug, Clone, PartialEq)]
pub struct HeldOutPoint {
    /// Case identifier.
    pub case_id: String,
    /// Number of bellows of the case.
    pub n_bellows: u32,
    /// Repeat (fold assignment) of this prediction, from 0.
    pub repeat: usize,
    /// Fold that held the case out in that repeat.
    pub fold: usize,
    /// Grid pressure, bar.
    pub p_bar: f64,
    /// Output name (`tip_uz_mm`, `tip_uy_mm`, `angle_deg`, `force_n`).
    pub output: &'static str,
    /// FE value.
    pub truth: f64,
    /// Prediction of the model fitted without the case's fold.
    pub predicted: f64,
    /// Predictive standard deviation, calibrated by the output's `std_ratio` (0 if the
    /// regressor gives none).
    pub std: f64,
}

/// Leave-one-node-out check of the pressure interpolation on the training ramps.
fn interpolation_check(set: &CaseSet) -> Vec<InterpolationCheck> {
    let grid = &set.pressures;
    let n_p = grid.len();
    if n_p < 4 {
        return Vec::new();
    }
    let mut acc = vec![ErrorAccumulator::default(); 5];
    for j in 1..n_p - 1 {
        let reduced: Vec<f64> = grid
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != j)
            .map(|(_, &p)| p)
            .collect();
        let st = surrogate_predict::stencil(&reduced, grid[j]);
        let node = |s: usize| {
            if st.start + s < j {
                st.start + s
            } else {
                st.start + s + 1
            }
        };
        for case in &set.cases {
            for q in 0..22 {
                let y: f64 = (0..st.len).map(|s| st.w[s] * case.values[node(s)][q]).sum();
                let output = if q < N_MARKER_COMPONENTS {
                    0
                } else {
                    q - Q_TIP_UZ + 1
                };
                acc[output].add(case.values[j][q], y);
            }
        }
    }
    let names = schema::names(&schema::VALIDATION_GROUPS);
    names
        .iter()
        .zip(acc)
        .map(|(n, a)| InterpolationCheck {
            name: n.to_string(),
            stats: a.finish(),
        })
        .collect()
}

fn input_specs(cases: &[CaseInputs], pressures: &[f64]) -> Vec<InputSpec> {
    type Getter = fn(&CaseInputs) -> f64;
    let get: [(Quantity, Getter); 6] = [
        (schema::N_BELLOWS, |c| c.n_bellows as f64),
        (schema::WALL_THICKNESS, |c| c.wall_thickness_mm),
        (schema::MU1, |c| c.material.mu1_mpa),
        (schema::ALPHA1, |c| c.material.alpha1),
        (schema::MU2, |c| c.material.mu2_mpa),
        (schema::ALPHA2, |c| c.material.alpha2),
    ];
    let spec = |(q, f): (Quantity, Getter)| InputSpec {
        name: q.name.into(),
        unit: q.unit.into(),
        min: cases.iter().map(f).fold(f64::INFINITY, f64::min),
        max: cases.iter().map(f).fold(f64::NEG_INFINITY, f64::max),
    };
    let mut v: Vec<InputSpec> = get.into_iter().map(spec).collect();
    v.insert(
        2,
        InputSpec {
            name: schema::PRESSURE.name.into(),
            unit: schema::PRESSURE.unit.into(),
            min: pressures[0],
            max: pressures[pressures.len() - 1],
        },
    );
    v
}

/// The surrogate from the final fit and the chosen sources of the outputs.
fn assemble(
    set: &CaseSet,
    fitted: Fitted,
    registry: &Registry,
    (field_kind, scalar_choice): (usize, [(usize, usize); 4]),
    validation: Validation,
    training: TrainingInfo,
) -> Surrogate {
    let kind_of = |k: usize| registry.entries()[k].kind();
    let mut blocks: Vec<Block> = fitted
        .blocks
        .into_iter()
        .map(|(name, pod, coef_offset)| Block {
            name,
            pod,
            coef_offset,
            regressor: kind_of(field_kind),
        })
        .collect();
    let mut output_block: Vec<usize> = vec![0; 22];
    let mut output_slot: Vec<usize> = (0..22).collect();
    for (si, &(direct, kind)) in scalar_choice.iter().enumerate() {
        if direct == 1 {
            blocks[si + 1].regressor = kind_of(kind);
            output_block[Q_TIP_UZ + si] = si + 1;
            output_slot[Q_TIP_UZ + si] = 0;
        }
    }
    let mut regression_points: Vec<CaseInputs> = set.cases.iter().map(|c| c.inputs).collect();
    if training.filled_cases > 0 {
        regression_points.extend(set.partial.iter().map(|c| c.inputs));
    }
    let (n_allowed, n_trained) = predicted_n(&regression_points, training.ordinal_n());
    let std_scale = (0..22)
        .map(|q| {
            let o = if q < N_MARKER_COMPONENTS {
                0
            } else {
                q - Q_TIP_UZ + 1
            };
            let z = validation.outputs[o].std_ratio;
            if z > 0.0 && z.is_finite() {
                z
            } else {
                1.0
            }
        })
        .collect();
    Surrogate {
        inputs: input_specs(&regression_points, &set.pressures),
        outputs: QUANTITY_NAMES.iter().map(|s| s.to_string()).collect(),
        n_allowed,
        n_trained,
        pressures: set.pressures.clone(),
        features: fitted.features,
        blocks,
        regressors: Regressors::new(fitted.regressors),
        output_block,
        output_slot,
        std_scale,
        validation,
        training,
        model_form: None,
        derived: Default::default(),
    }
}

/// The numbers of bellows a model predicts and, when they differ (ordinal `N`), the trained
/// ones: every integer between the trained ends, or the trained ones alone.
fn predicted_n(points: &[CaseInputs], ordinal: bool) -> (Vec<u32>, Vec<u32>) {
    let mut trained: Vec<u32> = points.iter().map(|c| c.n_bellows).collect();
    trained.sort_unstable();
    trained.dedup();
    match (ordinal, trained.first(), trained.last()) {
        (true, Some(&lo), Some(&hi)) if (hi - lo + 1) as usize > trained.len() => {
            ((lo..=hi).collect(), trained)
        }
        _ => (trained, Vec::new()),
    }
}

/// How a model treats `N`, as its training information states it.
fn n_treatment(ordinal: bool) -> String {
    if ordinal {
        N_ORDINAL.into()
    } else {
        "numeric regression input; predictions only at trained N".into()
    }
}

/// Trains a surrogate on a case set: cross-validation, choice, final fit.
/// `progress(done, total)` is called after each fold and after the final fit.
///
/// # Errors
/// Fewer than 4 cases, or a numerical failure.
pub fn train(
    set: &CaseSet,
    source: &str,
    skipped_unconverged: usize,
    cfg: &TrainConfig,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<TrainReport, RomError> {
    let start = std::time::Instant::now();
    let n = set.cases.len();
    if n < 4 {
        return Err(RomError::InsufficientData(format!(
            "{n} complete cases; at least 4 are needed"
        )));
    }
    if let Some(only) = &cfg.only {
        if cfg.regressors.get(only.name()).is_none() {
            return Err(RomError::invalid(
                "only",
                only,
                &format!("one of the regressors {:?}", cfg.regressors.names()),
            ));
        }
    }
    let k = cfg.folds.clamp(2, n);
    let (table, (fitted, final_fit_seconds), raw) = cross_validate_and_fit(set, k, cfg, progress)?;
    let scheme = match cfg.repeats.max(1) {
        1 => format!("{k}-fold by case"),
        r => format!("{k}-fold by case, {r} fold assignments pooled"),
    };
    let (field_kind, scalar_choice, mut validation) = choose(&table, cfg, scheme, n);
    let folds: Vec<Vec<usize>> = (0..cfg.repeats.max(1))
        .map(|r| repeat_folds(n, k, cfg, r))
        .collect();
    let held_out = raw
        .into_iter()
        .filter(|h| {
            let (direct, kind) = scalar_choice[h.scalar];
            h.cand == cand_index(h.scalar + 1, direct, kind, cfg.regressors.entries().len())
        })
        .map(|h| {
            let case = &set.cases[h.case];
            HeldOutPoint {
                case_id: case.case_id.clone(),
                n_bellows: case.inputs.n_bellows,
                repeat: h.repeat,
                fold: folds[h.repeat][h.case],
                p_bar: set.pressures[h.p_index],
                output: SCALARS[h.scalar].0,
                truth: h.truth,
                predicted: h.predicted,
                std: h.var.max(0.0).sqrt() * validation.outputs[h.scalar + 1].std_ratio,
            }
        })
        .collect();
    validation.pressure_interpolation = interpolation_check(set);
    let training = TrainingInfo {
        source: source.to_string(),
        n_cases: n,
        dropped_cases: set.dropped.len(),
        filled_cases: if cfg.fill_truncated {
            set.partial.len()
        } else {
            0
        },
        skipped_unconverged,
        code_version: env!("CARGO_PKG_VERSION").to_string(),
        n_treatment: n_treatment(cfg.ordinal_n),
        gp_inducing: cfg.gp.inducing,
        correction: None,
        plan_domain: None,
        built_with: None,
    };
    let surrogate = assemble(
        set,
        fitted,
        &cfg.regressors,
        (field_kind, scalar_choice),
        validation,
        training,
    );
    Ok(TrainReport {
        surrogate,
        dropped: set.dropped.clone(),
        seconds: start.elapsed().as_secs_f64(),
        final_fit_seconds,
        fits: k * cfg.repeats.max(1) + 1,
        held_out,
    })
}
