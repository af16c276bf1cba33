//! Whether a model interpolates in the number of bellows: train with `N` as an ordinal input
//! ([`TrainConfig::ordinal_n`]) on the cases whose `N` is not held out, then predict every
//! case of the held-out `N` and compare with its snapshots.
//!
//! ```no_run
//! use surrogate::rom::{held_out_n, SnapshotSet, TrainConfig};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let set = SnapshotSet::read("snapshots.csv".as_ref())?.into_cases()?;
//! let report = held_out_n::study(&set, "snapshots.csv", &[8, 10, 14], &TrainConfig::default(), &|_, _| {})?;
//! println!("{}", report.table());
//! # Ok(()) }
//! ```
//!
//! The errors are mean absolute errors over every held-out case and every grid pressure above
//! zero: the tip as the distance between the predicted and the FE tip positions (mm), the
//! bending angle (°) and the blocked force (N).

pub use super::metrics::{HeldOutErrors, HeldOutNReport};

use super::data::CaseSet;
use super::train::{train, TrainConfig};
use super::{RomError, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::Query;

/// Trains on the cases of `set` whose `N` is not in `held_out` (with `N` ordinal, whatever
/// `cfg` says) and measures the model on the held-out cases.
///
/// # Errors
/// [`RomError::InvalidInput`] when a held-out `N` has no case, is not strictly between the
/// trained ends (that would be extrapolation) or nothing is left to train on; training errors.
pub fn study(
    set: &CaseSet,
    source: &str,
    held_out: &[u32],
    cfg: &TrainConfig,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<HeldOutNReport, RomError> {
    let (train_set, test) = split(set, held_out)?;
    let cfg = TrainConfig {
        ordinal_n: true,
        ..cfg.clone()
    };
    let model = train(&train_set, source, 0, &cfg, progress)?.surrogate;
    let mut pred = model.new_prediction();
    let mut per_n = vec![Sums::default(); held_out.len()];
    for case in &test.cases {
        let k = held_out
            .iter()
            .position(|&n| n == case.inputs.n_bellows)
            .unwrap_or(0);
        per_n[k].cases += 1;
        for (p, fe) in set.pressures.iter().zip(&case.values) {
            if *p <= 0.0 {
                continue;
            }
            model.predict_scalars_into(&Query::from_case(&case.inputs, *p), &mut pred)?;
            let tip = (pred.tip_uz_mm() - fe[Q_TIP_UZ]).hypot(pred.tip_uy_mm() - fe[Q_TIP_UY]);
            per_n[k].add(
                tip,
                (pred.angle_deg() - fe[Q_ANGLE]).abs(),
                (pred.force_n() - fe[Q_FORCE]).abs(),
            );
        }
    }
    let mut all = Sums::default();
    for s in &per_n {
        all.merge(s);
    }
    Ok(HeldOutNReport {
        held_out: held_out.to_vec(),
        trained: model.n_trained().to_vec(),
        training_cases: train_set.cases.len(),
        per_n: per_n.iter().map(Sums::finish).collect(),
        all: all.finish(),
    })
}

/// The cases without and with the held-out `N`.
fn split(set: &CaseSet, held_out: &[u32]) -> Result<(CaseSet, CaseSet), RomError> {
    let (test, kept): (Vec<_>, Vec<_>) = set
        .cases
        .iter()
        .cloned()
        .partition(|c| held_out.contains(&c.inputs.n_bellows));
    let (lo, hi) = kept
        .iter()
        .map(|c| c.inputs.n_bellows)
        .fold((u32::MAX, 0), |(a, b), n| (a.min(n), b.max(n)));
    for &n in held_out {
        if !test.iter().any(|c| c.inputs.n_bellows == n) {
            return Err(RomError::invalid(
                "held_out_n",
                n,
                "a number of bellows with cases in the set",
            ));
        }
        if kept.is_empty() || n <= lo || n >= hi {
            return Err(RomError::invalid(
                "held_out_n",
                n,
                &format!("strictly between the trained ends {lo}..{hi} (N is not extrapolated)"),
            ));
        }
    }
    let with = |cases: Vec<_>| CaseSet {
        pressures: set.pressures.clone(),
        cases,
        dropped: Vec::new(),
        partial: Vec::new(),
        interpolated_points: 0,
        off_grid_rows: 0,
    };
    Ok((with(kept), with(test)))
}

#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    cases: usize,
    points: usize,
    tip: f64,
    angle: f64,
    force: f64,
    max_tip: f64,
}

impl Sums {
    fn add(&mut self, tip: f64, angle: f64, force: f64) {
        self.points += 1;
        self.tip += tip;
        self.angle += angle;
        self.force += force;
        self.max_tip = self.max_tip.max(tip);
    }

    fn merge(&mut self, o: &Sums) {
        self.cases += o.cases;
        self.points += o.points;
        self.tip += o.tip;
        self.angle += o.angle;
        self.force += o.force;
        self.max_tip = self.max_tip.max(o.max_tip);
    }

    fn finish(&self) -> HeldOutErrors {
        let m = self.points.max(1) as f64;
        HeldOutErrors {
            cases: self.cases,
            points: self.points,
            tip_mm: self.tip / m,
            angle_deg: self.angle / m,
            force_n: self.force / m,
            max_tip_mm: self.max_tip,
        }
    }
}
