//! The extension itself: round after round, the box moved out where the optimum presses, new
//! FE cases in the slabs, the surrogate retrained and the material refitted, until a stop.

use std::collections::HashSet;
use std::path::Path;

use super::material_box::{MaterialBox, PressedBound};
use super::plan::{extension_case_id, extension_plan, high_fidelity_cases, high_fidelity_plan};
use super::report::{BoxExtension, ExtendRound, ExtendStop, FailedCase, Optimum, FORMAT, VERSION};
use super::settings::ExtendSettings;
use crate::calibrate::fit::{calibrate, Calibration};
use crate::calibrate::identify::Determinacy;
use crate::calibrate::objective::Recordings;
use crate::calibrate::refine::{run_round_plan, GrownSet, Refit, TrainingSet};
use crate::calibrate::CalibrateError;
use crate::rom::data::{SnapshotRow, SnapshotSet};
use crate::rom::Surrogate;
use crate::snapshots::plan::{case_name, Plan};
use crate::snapshots::run::{shard_status, CaseRunner, Progress, RunSummary};
use crate::snapshots::shard::Shard;

/// What [`extend_box`] reports as it goes.
#[derive(Clone, Debug)]
pub enum ExtendEvent<'a> {
    /// A stage, in words.
    Stage(String),
    /// FE progress of a round.
    Fe {
        /// Round.
        round: usize,
        /// Cases done of total in this run.
        progress: Progress,
    },
    /// A round finished.
    Round(&'a ExtendRound),
}

/// Extends the training box of `model`, trained on `training`, where the optimum for `rec`
/// presses it (see the [module docs](super)). The FE cases are run by `runner` (the FE:
/// [`crate::snapshots::fe_runner::fe_runner`]) into `dir/extend_k/` (and `dir/extend_k_high/`
/// for a multi-fidelity set); the retrained surrogates are written to
/// `dir/model_extend_k.json`. Everything is checked before the first FE case runs.
///
/// # Errors
/// Bad settings ([`ExtendSettings::validate`]); a training set that is not the model's (its
/// values of `N`, its number of cases, a high fidelity the model does not have or lacks);
/// training case ids in the extension's range; bad recordings; a round whose every case fails;
/// FE directory errors (another plan in a round directory); training errors.
pub fn extend_box(
    model: &Surrogate,
    training: &TrainingSet,
    rec: &Recordings,
    settings: &ExtendSettings,
    runner: &dyn CaseRunner,
    dir: &Path,
    progress: &(dyn Fn(ExtendEvent) + Sync),
) -> Result<BoxExtension, CalibrateError> {
    let n_values = trained_n_values(model, training)?;
    settings.validate(n_values.len())?;
    check_ids(training, settings)?;
    let fe = SlabFe {
        training,
        n_values,
        settings,
        runner,
        dir,
        progress,
    };
    let mut e = Extending::start(model, rec, &fe)?;
    let stop = loop {
        match e.next() {
            Next::Stop(stop) => break stop,
            Next::Extend(new_box, pressed) => e.round(&fe, new_box, pressed)?,
        }
    };
    fe.stage(format!("box extension stopped: {}", stop.describe()));
    Ok(e.finish(stop))
}

/// The values of `N` of `training`, checked to be the set `model` was trained on: every
/// value trained, as many cases as the model's (and a high fidelity exactly when the model
/// has a correction).
fn trained_n_values(
    model: &Surrogate,
    training: &TrainingSet,
) -> Result<Vec<usize>, CalibrateError> {
    let rows = &training.snapshots.rows;
    let mut n: Vec<usize> = rows.iter().map(|r| r.inputs.n_bellows as usize).collect();
    n.sort_unstable();
    n.dedup();
    let source = &training.snapshots.source;
    if let Some(v) = n.iter().find(|&&v| !model.n_allowed.contains(&(v as u32))) {
        return Err(CalibrateError::input(
            "training set",
            format!("{source} (N = {v})"),
            &format!(
                "the set the model was trained on (its N: {:?})",
                model.n_allowed
            ),
        ));
    }
    let ids: HashSet<&str> = rows.iter().map(|r| r.case_id.as_str()).collect();
    let trained = model.training.n_cases + model.training.dropped_cases;
    if ids.len() != trained {
        return Err(CalibrateError::input(
            "training set",
            format!("{source} ({} cases)", ids.len()),
            &format!(
                "the set the model was trained on ({trained} cases, from {})",
                model.training.source
            ),
        ));
    }
    match (&model.training.correction, &training.high) {
        (Some(c), None) => Err(CalibrateError::input(
            "training set",
            source,
            &format!(
                "the model's low-fidelity set with its high-fidelity set {} (the model is \
                 corrected by it; retraining without it would drop the correction)",
                c.high_source
            ),
        )),
        (None, Some(h)) => Err(CalibrateError::input(
            "training set",
            format!("{source} with the high fidelity {}", h.snapshots.source),
            "one set, as the model (which has no multi-fidelity correction) was trained",
        )),
        _ => Ok(n),
    }
}

/// No training case carries an id an extension round would give.
fn check_ids(training: &TrainingSet, s: &ExtendSettings) -> Result<(), CalibrateError> {
    let high = training.high.iter().flat_map(|h| &h.snapshots.rows);
    let ids: HashSet<&str> = training
        .snapshots
        .rows
        .iter()
        .chain(high)
        .map(|r| r.case_id.as_str())
        .collect();
    for k in 1..=s.max_rounds {
        for j in 0..s.cases_per_round {
            let name = case_name(extension_case_id(k, j));
            if ids.contains(name.as_str()) {
                return Err(CalibrateError::input(
                    "training set case id",
                    name,
                    "ids outside the box extension's (10000·k + 5000 + j for round k)",
                ));
            }
        }
    }
    Ok(())
}

/// How the FE cases of a round are run: with the training plans' settings, by `runner` into
/// `dir`.
struct SlabFe<'a> {
    training: &'a TrainingSet,
    n_values: Vec<usize>,
    settings: &'a ExtendSettings,
    runner: &'a dyn CaseRunner,
    dir: &'a Path,
    progress: &'a (dyn Fn(ExtendEvent<'_>) + Sync),
}

/// The FE of one mesh of a round.
struct MeshRun {
    summary: RunSummary,
    set: SnapshotSet,
    failed: Vec<FailedCase>,
}

impl MeshRun {
    /// The rows of the cases that did not fail, nor are in `also_failed`.
    fn good_rows(self, also_failed: &HashSet<String>) -> Vec<SnapshotRow> {
        let failed: HashSet<String> = self.failed.iter().map(|f| case_name(f.id)).collect();
        self.set
            .rows
            .into_iter()
            .filter(|r| !failed.contains(&r.case_id) && !also_failed.contains(&r.case_id))
            .collect()
    }
}

impl SlabFe<'_> {
    fn stage(&self, s: String) {
        (self.progress)(ExtendEvent::Stage(s));
    }

    /// Runs `plan` (round `k`) into `dir/extend_k{suffix}/` (resuming what is there), merged
    /// into `dir/extend_k{suffix}.csv`; the failed cases named. A round whose every case
    /// fails is an error.
    fn run(&self, plan: &Plan, k: usize, suffix: &str) -> Result<MeshRun, CalibrateError> {
        let fe_dir = self.dir.join(format!("extend_{k}{suffix}"));
        let csv = self.dir.join(format!("extend_{k}{suffix}.csv"));
        let mesh = plan.settings.mesh.level.name();
        self.stage(format!(
            "round {k}: FE of {} cases on the {mesh} mesh in {} (plan {})",
            plan.cases.len(),
            fe_dir.display(),
            plan.hash()
        ));
        let what = "box extension FE";
        let ran = run_round_plan(
            plan,
            &fe_dir,
            &csv,
            self.settings.threads,
            self.runner,
            what,
            &|p| {
                (self.progress)(ExtendEvent::Fe {
                    round: k,
                    progress: p,
                })
            },
        );
        let status = shard_status(plan, &fe_dir, Shard::ALL)
            .map_err(|e| CalibrateError::input(what, fe_dir.display(), &e.to_string()))?;
        if status.finished == plan.cases.len() && status.failed.len() == plan.cases.len() {
            return Err(CalibrateError::input(
                what,
                format!(
                    "round {k}: all {} cases failed on the {mesh} mesh",
                    plan.cases.len()
                ),
                &format!(
                    "at least one case that runs (the first: case {}: {})",
                    status.failed[0].0, status.failed[0].1
                ),
            ));
        }
        let (summary, set) = ran?;
        let failed = status
            .failed
            .into_iter()
            .map(|(id, error)| FailedCase {
                id,
                mesh: mesh.to_string(),
                error,
            })
            .collect();
        Ok(MeshRun {
            summary,
            set,
            failed,
        })
    }
}

/// What comes after a calibration: a stop, or a round with the new box.
enum Next {
    Stop(ExtendStop),
    Extend(MaterialBox, Vec<PressedBound>),
}

/// An extension under way: the current surrogate and its calibration, the nominal box, the
/// training rows so far, and what the rounds found.
struct Extending<'a> {
    rec: &'a Recordings,
    settings: &'a ExtendSettings,
    current: Surrogate,
    cal: Calibration,
    nominal: MaterialBox,
    start: Optimum,
    rows: GrownSet,
    rounds: Vec<ExtendRound>,
}

impl<'a> Extending<'a> {
    /// The calibration through `model`, its box, and the training rows.
    fn start(
        model: &Surrogate,
        rec: &'a Recordings,
        fe: &SlabFe<'a>,
    ) -> Result<Self, CalibrateError> {
        let cal = calibrate(model, rec, &fe.settings.calibration, &|s| {
            fe.stage(s.into())
        })?;
        let start = Optimum::of(&cal, model.training.n_cases)?;
        let t = fe.training;
        Ok(Extending {
            rec,
            settings: fe.settings,
            current: model.clone(),
            nominal: start.domain,
            start,
            cal,
            rows: GrownSet::of(t),
            rounds: Vec::new(),
        })
    }

    /// The stop the current calibration calls for, else the extended box: inside (no bound
    /// active), only bounds of undetermined coordinates pressed, every pressed bound at its
    /// physical limit, the last round run.
    fn next(&self) -> Next {
        let s = self.settings;
        if self.cal.pressed.is_empty() {
            return Next::Stop(ExtendStop::Inside);
        }
        // a bound of a coordinate the recordings do not determine (its profile open on both
        // sides) is pressed by chance: moving it changes nothing they see
        let undetermined = |b: &crate::calibrate::fit::ActiveBound| {
            self.cal
                .identifiability
                .profiles
                .iter()
                .any(|p| p.name == b.name && p.determinacy == Determinacy::NotDetermined)
        };
        let (flat, informative): (Vec<_>, Vec<_>) =
            self.cal.pressed.iter().cloned().partition(undetermined);
        if informative.is_empty() {
            return Next::Stop(ExtendStop::Undetermined {
                bounds: flat.iter().map(ToString::to_string).collect(),
            });
        }
        let (new_box, pressed) = self.nominal.extended(&informative, s.step, &s.limits);
        if pressed.iter().all(|p| p.moved_to.is_none()) {
            return Next::Stop(ExtendStop::PhysicalLimit {
                bounds: pressed.iter().map(PressedBound::describe).collect(),
                undetermined: flat.iter().map(ToString::to_string).collect(),
            });
        }
        if self.rounds.len() >= s.max_rounds {
            return Next::Stop(ExtendStop::MaxRounds);
        }
        Next::Extend(new_box, pressed)
    }

    /// Round `k`: the slabs' cases (both meshes of a multi-fidelity set), the failed ones left
    /// out, the surrogate retrained (written to `model_extend_k.json`) and the material
    /// refitted.
    fn round(
        &mut self,
        fe: &SlabFe<'_>,
        new_box: MaterialBox,
        pressed: Vec<PressedBound>,
    ) -> Result<(), CalibrateError> {
        let k = self.rounds.len() + 1;
        let s = self.settings;
        let moved: Vec<String> = pressed.iter().map(PressedBound::describe).collect();
        fe.stage(format!(
            "round {k}: {}; box {}",
            moved.join("; "),
            new_box.describe()
        ));
        let plan = extension_plan(
            &fe.training.plan,
            &fe.n_values,
            &self.nominal,
            &new_box,
            k,
            s.cases_per_round,
            s.seed,
        )?;
        let low = fe.run(&plan, k, "")?;
        let (mut runs, mut failed) = (vec![low.summary.clone()], low.failed.clone());
        let low_failed: HashSet<String> = low.failed.iter().map(|f| case_name(f.id)).collect();
        let mut high_cases = 0;
        if let Some(h) = &fe.training.high {
            high_cases = high_fidelity_cases(
                plan.cases.len(),
                fe.training.plan.cases.len(),
                h.plan.cases.len(),
                fe.n_values.len(),
            );
            let high_plan = high_fidelity_plan(&plan, &h.plan, high_cases, k)?;
            let high = fe.run(&high_plan, k, "_high")?;
            runs.push(high.summary.clone());
            failed.extend(high.failed.clone());
            self.rows.high.extend(high.good_rows(&low_failed));
        }
        let skipped = low.set.skipped_unconverged;
        self.rows.add_low(low.good_rows(&HashSet::new()), skipped);
        let model = self.retrain(fe, k)?;
        let round = ExtendRound {
            round: k,
            box_before: self.nominal,
            box_after: new_box,
            pressed,
            plan_hash: plan.hash(),
            cases: plan.cases.len(),
            high_fidelity_cases: high_cases,
            cases_run: runs.iter().map(|r| r.done).sum(),
            cases_read_back: runs.iter().map(|r| r.skipped).sum(),
            failed,
            fe_wall_time_s: runs.iter().map(|r| r.wall_time_s).sum(),
            fe_dir: fe.dir.join(format!("extend_{k}")),
            model,
            refit: Optimum::of(&self.cal, self.current.training.n_cases)?,
        };
        (fe.progress)(ExtendEvent::Round(&round));
        self.rounds.push(round);
        self.nominal = new_box;
        Ok(())
    }

    /// After round `k`: the surrogate retrained on every row so far, written to
    /// `model_extend_k.json` (its path returned), and the material refitted through it.
    fn retrain(&mut self, fe: &SlabFe<'_>, k: usize) -> Result<std::path::PathBuf, CalibrateError> {
        let refit = Refit {
            training: fe.training,
            train: &self.settings.train,
            calibration: &self.settings.calibration,
            recordings: self.rec,
        };
        let added = format!("box extension rounds 1..{k}");
        let path = fe.dir.join(format!("model_extend_{k}.json"));
        (self.current, self.cal) =
            refit.retrain_and_refit(&self.rows, &added, &path, &|s| fe.stage(s))?;
        Ok(path)
    }

    fn finish(self, stop: ExtendStop) -> BoxExtension {
        let s = self.settings;
        BoxExtension {
            format: FORMAT.into(),
            version: VERSION,
            step: s.step,
            cases_per_round: s.cases_per_round,
            seed: s.seed,
            limits: s.limits,
            start: self.start,
            rounds: self.rounds,
            stop,
            final_box: self.nominal,
            last: Some(self.cal),
        }
    }
}
