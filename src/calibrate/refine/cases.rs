//! The FE cases of a round, and their rows against the experiments.

use crate::calibrate::baseline::BaselineRow;
use crate::calibrate::experiments::bending_error;
use crate::calibrate::objective::Recordings;
use crate::calibrate::CalibrateError;
use crate::case::OgdenSet;
use crate::rom::data::SnapshotSet;
use crate::rom::{Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::snapshots::plan::{Plan, PlannedCase};

/// The planned case `id` of design `(n, t)` at the Ogden set `set`, without effects.
pub fn case_at(id: usize, n: usize, t: f64, set: &OgdenSet) -> PlannedCase {
    PlannedCase {
        id,
        n_bellows: n,
        wall_thickness_mm: t,
        material: *set,
        effects: Default::default(),
    }
}

/// The FE cases of round `round` (1-based): every design of `designs` at `set`, with the
/// training plan's settings.
///
/// # Errors
/// A set or design the plan's validation refuses.
pub fn round_plan(
    training: &Plan,
    designs: &[(usize, f64)],
    set: &OgdenSet,
    round: usize,
) -> Result<Plan, CalibrateError> {
    let cases = designs
        .iter()
        .enumerate()
        .map(|(j, &(n, t))| case_at(10_000 * round + j, n, t, set))
        .collect();
    let plan = Plan {
        sampler: format!(
            "refinement round {round}: the recorded designs at the set calibrated through the surrogate"
        ),
        cases,
        ..training.clone()
    };
    plan.validate().map_err(|e| {
        CalibrateError::input("refinement plan", format!("round {round}"), &e.to_string())
    })?;
    Ok(plan)
}

/// The recorded designs `(N, T)`, sorted by N then T.
pub fn recorded_designs(rec: &Recordings) -> Vec<(usize, f64)> {
    let mut d: Vec<(usize, f64)> = rec
        .bending
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm))
        .chain(rec.force.iter().map(|r| (r.n_bellows, r.wall_thickness_mm)))
        .collect();
    d.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    d.dedup();
    d
}

/// Baseline rows (FE against the experiments) from snapshot rows of designs at one set: one per
/// bending record; a configuration the FE did not reach gets `NaN` values and a message.
pub fn baseline_rows(fe: &SnapshotSet, rec: &Recordings) -> Vec<BaselineRow> {
    let at = |n: usize, t: f64, p: f64| {
        fe.rows.iter().find(|r| {
            r.inputs.n_bellows as usize == n
                && (r.inputs.wall_thickness_mm - t).abs() < 1e-9
                && (r.pressure_bar - p).abs() < 1e-9
        })
    };
    rec.bending
        .iter()
        .map(|b| {
            let row = at(b.n_bellows, b.wall_thickness_mm, b.pressure_bar);
            let v = |q: usize| row.map_or(f64::NAN, |r| r.values[q]);
            let (uz, uy) = (v(Q_TIP_UZ), v(Q_TIP_UY));
            let f_exp = rec
                .force
                .iter()
                .find(|f| {
                    f.n_bellows == b.n_bellows
                        && f.wall_thickness_mm == b.wall_thickness_mm
                        && f.pressure_bar == b.pressure_bar
                })
                .map_or(f64::NAN, |f| f.force_n);
            BaselineRow {
                n_bellows: b.n_bellows,
                wall_thickness_mm: b.wall_thickness_mm,
                pressure_bar: b.pressure_bar,
                uz_exp_mm: b.tip_uz_mm,
                uz_sim_mm: uz,
                uy_exp_mm: b.tip_uy_mm,
                uy_sim_mm: uy,
                angle_exp_deg: b.angle_deg,
                angle_sim_deg: v(Q_ANGLE),
                be_mm: bending_error(b.tip_uz_mm, b.tip_uy_mm, uz, uy),
                force_exp_n: f_exp,
                force_sim_n: v(Q_FORCE),
                force_error_n: v(Q_FORCE) - f_exp,
                error: if row.is_some() {
                    String::new()
                } else {
                    "the FE case did not converge to this pressure".into()
                },
            }
        })
        .collect()
}
