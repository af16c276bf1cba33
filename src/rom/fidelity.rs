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
//! The surrogate is then trained on the corrected set. The mesh error of a coarse level is
//! mostly a smooth stiffness bias, so a few dozen high-fidelity cases describe it; its held-out
//! error ([`CorrectionInfo::validation`]) adds to the surrogate's own.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use super::data::{CaseInputs, SnapshotRow, SnapshotSet};
use super::metrics::Validation;
use super::surrogate::{Query, Surrogate};
use super::RomError;

/// How a training set was corrected (stored in the model's training information).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorrectionInfo {
    /// High-fidelity snapshot source.
    pub high_source: String,
    /// Cases run at both fidelities.
    pub matched_cases: usize,
    /// Low-fidelity rows replaced by their high-fidelity values.
    pub replaced_rows: usize,
    /// Low-fidelity rows corrected by the discrepancy surrogate.
    pub corrected_rows: usize,
    /// Held-out errors of the discrepancy surrogate (k-fold over the matched cases): the
    /// error the correction adds to the surrogate's.
    pub validation: Validation,
}

fn same_inputs(a: &CaseInputs, b: &CaseInputs) -> bool {
    a.n_bellows == b.n_bellows
        && a.wall_thickness_mm == b.wall_thickness_mm
        && a.mu1_mpa == b.mu1_mpa
        && a.alpha1 == b.alpha1
        && a.mu2_mpa == b.mu2_mpa
        && a.alpha2 == b.alpha2
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
