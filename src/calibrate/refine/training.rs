//! The training set of the surrogate being refined, and the surrogate retrained on it with the
//! rounds' cases.

use std::path::Path;

use crate::calibrate::fit::{calibrate, Calibration, CalibrationSettings};
use crate::calibrate::objective::Recordings;
use crate::calibrate::CalibrateError;
use crate::rom::data::{SnapshotRow, SnapshotSet};
use crate::rom::provenance::BuiltWith;
use crate::rom::{train, Surrogate, TrainConfig};
use crate::snapshots::merge::merge;
use crate::snapshots::plan::Plan;
use crate::snapshots::run::{run_shard, CaseRunner, Progress, RunOptions, RunSummary};
use crate::snapshots::shard::Shard;

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

    /// Reads the sets of a source `"a.csv + b.csv + …"` (`train --add-data`), each with its
    /// plan beside it, appended in that order; the training plan is the first set's (its FE
    /// settings are the rounds').
    ///
    /// # Errors
    /// As [`Self::read`]; a case in two of the sets.
    fn read_appended(files: &[std::path::PathBuf]) -> Result<Self, CalibrateError> {
        let mut sets = files
            .iter()
            .map(|f| Self::read(f, &crate::snapshots::merge::sidecar_path(f)));
        let Some(first) = sets.next() else {
            return Err(CalibrateError::input(
                "model training source",
                "",
                "at least one snapshot CSV",
            ));
        };
        let mut set = first?;
        for more in sets {
            set.snapshots.append(more?.snapshots)?;
        }
        Ok(set)
    }

    /// The set a model was trained on: its recorded sources (relative to `root`; for a
    /// multi-fidelity model the low- and the high-fidelity set; a low-fidelity source of
    /// appended sets, `"a.csv + b.csv"`, as `train --add-data` records it, read set by set)
    /// and the plans beside them (`<stem>.plan.json`).
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
        let files = |source: &str, what: &str| {
            source
                .split(crate::rom::data::SOURCE_SEPARATOR)
                .map(|name| file(name, what))
                .collect::<Result<Vec<_>, _>>()
        };
        match &model.training.correction {
            None => Self::read_appended(&files(&model.training.source, "model training source")?),
            Some(c) => {
                // "<low> warped in pressure corrected by <high>" (`rom::fidelity`)
                let src = &model.training.source;
                let low = src
                    .split(" warped in pressure")
                    .next()
                    .and_then(|l| l.split(" corrected by ").next())
                    .unwrap_or(src);
                let high = file(&c.high_source, "model training source (high fidelity)")?;
                Self::read_appended(&files(low, "model training source (low fidelity)")?)?
                    .with_high_fidelity(&high, c.pressure_warp.is_some())
            }
        }
    }
}

/// The surrogate retrained on the training set and the cases added since (`low` and `high`:
/// every row so far, the training set's included), as the original was trained (`train`).
/// `added` names what was added (`refinement rounds 1..2`), in the new set's source and in
/// the stage line.
pub(crate) fn retrain(
    training: &TrainingSet,
    low: &[SnapshotRow],
    high: &[SnapshotRow],
    skipped: usize,
    added: &str,
    train_config: &TrainConfig,
    stage: &dyn Fn(String),
) -> Result<Surrogate, CalibrateError> {
    let low_set = SnapshotSet {
        source: format!("{} + {added}", training.snapshots.source),
        rows: low.to_vec(),
        skipped_unconverged: skipped,
    };
    let (set, correction) = match &training.high {
        Some(h) => {
            let high_set = SnapshotSet {
                source: format!("{} + {added}", h.snapshots.source),
                rows: high.to_vec(),
                skipped_unconverged: h.snapshots.skipped_unconverged,
            };
            let (set, info) = crate::rom::fidelity::correct_low_fidelity(
                &low_set,
                &high_set,
                train_config,
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
        "retraining on {} cases (with the {added})",
        cases.cases.len()
    ));
    let mut report = train(&cases, &source, skipped, train_config, &|_, _| {})?;
    report.surrogate.training.correction = correction;
    // every round's plan builds its cases as the training plan does (its settings are the
    // rounds'), so the grown set is built as the training set was
    report.surrogate.training.built_with = BuiltWith::of_plan(&training.plan);
    Ok(report.surrogate)
}

/// What a refinement or a box extension retrains with after each of its rounds: the base
/// training set, the training and calibration settings and the recordings it refits to.
pub(crate) struct Refit<'a> {
    /// The surrogate's own training set (and its high-fidelity set, if multi-fidelity).
    pub training: &'a TrainingSet,
    /// How the surrogate is trained.
    pub train: &'a TrainConfig,
    /// How the material is fitted through it.
    pub calibration: &'a CalibrationSettings,
    /// The recordings fitted.
    pub recordings: &'a Recordings,
}

/// The training set grown by rounds: every low- and high-fidelity row so far (the base set's
/// first) and how many unconverged rows were skipped.
#[derive(Clone, Debug, Default)]
pub(crate) struct GrownSet {
    /// Every low-fidelity row so far, the base set's and the rounds'.
    pub low: Vec<SnapshotRow>,
    /// Every high-fidelity row so far (empty for a single-fidelity surrogate).
    pub high: Vec<SnapshotRow>,
    /// Unconverged rows skipped, of the base set and the rounds.
    pub skipped: usize,
}

impl GrownSet {
    /// The base training set's rows, before any round.
    pub(crate) fn of(training: &TrainingSet) -> Self {
        GrownSet {
            low: training.snapshots.rows.clone(),
            high: training
                .high
                .iter()
                .flat_map(|h| h.snapshots.rows.iter().cloned())
                .collect(),
            skipped: training.snapshots.skipped_unconverged,
        }
    }

    /// Adds a round's low-fidelity rows and its count of skipped unconverged rows.
    pub(crate) fn add_low(&mut self, rows: impl IntoIterator<Item = SnapshotRow>, skipped: usize) {
        self.skipped += skipped;
        self.low.extend(rows);
    }
}

impl Refit<'_> {
    /// The surrogate retrained on `rows` ([`retrain`]; `added` names what the rounds added,
    /// e.g. "refinement rounds 1..2", in the new set's source), written to `model_path`, and
    /// the material refitted through it.
    ///
    /// # Errors
    /// Training, writing the model, or the calibration failing.
    pub(crate) fn retrain_and_refit(
        &self,
        rows: &GrownSet,
        added: &str,
        model_path: &Path,
        stage: &dyn Fn(String),
    ) -> Result<(Surrogate, Calibration), CalibrateError> {
        let model = retrain(
            self.training,
            &rows.low,
            &rows.high,
            rows.skipped,
            added,
            self.train,
            stage,
        )?;
        model.save(model_path)?;
        let cal = calibrate(&model, self.recordings, self.calibration, &|s| {
            stage(s.into())
        })?;
        Ok((model, cal))
    }
}

/// Runs `plan` into the snapshot shard directory `fe_dir` (resuming what is there: finished
/// cases are read back, not run again) by `runner` with `threads` cases at a time, and merges
/// it into `csv`; the run's summary and the merged snapshots. `what` names the FE in errors.
///
/// # Errors
/// Another plan in `fe_dir`, an invalid case file, I/O errors (named by `what`).
pub(crate) fn run_round_plan(
    plan: &Plan,
    fe_dir: &Path,
    csv: &Path,
    threads: Option<usize>,
    runner: &dyn CaseRunner,
    what: &str,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
    let opts = RunOptions {
        shard: Shard::ALL,
        threads,
        retry_failed: false,
    };
    let summary = run_shard(plan, fe_dir, &opts, runner, progress)
        .map_err(|e| CalibrateError::input(what, fe_dir.display(), &e.to_string()))?;
    merge(&[fe_dir.to_path_buf()], csv)
        .map_err(|e| CalibrateError::input(what, csv.display(), &e.to_string()))?;
    Ok((summary, SnapshotSet::read(csv)?))
}
