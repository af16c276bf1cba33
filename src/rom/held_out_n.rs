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
//! The errors are those of [`super::unseen`]: mean absolute errors over every held-out case and
//! every grid pressure above zero, the tip as the distance between the predicted and the FE tip
//! positions (mm), the bending angle (°) and the blocked force (N).

pub use super::metrics::{HeldOutErrors, HeldOutNReport};

use super::data::CaseSet;
use super::train::{train, TrainConfig};
use super::unseen::errors_by_n;
use super::RomError;

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
    let scored = errors_by_n(&model, &test, held_out)?;
    Ok(HeldOutNReport {
        held_out: held_out.to_vec(),
        trained: model.n_trained().to_vec(),
        training_cases: train_set.cases.len(),
        per_n: scored.per_n,
        all: scored.all,
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
