//! The refinement itself: round after round, the FE at the calibrated set, the surrogate
//! retrained on it and the material refitted, until a stop.

use std::path::{Path, PathBuf};

use super::cases::{baseline_rows, recorded_designs, round_plan};
use super::report::{RefineRound, RefineStop, Refinement};
use super::settings::RefineSettings;
use super::shift::{data_space_shift, DataSpaceShift};
use super::training::{run_round_plan, GrownSet, Refit, TrainingSet};
use crate::calibrate::baseline::BaselineRow;
use crate::calibrate::fit::{calibrate, Calibration};
use crate::calibrate::objective::{Recordings, Selection};
use crate::calibrate::verify::{compare_fe, FeVerification};
use crate::calibrate::CalibrateError;
use crate::case::OgdenSet;
use crate::fe::mesh::MeshOptions;
use crate::rom::data::SnapshotSet;
use crate::rom::Surrogate;
use crate::snapshots::plan::Plan;
use crate::snapshots::run::{CaseRunner, Progress, RunSummary};

/// What [`refine`] reports as it goes.
#[derive(Clone, Debug)]
pub enum RefineEvent<'a> {
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
    Round(&'a RefineRound),
}

/// Runs the refinement (see the [module docs](crate::calibrate::refine)) from `model`, trained
/// on `training`, for `rec`. The FE cases are run by `runner` (the FE:
/// [`crate::snapshots::fe_runner::fe_runner`]) into `dir/round_k/`; the retrained surrogates are
/// written to `dir/model_round_k.json`.
///
/// # Errors
/// Bad recordings or settings, a refinement case the plan refuses, FE directory errors
/// (another plan in a round directory), training errors.
pub fn refine(
    model: &Surrogate,
    training: &TrainingSet,
    rec: &Recordings,
    settings: &RefineSettings,
    runner: &dyn CaseRunner,
    dir: &Path,
    progress: &(dyn Fn(RefineEvent) + Sync),
) -> Result<Refinement, CalibrateError> {
    settings.validate()?;
    let fe = RoundFe {
        training,
        designs: recorded_designs(rec),
        runner,
        dir,
        threads: settings.threads,
        progress,
    };
    let mut r = Refining::start(model, &fe, rec, settings)?;
    let stop = loop {
        let k = r.rounds.len() + 1;
        let (last_rows, agree) = r.verify(&fe, k)?;
        if agree {
            break RefineStop::Agree;
        }
        if k == settings.max_rounds {
            break RefineStop::MaxRounds;
        }
        r.retrain(&fe, k)?;
        if let Some(stop) = r.settled(&fe, k, last_rows)? {
            break stop;
        }
    };
    Ok(r.finish(stop))
}

/// How the FE cases of a round are run: every recorded design, with the training plans'
/// settings, by `runner` into `dir`.
struct RoundFe<'a> {
    training: &'a TrainingSet,
    designs: Vec<(usize, f64)>,
    runner: &'a dyn CaseRunner,
    dir: &'a Path,
    threads: Option<usize>,
    progress: &'a (dyn Fn(RefineEvent<'_>) + Sync),
}

impl RoundFe<'_> {
    /// A stage, in words, to `progress`.
    fn stage(&self, s: String) {
        (self.progress)(RefineEvent::Stage(s));
    }

    /// The plan the surrogate is compared with: the high fidelity's of a multi-fidelity set.
    fn verify_plan(&self) -> &Plan {
        match &self.training.high {
            Some(h) => &h.plan,
            None => &self.training.plan,
        }
    }

    /// Runs `plan` (round `k`) into `fe_dir` (resuming what is there) and merges it into `csv`;
    /// the run's summary and the merged snapshots.
    fn run(
        &self,
        plan: &Plan,
        fe_dir: &Path,
        csv: &Path,
        k: usize,
    ) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
        run_round_plan(
            plan,
            fe_dir,
            csv,
            self.threads,
            self.runner,
            "refinement FE",
            &|p| {
                (self.progress)(RefineEvent::Fe {
                    round: k,
                    progress: p,
                })
            },
        )
    }

    /// Round `k`'s low-fidelity FE of every design at `set` (in `round_k_low/`).
    fn low(&self, set: &OgdenSet, k: usize) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
        let low_dir = self.dir.join(format!("round_{k}_low"));
        self.stage(format!(
            "round {k}: low-fidelity FE of {} designs at {} in {}",
            self.designs.len(),
            set.spec(),
            low_dir.display()
        ));
        let plan = round_plan(&self.training.plan, &self.designs, set, k)?;
        let csv = self.dir.join(format!("round_{k}_low.csv"));
        self.run(&plan, &low_dir, &csv, k)
    }

    /// Round `k`'s FE of every design at `set` that the surrogate is compared with (in
    /// `round_k/`).
    fn verified(
        &self,
        set: &OgdenSet,
        k: usize,
    ) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
        let fe_dir = self.dir.join(format!("round_{k}"));
        self.stage(format!(
            "round {k}: FE of {} designs at {} in {}",
            self.designs.len(),
            set.spec(),
            fe_dir.display()
        ));
        let plan = round_plan(self.verify_plan(), &self.designs, set, k)?;
        let csv = self.dir.join(format!("round_{k}.csv"));
        self.run(&plan, &fe_dir, &csv, k)
    }
}

/// A refinement under way: the current surrogate and its calibration, the training rows so
/// far, and what the rounds found.
struct Refining<'a> {
    rec: &'a Recordings,
    settings: &'a RefineSettings,
    current: Surrogate,
    cal: Calibration,
    /// Every training row so far.
    rows: GrownSet,
    rounds: Vec<RefineRound>,
    models: Vec<PathBuf>,
    final_check: Option<FeVerification>,
    shifts: Vec<DataSpaceShift>,
}

impl<'a> Refining<'a> {
    /// The training set's rows and the calibration through `model`.
    fn start(
        model: &Surrogate,
        fe: &RoundFe<'_>,
        rec: &'a Recordings,
        settings: &'a RefineSettings,
    ) -> Result<Self, CalibrateError> {
        let cal = calibrate(model, rec, &settings.calibration, &|s| fe.stage(s.into()))?;
        let training = fe.training;
        Ok(Refining {
            rec,
            settings,
            current: model.clone(),
            cal,
            rows: GrownSet::of(training),
            rounds: Vec::new(),
            models: Vec::new(),
            final_check: None,
            shifts: Vec::new(),
        })
    }

    /// Round `k`: the FE of every design at the calibrated set (as reported), compared with
    /// the current surrogate and recorded; its cases join the training rows. Returns the FE
    /// rows of the comparison, and whether the two agree everywhere.
    fn verify(
        &mut self,
        fe: &RoundFe<'_>,
        k: usize,
    ) -> Result<(Vec<BaselineRow>, bool), CalibrateError> {
        let set = self.cal.best.rounded(4);
        let (mut cases_run, mut wall) = (0, 0.0);
        let high = fe.training.high.is_some();
        if high {
            let (summary, low) = fe.low(&set, k)?;
            cases_run += summary.done;
            wall += summary.wall_time_s;
            self.rows.add_low(low.rows, low.skipped_unconverged);
        }
        let (summary, verified) = fe.verified(&set, k)?;
        let mesh: MeshOptions = fe.verify_plan().settings.mesh;
        let verification = compare_fe(
            &self.current,
            &set,
            mesh,
            baseline_rows(&verified, self.rec),
        )?;
        let round = RefineRound {
            round: k,
            model_cases: self.current.training.n_cases,
            model: self.cal.model.clone(),
            set,
            chi2: self.cal.chi2,
            active_bounds: self.cal.active_bounds.clone(),
            surrogate_mean_be_mm: self.cal.calibrated.mean_be_mm,
            verification,
            fe_cases_run: cases_run + summary.done,
            fe_wall_time_s: wall + summary.wall_time_s,
            fe_dir: fe.dir.join(format!("round_{k}")),
        };
        (fe.progress)(RefineEvent::Round(&round));
        let agree = round.verification.disagreements == 0;
        let rows = round
            .verification
            .rows
            .iter()
            .map(|r| r.fe.clone())
            .collect();
        self.rounds.push(round);
        if high {
            self.rows.high.extend(verified.rows);
        } else {
            self.rows
                .add_low(verified.rows, verified.skipped_unconverged);
        }
        Ok((rows, agree))
    }

    /// After round `k`: the surrogate retrained on every row so far (written to
    /// `model_round_k.json`) and the material refitted through it.
    fn retrain(&mut self, fe: &RoundFe<'_>, k: usize) -> Result<(), CalibrateError> {
        let refit = Refit {
            training: fe.training,
            train: &self.settings.train,
            calibration: &self.settings.calibration,
            recordings: self.rec,
        };
        let added = format!("refinement rounds 1..{k}");
        let path = fe.dir.join(format!("model_round_{k}.json"));
        (self.current, self.cal) =
            refit.retrain_and_refit(&self.rows, &added, &path, &|s| fe.stage(s))?;
        self.models.push(path);
        Ok(())
    }

    /// Whether the refit after round `k` ends the refinement: the same set as the round
    /// verified, or predictions within `data_tolerance` of it (then the round's FE rows
    /// `last_rows` are compared with the retrained surrogate).
    fn settled(
        &mut self,
        fe: &RoundFe<'_>,
        k: usize,
        last_rows: Vec<BaselineRow>,
    ) -> Result<Option<RefineStop>, CalibrateError> {
        let mesh: MeshOptions = fe.verify_plan().settings.mesh;
        let last = self.rounds.last().expect("a round was pushed");
        if self.cal.best.rounded(4) == last.set {
            self.final_check = Some(compare_fe(&self.current, &last.set, mesh, last_rows)?);
            return Ok(Some(RefineStop::OptimumUnchanged));
        }
        let selection = Selection {
            exclude: self.cal.excluded.clone(),
            ..self.settings.calibration.selection.clone()
        };
        let shift = data_space_shift(
            &self.current,
            self.rec,
            &selection,
            &last.set,
            &self.cal.best.rounded(4),
            k,
        )?;
        fe.stage(shift.describe());
        let unchanged = shift.max_abs_z <= self.settings.data_tolerance;
        self.shifts.push(shift);
        if unchanged {
            self.final_check = Some(compare_fe(&self.current, &last.set, mesh, last_rows)?);
            return Ok(Some(RefineStop::PredictionsUnchanged));
        }
        Ok(None)
    }

    fn finish(self, stop: RefineStop) -> Refinement {
        Refinement {
            rounds: self.rounds,
            stop,
            last_model_cases: self.current.training.n_cases,
            last: self.cal,
            final_check: self.final_check,
            shifts: self.shifts,
            models: self.models,
        }
    }
}
