//! Multi-fidelity training sets: many low-fidelity snapshots (a coarse mesh) corrected by a
//! surrogate of the discrepancy to a high-fidelity subset (the mesh the convergence study
//! supports) run on the same cases.
//!
//! With `L` the low- and `H` the high-fidelity snapshots of a case at a pressure:
//!
//! ```text
//!   δ = H − L                 on the cases run at both fidelities (matched by case id)
//!   δ̂ = POD + regression of δ (the same machinery as the surrogate, with its own k-fold error)
//!   corrected = H             where the high fidelity was run
//!             = L + δ̂         elsewhere
//! ```
//!
//! The surrogate is then trained on the corrected set; the discrepancy's held-out error
//! ([`CorrectionInfo::validation`]) adds to the surrogate's own. Without contact the mesh error
//! of the coarse level is a smooth stiffness bias; with contact it also shifts the pressure at
//! which neighbouring bellows touch, which an additive `δ` learns poorly from a few dozen
//! cases. [`super::warp`] first maps `L` in pressure (`L(x, P / r(x))`), and `δ` is fitted to
//! what that leaves (`train --pressure-warp`).
//!
//! [`end_to_end`] measures the whole pipeline (warp, discrepancy, correction, surrogate)
//! against high-fidelity cases it never saw: the accuracy that matters to a user of a model
//! trained on a corrected set (`train --check-high-fidelity`).

use std::collections::HashMap;

use super::data::{SnapshotRow, SnapshotSet};
use super::metrics::ErrorAccumulator;
pub use super::provenance::{CorrectionInfo, EndToEnd};
use super::surrogate::Surrogate;
use super::train::{train, TrainConfig};
use super::RomError;
use crate::case::{CaseInputs, Query};
use crate::schema;

/// Output groups of the end-to-end check: the 18 marker components, then each scalar.
const GROUPS: [(&str, std::ops::Range<usize>); 5] = [
    (schema::MARKERS.name, 0..18),
    (schema::TIP_UZ.name, 18..19),
    (schema::TIP_UY.name, 19..20),
    (schema::ANGLE.name, 20..21),
    (schema::FORCE.name, 21..22),
];

/// Runs the end-to-end check of [`EndToEnd`] with `folds` folds over the high-fidelity cases
/// (seeded by `cfg.seed`). Each fold trains two surrogates with `cfg` (the discrepancy and
/// the corrected set), so it costs about `2 × folds` trainings. With `warp`, each fold also
/// fits the pressure warp ([`super::warp`]) on its training cases and corrects the warped
/// low fidelity.
///
/// # Errors
/// Fewer than 2 high-fidelity cases, or any error of [`discrepancy`], [`correct`] or training.
pub fn end_to_end(
    low: &SnapshotSet,
    high: &SnapshotSet,
    folds: usize,
    cfg: &TrainConfig,
    warp: bool,
) -> Result<EndToEnd, RomError> {
    use rand::seq::SliceRandom;
    use rand::SeedableRng;
    let mut ids: Vec<&str> = high.rows.iter().map(|r| r.case_id.as_str()).collect();
    ids.sort_unstable();
    ids.dedup();
    if ids.len() < 2 {
        return Err(RomError::InsufficientData(format!(
            "{} high-fidelity cases; the end-to-end check needs at least 2",
            ids.len()
        )));
    }
    let k = folds.clamp(2, ids.len());
    // folds stratified by N (each N dealt round the folds in turn), so that every fold's
    // training cases cover every N while each N has at least `k` cases
    let n_of: HashMap<&str, u32> = high
        .rows
        .iter()
        .map(|r| (r.case_id.as_str(), r.inputs.n_bellows))
        .collect();
    ids.shuffle(&mut rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(
        cfg.seed,
    ));
    ids.sort_by_key(|id| n_of[id]);
    let fold_of: HashMap<&str, usize> =
        ids.iter().enumerate().map(|(i, &id)| (id, i % k)).collect();
    let low_rows: HashMap<(String, u64), &SnapshotRow> =
        low.rows.iter().map(|r| (key(r), r)).collect();
    let mut acc = vec![ErrorAccumulator::default(); GROUPS.len()];
    let mut raw = vec![ErrorAccumulator::default(); GROUPS.len()];
    let mut cor = vec![ErrorAccumulator::default(); GROUPS.len()];
    for f in 0..k {
        let (held, kept): (Vec<&SnapshotRow>, Vec<&SnapshotRow>) = high
            .rows
            .iter()
            .partition(|r| fold_of[r.case_id.as_str()] == f);
        let train_high = SnapshotSet {
            source: format!("{} without fold {f}", high.source),
            rows: kept.into_iter().cloned().collect(),
            skipped_unconverged: 0,
        };
        let (mut set, _) = correct_low_fidelity(low, &train_high, cfg, warp, false, &|_| {})?;
        let held_out_case = |id: &str| fold_of.get(id).is_some_and(|&g| g == f);
        let corrected_rows: HashMap<(String, u64), [f64; 22]> = set
            .rows
            .iter()
            .filter(|r| held_out_case(&r.case_id))
            .map(|r| (key(r), r.values))
            .collect();
        set.rows.retain(|r| !held_out_case(&r.case_id));
        let model = train(&set.into_cases()?, "corrected", 0, cfg, &|_, _| {})?.surrogate;
        let mut pred = model.new_prediction();
        for h in held {
            let Some(l) = low_rows.get(&key(h)) else {
                continue;
            };
            let Some(c) = corrected_rows.get(&key(h)) else {
                continue;
            };
            model.predict_into(&Query::from_case(&h.inputs, h.pressure_bar), &mut pred)?;
            for (g, (_, range)) in GROUPS.iter().enumerate() {
                for q in range.clone() {
                    acc[g].add(h.values[q], pred.values[q]);
                    cor[g].add(h.values[q], c[q]);
                    raw[g].add(h.values[q], l.values[q]);
                }
            }
        }
    }
    let stats = |a: &[ErrorAccumulator]| {
        GROUPS
            .iter()
            .zip(a)
            .map(|((name, _), a)| (name.to_string(), a.finish()))
            .collect()
    };
    Ok(EndToEnd {
        scheme: format!(
            "{k}-fold over the {} high-fidelity cases{}",
            ids.len(),
            if warp { ", pressure warp" } else { "" }
        ),
        surrogate: stats(&acc),
        corrected: stats(&cor),
        low_fidelity: stats(&raw),
    })
}

/// The multi-fidelity pipeline of `surrogate train --high-fidelity`: the low-fidelity set,
/// warped in pressure first if `warp` ([`super::warp`]), corrected by a surrogate of the
/// discrepancy `H − L` trained with `cfg` on the cases of both sets ([`discrepancy`],
/// [`correct`]); with `check`, also the [`end_to_end`] error against high-fidelity cases it
/// never saw. `log` receives a line (or a table) at each stage. Returns the corrected set and
/// the record stored in the model.
///
/// # Errors
/// Those of [`super::warp::PressureWarp::fit`], [`discrepancy`], [`train`], [`correct`] and
/// [`end_to_end`].
pub fn correct_low_fidelity(
    low: &SnapshotSet,
    high: &SnapshotSet,
    cfg: &TrainConfig,
    warp: bool,
    check: bool,
    log: &dyn Fn(&str),
) -> Result<(SnapshotSet, CorrectionInfo), RomError> {
    let (warped, pressure_warp) = if warp {
        let w = super::warp::PressureWarp::fit(low, high)?;
        log(&w.info.summary());
        (Some(w.apply(low)), Some(w.info))
    } else {
        (None, None)
    };
    let mapped = warped.as_ref().unwrap_or(low);
    let delta = discrepancy(mapped, high)?;
    let source = delta.source.clone();
    let cases = delta.into_cases()?;
    log(&format!(
        "discrepancy {source}: {} cases on a {}-pressure grid ({} dropped)",
        cases.cases.len(),
        cases.pressures.len(),
        cases.dropped.len()
    ));
    let report = train(&cases, &source, 0, cfg, &|_, _| {})?;
    log(&format!(
        "discrepancy surrogate (high − low fidelity), held out:\n{}",
        report.surrogate.validation.table()
    ));
    let (set, replaced_rows, corrected_rows) = correct(mapped, high, &report.surrogate)?;
    log(&format!(
        "corrected set: {replaced_rows} rows replaced by high fidelity, {corrected_rows} rows corrected"
    ));
    let end_to_end = if check {
        log(&format!(
            "end-to-end check against the high fidelity ({} folds)…",
            cfg.folds
        ));
        let e = end_to_end(low, high, cfg.folds, cfg, warp)?;
        log(&e.table());
        Some(e)
    } else {
        None
    };
    let info = CorrectionInfo {
        high_source: high.source.clone(),
        matched_cases: cases.cases.len(),
        replaced_rows,
        corrected_rows,
        validation: report.surrogate.validation,
        pressure_warp,
        end_to_end,
    };
    Ok((set, info))
}

fn same_inputs(a: &CaseInputs, b: &CaseInputs) -> bool {
    a.n_bellows == b.n_bellows
        && a.wall_thickness_mm == b.wall_thickness_mm
        && a.material == b.material
}

/// Key of a row: case id and pressure (exact: both sets come from plans with one grid).
fn key(r: &SnapshotRow) -> (String, u64) {
    (r.case_id.clone(), r.pressure_bar.to_bits())
}

/// The discrepancy rows `H − L` of the (case, pressure) pairs present in both sets.
///
/// # Errors
/// [`RomError::InvalidInput`] if a high-fidelity case has no low-fidelity counterpart, its
/// inputs differ from the low-fidelity case of the same id, or no row pairs up.
pub fn discrepancy(low: &SnapshotSet, high: &SnapshotSet) -> Result<SnapshotSet, RomError> {
    let low_rows: HashMap<(String, u64), &SnapshotRow> =
        low.rows.iter().map(|r| (key(r), r)).collect();
    let low_inputs: HashMap<&str, &CaseInputs> = low
        .rows
        .iter()
        .map(|r| (r.case_id.as_str(), &r.inputs))
        .collect();
    let mut rows = Vec::new();
    for h in &high.rows {
        let Some(li) = low_inputs.get(h.case_id.as_str()) else {
            return Err(RomError::invalid(
                &format!("{}: line {}: case_id", high.source, h.line),
                &h.case_id,
                &format!("a case of the low-fidelity set {}", low.source),
            ));
        };
        if !same_inputs(li, &h.inputs) {
            return Err(RomError::invalid(
                &format!("{}: line {}: inputs of {}", high.source, h.line, h.case_id),
                format!("{:?}", h.inputs),
                &format!("the inputs of the same case in {}: {li:?}", low.source),
            ));
        }
        if let Some(l) = low_rows.get(&key(h)) {
            let mut d = h.clone();
            for (v, lv) in d.values.iter_mut().zip(&l.values) {
                *v -= lv;
            }
            rows.push(d);
        }
    }
    if rows.is_empty() {
        return Err(RomError::invalid(
            "high-fidelity rows",
            0,
            "rows whose case and pressure are also in the low-fidelity set",
        ));
    }
    Ok(SnapshotSet {
        source: format!("{} − {}", high.source, low.source),
        rows,
        skipped_unconverged: 0,
    })
}

/// The corrected set: high-fidelity rows where they exist, low-fidelity rows plus the
/// discrepancy surrogate's prediction elsewhere. Returns (set, replaced rows, corrected rows).
///
/// # Errors
/// [`RomError::InvalidInput`] if the low-fidelity set has a number of bellows that `delta`
/// was not trained on (the high-fidelity subset must cover every N).
pub fn correct(
    low: &SnapshotSet,
    high: &SnapshotSet,
    delta: &Surrogate,
) -> Result<(SnapshotSet, usize, usize), RomError> {
    if let Some(r) = low
        .rows
        .iter()
        .find(|r| !delta.n_allowed.contains(&r.inputs.n_bellows))
    {
        return Err(RomError::invalid(
            &format!("{}: line {}: n_bellows", low.source, r.line),
            r.inputs.n_bellows,
            &format!(
                "a number of bellows of the high-fidelity set {} ({:?}): its cases must cover every N of the low-fidelity set",
                high.source, delta.n_allowed
            ),
        ));
    }
    let high_rows: HashMap<(String, u64), &SnapshotRow> =
        high.rows.iter().map(|r| (key(r), r)).collect();
    let mut pred = delta.new_prediction();
    let (mut replaced, mut corrected) = (0, 0);
    let mut rows = Vec::with_capacity(low.rows.len());
    for l in &low.rows {
        let mut r = l.clone();
        if let Some(h) = high_rows.get(&key(l)) {
            r.values = h.values;
            replaced += 1;
        } else {
            delta.predict_into(&Query::from_case(&l.inputs, l.pressure_bar), &mut pred)?;
            for (v, d) in r.values.iter_mut().zip(&pred.values) {
                *v += d;
            }
            corrected += 1;
        }
        rows.push(r);
    }
    let set = SnapshotSet {
        source: format!("{} corrected by {}", low.source, high.source),
        rows,
        skipped_unconverged: low.skipped_unconverged,
    };
    Ok((set, replaced, corrected))
}
