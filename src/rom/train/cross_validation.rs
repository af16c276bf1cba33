//! k-fold cross-validation by case: every fold's pipeline fitted without the fold and
//! evaluated on it (folds in parallel, each deterministic), the held-out errors of every
//! candidate source of each output, and the choice among them.

use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use super::pipeline::{fit_pipeline, Fitted, TrainConfig, SCALARS};
use crate::case::raw_features;
use crate::rom::data::{CaseRamp, CaseSet, PartialRamp};
use crate::rom::metrics::{ErrorAccumulator, OutputValidation, Validation};
use crate::rom::pod::PodBasis;
use crate::rom::regression::poly::Poly;
use crate::rom::regression::Regressor;
use crate::rom::{RomError, N_MARKER_COMPONENTS, Q_TIP_UZ};
use crate::schema;

/// A held-out scalar prediction of one candidate, before the choice.
pub(super) struct RawHeldOut {
    pub(super) cand: usize,
    pub(super) case: usize,
    pub(super) repeat: usize,
    pub(super) p_index: usize,
    pub(super) scalar: usize,
    pub(super) truth: f64,
    pub(super) predicted: f64,
    pub(super) var: f64,
}

/// Held-out error accumulators of one candidate (output × block × regressor).
#[derive(Debug, Clone, Default)]
pub(super) struct CandidateErrors {
    total: ErrorAccumulator,
    projection: ErrorAccumulator,
    regression: ErrorAccumulator,
    /// Sum of squared standardised errors `((y − ŷ)/σ̂)²` and their count.
    z2: (f64, usize),
}

/// Candidates: markers from the field block; each scalar from the field or its direct block.
/// Index: `output (0 markers, 1..=4 scalars) × block kind (0 field, 1 direct) × regressor`
/// ([`cand_index`]).
pub(super) type Table = Vec<CandidateErrors>;

/// Index of a candidate among `n_kinds` regressors.
pub(super) fn cand_index(output: usize, direct: usize, kind: usize, n_kinds: usize) -> usize {
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

/// Chooses the regressors (by index in the registry); returns (field regressor, per scalar
/// (direct?, regressor)), validation.
pub(super) fn choose(
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

/// Fold of each case in repeat `r` of the cross-validation.
pub(super) fn repeat_folds(n: usize, k: usize, cfg: &TrainConfig, r: usize) -> Vec<usize> {
    fold_assignment(n, k, cfg.seed.wrapping_add(r as u64))
}

/// A fitted pipeline and its wall time in seconds.
pub(super) type TimedFit = (Fitted, f64);

/// Runs the `k` folds of every repeat and the final fit on all cases as
/// `repeats × k + 1` parallel tasks; returns the merged held-out errors and the final fit.
pub(super) fn cross_validate_and_fit(
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
