//! Training: fit the pipeline, cross-validate by case, choose the predictor of each output.
//!
//! Stages: features → POD blocks → coefficients → a fit of every regressor of the registry
//! ([`TrainConfig::regressors`]; the GP and the polynomial by default) ([`fit_pipeline`]);
//! k-fold cross-validation by case runs the same pipeline per fold (folds in parallel; each
//! fold is deterministic, so results do not depend on the thread count); the held-out errors
//! choose the regressor of the field block (by marker RMSE) and the source of each scalar
//! (field or direct block, and its regressor, by its RMSE); the final model is fitted on all
//! cases.

use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use super::data::{CaseRamp, CaseSet, PartialRamp};
use super::metrics::{ErrorAccumulator, InterpolationCheck, OutputValidation, Validation};
use super::pod::PodBasis;
use super::provenance::{TrainingInfo, N_ORDINAL};
use super::regression::gp::{Gp, GpParams};
use super::regression::poly::{Poly, PolyParams};
use super::regression::{
    Data, DynRegressor, Registry, Regressor, RegressorKind, Regressors, TrainingSettings,
};
use super::surrogate::{Block, InputSpec, Surrogate};
use super::{RomError, N_MARKER_COMPONENTS, QUANTITY_NAMES, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::{raw_features, CaseInputs, FeatureScaler};
use crate::schema::{self, Quantity};
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
    /// Gaussian-process settings.
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
    /// ([`super::held_out_n`]).
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

/// A held-out scalar prediction of one candidate, before the choice.
struct RawHeldOut {
    cand: usize,
    case: usize,
    repeat: usize,
    p_index: usize,
    scalar: usize,
    truth: f64,
    predicted: f64,
    var: f64,
}

/// A fitted pipeline (one fold or the final model).
pub struct Fitted {
    features: FeatureScaler,
    blocks: Vec<(String, PodBasis, usize)>,
    /// One per registry entry, in its order.
    regressors: Vec<Box<dyn DynRegressor>>,
}

const SCALARS: [(&str, usize); 4] = [
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

/// Held-out error accumulators of one candidate (output × block × regressor).
#[derive(Debug, Clone, Default)]
struct CandidateErrors {
    total: ErrorAccumulator,
    projection: ErrorAccumulator,
    regression: ErrorAccumulator,
    /// Sum of squared standardised errors `((y − ŷ)/σ̂)²` and their count.
    z2: (f64, usize),
}

/// Candidates: markers from the field block; each scalar from the field or its direct block.
/// Index: `output (0 markers, 1..=4 scalars) × block kind (0 field, 1 direct) × regressor`
/// ([`cand_index`]).
type Table = Vec<CandidateErrors>;

/// Index of a candidate among `n_kinds` regressors.
fn cand_index(output: usize, direct: usize, kind: usize, n_kinds: usize) -> usize {
    (output * 2 + direct) * n_kinds + kind
}

fn evaluate_fold(
    fit: &Fitted,
    test: &[(usize, &CaseRamp)],
    repeat: usize,
) -> (Table, Vec<RawHeldOut>) {
    let regs = &fit.regressors;
    let nk = regs.len();
    let mut table = vec![CandidateErrors::default(); 5 * 2 * nk];
    let mut raw = Vec::new();
    let (d, m) = (
        fit.features.dim(),
        regs.first().map_or(0, |r| r.n_outputs()),
    );
    let mut x = vec![0.0; d];
    let mut scratch = vec![0.0; regs.iter().map(|r| r.scratch_len()).max().unwrap_or(0)];
    let mut coef = vec![vec![0.0; m]; nk];
    let mut var = vec![vec![0.0; m]; nk];
    for &(case_index, case) in test {
        fit.features.scale_into(&raw_features(&case.inputs), &mut x);
        for (k, r) in regs.iter().enumerate() {
            r.predict_into(&x, &mut coef[k], &mut scratch);
        }
        for (k, r) in regs.iter().enumerate() {
            r.variance_into(&x, &mut var[k], &mut scratch);
        }
        for (bi, (_, pod, off)) in fit.blocks.iter().enumerate() {
            let r = pod.n_modes;
            let truth = PodBasis::snapshot_of(&pod.quantities, case);
            let mut proj = vec![0.0; r];
            pod.project_into(&truth, &mut proj);
            let nq = pod.quantities.len();
            for e in 0..pod.dim() {
                let q = pod.quantities[e % nq];
                let output = if q < N_MARKER_COMPONENTS {
                    0
                } else {
                    q - Q_TIP_UZ + 1
                };
                let y_proj = pod.entry(e, &proj);
                for (kind, c) in coef.iter().enumerate() {
                    let y_hat = pod.entry(e, &c[*off..off + r]);
                    let row = &pod.modes[e * r..(e + 1) * r];
                    let v: f64 = (0..r)
                        .map(|k| (pod.scale[e] * row[k]).powi(2) * var[kind][off + k])
                        .sum();
                    let cand = cand_index(output, usize::from(bi > 0), kind, nk);
                    if output > 0 {
                        raw.push(RawHeldOut {
                            cand,
                            case: case_index,
                            repeat,
                            p_index: e / nq,
                            scalar: output - 1,
                            truth: truth[e],
                            predicted: y_hat,
                            var: v,
                        });
                    }
                    let t = &mut table[cand];
                    t.total.add(truth[e], y_hat);
                    t.projection.add(truth[e], y_proj);
                    t.regression.add(y_proj, y_hat);
                    if v > 0.0 {
                        t.z2.0 += (truth[e] - y_hat).powi(2) / v;
                        t.z2.1 += 1;
                    }
                }
            }
        }
    }
    (table, raw)
}

fn fold_assignment(n: usize, k: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    order.shuffle(&mut Xoshiro256PlusPlus::seed_from_u64(seed));
    let mut fold = vec![0; n];
    for (pos, &i) in order.iter().enumerate() {
        fold[i] = pos % k;
    }
    fold
}

fn validation_entry(
    name: &str,
    output: usize,
    (direct, kind): (usize, usize),
    t: &Table,
    kinds: &[&str],
) -> OutputValidation {
    let c = &t[cand_index(output, direct, kind, kinds.len())];
    let block = if direct == 1 { "direct" } else { "field" };
    let reg = kinds[kind];
    OutputValidation {
        name: name.to_string(),
        source: format!("{block}/{reg}"),
        total: c.total.finish(),
        projection_rmse: c.projection.rmse(),
        regression_rmse: c.regression.rmse(),
        std_ratio: if c.z2.1 > 0 {
            (c.z2.0 / c.z2.1 as f64).sqrt()
        } else {
            0.0
        },
    }
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

/// Chooses the regressors (by index in the registry); returns (field regressor, per scalar
/// (direct?, regressor)), validation.
fn choose(
    table: &Table,
    cfg: &TrainConfig,
    scheme: String,
    n_cases: usize,
) -> (usize, [(usize, usize); 4], Validation) {
    let names = cfg.regressors.names();
    let nk = names.len();
    let kinds: Vec<usize> = match &cfg.only {
        Some(only) => names
            .iter()
            .position(|n| *n == only.name())
            .into_iter()
            .collect(),
        None => (0..nk).collect(),
    };
    // another regressor must beat the (faster) polynomial by the factor 1 + prefer_poly_within
    let rmse = |o: usize, dir: usize, k: usize| {
        let penalty = if names[k] != Poly::NAME {
            1.0 + cfg.prefer_poly_within
        } else {
            1.0
        };
        table[cand_index(o, dir, k, nk)].total.rmse() * penalty
    };
    let field_kind = *kinds
        .iter()
        .min_by(|&&a, &&b| rmse(0, 0, a).total_cmp(&rmse(0, 0, b)))
        .unwrap_or(&0);
    let mut outputs = vec![validation_entry(
        schema::MARKERS.name,
        0,
        (0, field_kind),
        table,
        &names,
    )];
    let mut candidates = Vec::new();
    let mut scalar_choice = [(0, field_kind); 4];
    for (si, (name, _)) in SCALARS.iter().enumerate() {
        let o = si + 1;
        let mut options = vec![(0, field_kind)];
        options.extend(kinds.iter().map(|&k| (1, k)));
        let best = *options
            .iter()
            .min_by(|a, b| rmse(o, a.0, a.1).total_cmp(&rmse(o, b.0, b.1)))
            .unwrap_or(&(0, field_kind));
        scalar_choice[si] = best;
        outputs.push(validation_entry(name, o, best, table, &names));
    }
    for o in 0..5 {
        let name = if o == 0 {
            schema::MARKERS.name
        } else {
            SCALARS[o - 1].0
        };
        for dir in 0..(if o == 0 { 1 } else { 2 }) {
            for &k in &kinds {
                candidates.push(validation_entry(name, o, (dir, k), table, &names));
            }
        }
    }
    (
        field_kind,
        scalar_choice,
        Validation {
            scheme,
            n_cases,
            outputs,
            candidates,
            pressure_interpolation: Vec::new(),
            held_out_n: None,
        },
    )
}

fn input_specs(cases: &[CaseInputs], pressures: &[f64]) -> Vec<InputSpec> {
    type Getter = fn(&CaseInputs) -> f64;
    let get: [(Quantity, Getter); 6] = [
        (schema::N_BELLOWS, |c| c.n_bellows as f64),
        (schema::WALL_THICKNESS, |c| c.wall_thickness_mm),
        (schema::MU1, |c| c.mu1_mpa),
        (schema::ALPHA1, |c| c.alpha1),
        (schema::MU2, |c| c.mu2_mpa),
        (schema::ALPHA2, |c| c.alpha2),
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

/// Fold of each case in repeat `r` of the cross-validation.
fn repeat_folds(n: usize, k: usize, cfg: &TrainConfig, r: usize) -> Vec<usize> {
    fold_assignment(n, k, cfg.seed.wrapping_add(r as u64))
}

/// Runs the `k` folds of every repeat and the final fit on all cases as
/// `repeats × k + 1` parallel tasks; returns the merged held-out errors and the final fit.
/// A fitted pipeline and its wall time in seconds.
type TimedFit = (Fitted, f64);

fn cross_validate_and_fit(
    set: &CaseSet,
    k: usize,
    cfg: &TrainConfig,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Table, TimedFit, Vec<RawHeldOut>), RomError> {
    let repeats = cfg.repeats.max(1);
    let folds: Vec<Vec<usize>> = (0..repeats)
        .map(|r| repeat_folds(set.cases.len(), k, cfg, r))
        .collect();
    let tasks = repeats * k;
    let partial: &[PartialRamp] = if cfg.fill_truncated {
        &set.partial
    } else {
        &[]
    };
    let done = std::sync::atomic::AtomicUsize::new(0);
    type Task = (Option<(Table, Vec<RawHeldOut>)>, Option<TimedFit>);
    let results: Vec<Result<Task, RomError>> = (0..=tasks)
        .into_par_iter()
        .map(|t| {
            let out = if t == tasks {
                let start = std::time::Instant::now();
                let fitted = fit_pipeline(&set.cases, partial, cfg)?;
                (None, Some((fitted, start.elapsed().as_secs_f64())))
            } else {
                let (r, f) = (t / k, t % k);
                let (mut tr, mut te) = (Vec::new(), Vec::new());
                for (i, c) in set.cases.iter().enumerate() {
                    if folds[r][i] == f {
                        te.push((i, c))
                    } else {
                        tr.push(c.clone())
                    }
                }
                let fitted = fit_pipeline(&tr, partial, cfg)?;
                (Some(evaluate_fold(&fitted, &te, r)), None)
            };
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1,
                tasks + 1,
            );
            Ok(out)
        })
        .collect();
    let mut table = vec![CandidateErrors::default(); 5 * 2 * cfg.regressors.entries().len()];
    let mut final_fit = None;
    let mut held_out = Vec::new();
    for r in results {
        let (t, fitted) = r?;
        let (t, raw) = t.unzip();
        held_out.extend(raw.into_iter().flatten());
        for (acc, part) in table.iter_mut().zip(t.unwrap_or_default()) {
            acc.total.merge(&part.total);
            acc.projection.merge(&part.projection);
            acc.regression.merge(&part.regression);
            acc.z2.0 += part.z2.0;
            acc.z2.1 += part.z2.1;
        }
        final_fit = fitted.or(final_fit);
    }
    let fitted = final_fit.ok_or_else(|| RomError::Numerical {
        stage: "training".into(),
        message: "final fit missing".into(),
    })?;
    held_out.sort_by_key(|h| (h.case, h.repeat, h.scalar, h.p_index, h.cand));
    Ok((table, fitted, held_out))
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
