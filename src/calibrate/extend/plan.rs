//! The FE cases of a round: a Latin hypercube over the slabs between the old box and the new
//! one, with the training plan's settings; and its high-fidelity subset.

use super::material_box::{allocate, MaterialBox};
use crate::calibrate::CalibrateError;
use crate::snapshots::plan::{Plan, PlannedCase, FORMAT_VERSION, SAMPLER};

/// The id of case `j` of extension round `round` (1-based): `10000·round + 5000 + j`, the
/// upper half of the round's block (the refinement's rounds take the lower,
/// [`crate::calibrate::refine::round_plan`]).
pub fn extension_case_id(round: usize, j: usize) -> usize {
    10_000 * round + 5_000 + j
}

/// The FE cases of extension round `round`: `cases` cases over `new − old` (the slabs of
/// [`MaterialBox::slabs`]), with the training plan's FE settings and its ranges of `T` and of
/// any sampled effect, stratified over `n_values` (the trained values of `N`).
///
/// Each slab gets `n_values.len()` cases first when there are enough for every slab (else one
/// each, when there are enough), the rest by volume, and is sampled as the plan sampler
/// samples a plan ([`Plan::generate`]: a maximin Latin hypercube, `N` stratified by rank, `T`
/// capped per `N`) with the seed `seed + 100·round + t` (slab `t`); its cases are numbered
/// by [`extension_case_id`] in slab order. The plan's ranges are the new box's.
///
/// # Errors
/// No slab (the boxes are the same), or ranges the plan refuses (named).
pub fn extension_plan(
    training: &Plan,
    n_values: &[usize],
    old: &MaterialBox,
    new: &MaterialBox,
    round: usize,
    cases: usize,
    seed: u64,
) -> Result<Plan, CalibrateError> {
    let field = || format!("box extension round {round}");
    let slabs = new.slabs(old);
    if slabs.is_empty() {
        return Err(CalibrateError::input(
            &field(),
            new.describe(),
            "a box larger than the last one",
        ));
    }
    let base = {
        let mut r = new.ranges(&training.ranges);
        r.n_bellows = n_values.to_vec();
        r
    };
    let m = n_values.len();
    let floor = if cases >= m * slabs.len() {
        m
    } else {
        usize::from(cases >= slabs.len())
    };
    let shares: Vec<f64> = slabs.iter().map(|s| s.1).collect();
    let counts = allocate(cases, &shares, floor);
    let mut all: Vec<PlannedCase> = Vec::with_capacity(cases);
    for (t, ((slab, _), &k)) in slabs.iter().zip(&counts).enumerate() {
        if k == 0 {
            continue;
        }
        let s = seed.wrapping_add((100 * round + t) as u64);
        let p = Plan::generate(k, s, slab.ranges(&base), training.settings.clone())
            .map_err(|e| CalibrateError::input(&field(), slab.describe(), &e.to_string()))?;
        all.extend(p.cases);
    }
    for (j, c) in all.iter_mut().enumerate() {
        c.id = extension_case_id(round, j);
    }
    let described: Vec<String> = slabs
        .iter()
        .zip(&counts)
        .map(|((s, share), k)| format!("{k} in [{}] ({:.0} %)", s.describe(), 100.0 * share))
        .collect();
    let plan = Plan {
        format_version: FORMAT_VERSION,
        seed,
        sampler: format!(
            "box extension round {round}: the slabs of the new box outside the old one ({}), \
             each: {SAMPLER}, seed + 100·round + slab; ids 10000·round + 5000 + j",
            described.join("; ")
        ),
        ranges: base,
        settings: training.settings.clone(),
        cases: all,
    };
    plan.validate()
        .map_err(|e| CalibrateError::input(&field(), plan.hash(), &e.to_string()))?;
    Ok(plan)
}

/// How many of a round's `cases` a multi-fidelity training set also runs on its
/// high-fidelity mesh: the training set's share (`high` of `low` cases), at least one per
/// value of `N` (`n_values`), at most all.
pub fn high_fidelity_cases(cases: usize, low: usize, high: usize, n_values: usize) -> usize {
    let share = (cases * high).div_ceil(low.max(1));
    share.max(n_values).min(cases)
}

/// The high-fidelity cases of a round: `k` of `low`'s cases picked as the training set's
/// high-fidelity subset was ([`Plan::subset`]: greedy maximin, `N` in turn), same ids, with
/// the high-fidelity plan's FE settings.
///
/// # Errors
/// `k` of 0 or beyond the round's cases, or settings the plan refuses.
pub fn high_fidelity_plan(
    low: &Plan,
    high_training: &Plan,
    k: usize,
    round: usize,
) -> Result<Plan, CalibrateError> {
    let field = format!("box extension round {round} (high fidelity)");
    let sub = low
        .subset(k, high_training.settings.mesh)
        .map_err(|e| CalibrateError::input(&field, k, &e.to_string()))?;
    let plan = Plan {
        settings: high_training.settings.clone(),
        ..sub
    };
    plan.validate()
        .map_err(|e| CalibrateError::input(&field, plan.hash(), &e.to_string()))?;
    Ok(plan)
}
