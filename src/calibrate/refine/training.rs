//! The training set of the surrogate being refined, and the surrogate retrained on it with the
//! rounds' cases.

use std::path::Path;

use super::settings::RefineSettings;
use crate::calibrate::CalibrateError;
use crate::rom::data::{SnapshotRow, SnapshotSet};
use crate::rom::{train, Surrogate};
use crate::snapshots::plan::Plan;

/// The high-fidelity part of a multi-fidelity training set.
#[derive(Clone, Debug)]
pub struct HighFidelity {
    /// The high-fidelity snapshots (their cases pair with low-fidelity ones by id).
    pub snapshots: SnapshotSet,
    /// Their plan (the high-fidelity FE settings of the refinement).
    pub plan: Plan,
    /// Whether the low fidelity is warped in pressure before the correction.
    pub pressure_warp: bool,
}

/// The training set of a surrogate and the plan it was run with (for the FE settings of the
/// refinement cases).
#[derive(Clone, Debug)]
pub struct TrainingSet {
    /// The snapshots (validated rows); the low fidelity of a multi-fidelity set.
    pub snapshots: SnapshotSet,
    /// The plan of those snapshots (its settings are the refinement's).
    pub plan: Plan,
    /// The high-fidelity set that corrects them, if any.
    pub high: Option<HighFidelity>,
}

impl TrainingSet {
    /// Reads a snapshot CSV and its plan.
    ///
    /// # Errors
    /// I/O, format and validation errors of either file.
    pub fn read(snapshots: &Path, plan: &Path) -> Result<Self, CalibrateError> {
        let snapshots = SnapshotSet::read(snapshots)?;
        let plan = Plan::read(plan)
            .map_err(|e| CalibrateError::input("training plan", plan.display(), &e.to_string()))?;
        Ok(TrainingSet {
            snapshots,
            plan,
            high: None,
        })
    }

    /// Adds the high-fidelity set `snapshots` (its plan beside it) that corrects this one.
    ///
    /// # Errors
    /// As [`Self::read`].
    pub fn with_high_fidelity(
        self,
        snapshots: &Path,
        pressure_warp: bool,
    ) -> Result<Self, CalibrateError> {
        let h = Self::read(snapshots, &crate::snapshots::merge::sidecar_path(snapshots))?;
        Ok(TrainingSet {
            high: Some(HighFidelity {
                snapshots: h.snapshots,
                plan: h.plan,
                pressure_warp,
            }),
            ..self
        })
    }

    /// The set a model was trained on: its recorded sources (relative to `root`; for a
    /// multi-fidelity model the low- and the high-fidelity set) and the plans beside them
    /// (`<stem>.plan.json`).
    ///
    /// # Errors
    /// A source that is not a file, or the errors of [`Self::read`].
    pub fn of_model(model: &Surrogate, root: &Path) -> Result<Self, CalibrateError> {
        let file = |name: &str, what: &str| {
            let csv = root.join(name);
            if csv.is_file() {
                Ok(csv)
            } else {
                Err(CalibrateError::input(
                    what,
                    csv.display(),
                    "the snapshot CSV the model was trained on (give it explicitly)",
                ))
            }
        };
        match &model.training.correction {
            None => {
                let csv = file(&model.training.source, "model training source")?;
                Self::read(&csv, &crate::snapshots::merge::sidecar_path(&csv))
            }
            Some(c) => {
                // "<low> warped in pressure corrected by <high>" (`rom::fidelity`)
                let src = &model.training.source;
                let low = src
                    .split(" warped in pressure")
                    .next()
                    .and_then(|l| l.split(" corrected by ").next())
                    .unwrap_or(src);
                let csv = file(low, "model training source (low fidelity)")?;
                let high = file(&c.high_source, "model training source (high fidelity)")?;
                Self::read(&csv, &crate::snapshots::merge::sidecar_path(&csv))?
                    .with_high_fidelity(&high, c.pressure_warp.is_some())
            }
        }
    }
}

/// The surrogate retrained on the training set and the refinement cases of rounds `1..=k`
/// (`low` and `high`: every row so far), as the original was trained.
pub(super) fn retrain(
    training: &TrainingSet,
    low: &[SnapshotRow],
    high: &[SnapshotRow],
    skipped: usize,
    k: usize,
    settings: &RefineSettings,
    stage: &dyn Fn(String),
) -> Result<Surrogate, CalibrateError> {
    let low_set = SnapshotSet {
        source: format!("{} + refinement rounds 1..{k}", training.snapshots.source),
        rows: low.to_vec(),
        skipped_unconverged: skipped,
    };
    let (set, correction) = match &training.high {
        Some(h) => {
            let high_set = SnapshotSet {
                source: format!("{} + refinement rounds 1..{k}", h.snapshots.source),
                rows: high.to_vec(),
                skipped_unconverged: h.snapshots.skipped_unconverged,
            };
            let (set, info) = crate::rom::fidelity::correct_low_fidelity(
                &low_set,
                &high_set,
                &settings.train,
                h.pressure_warp,
                false,
                &|line| stage(line.to_string()),
            )?;
            (set, Some(info))
        }
        None => (low_set, None),
    };
    let source = set.source.clone();
    let cases = set.into_cases()?;
    stage(format!(
        "retraining on {} cases (with the refinement rounds 1..{k})",
        cases.cases.len()
    ));
    let mut report = train(&cases, &source, skipped, &settings.train, &|_, _| {})?;
    report.surrogate.training.correction = correction;
    Ok(report.surrogate)
}
