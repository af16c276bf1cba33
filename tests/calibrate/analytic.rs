//! The analytic stand-in for the FE shared by the refinement and box-extension tests: scratch
//! directories, a quick calibration, a plan run and merged, a surrogate trained on it, and
//! noisy recordings of a runner at a true set.

use std::path::{Path, PathBuf};

use surrogate::calibrate::optimise::MultistartSettings;
use surrogate::calibrate::refine::{case_at, TrainingSet};
use surrogate::calibrate::synthetic::{noisy_recordings, TrueOutputs};
use surrogate::calibrate::{CalibrationSettings, OgdenSet, Recordings, Weights};
use surrogate::rom::data::SnapshotSet;
use surrogate::rom::{train, Surrogate, TrainConfig};
use surrogate::snapshots::merge::merge;
use surrogate::snapshots::plan::{Plan, PlanSettings};
use surrogate::snapshots::run::{run_shard, CaseRunner, RunOptions};
use surrogate::snapshots::shard::Shard;

/// A fresh scratch directory `<tmp>/surrogate_<group>_<name>_<pid>`.
pub fn scratch(group: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("surrogate_{group}_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The calibration of these tests: the tip, 6 starts, 4 profile points.
pub fn quick_calibration() -> CalibrationSettings {
    let mut c = CalibrationSettings {
        weights: Weights::parse("tip").unwrap(),
        multistart: MultistartSettings {
            starts: 6,
            ..MultistartSettings::default()
        },
        ..CalibrationSettings::default()
    };
    c.identify.profile_points = 4;
    c
}

/// The training configuration of these tests: 4 folds, one assignment.
pub fn quick_training() -> TrainConfig {
    TrainConfig {
        folds: 4,
        ..TrainConfig::default()
    }
}

/// The shipped coarse plan (its ranges and FE settings).
pub fn shipped_plan() -> Plan {
    Plan::read(Path::new("training_data/snapshots_coarse.plan.json")).unwrap()
}

/// `plan` run by `runner` into `dir/<name>/`, merged into `dir/<name>.csv` and read back.
pub fn run_plan(plan: &Plan, dir: &Path, name: &str, runner: &dyn CaseRunner) -> SnapshotSet {
    let fe = dir.join(name);
    let opts = RunOptions {
        shard: Shard::ALL,
        threads: None,
        retry_failed: false,
    };
    run_shard(plan, &fe, &opts, runner, &|_| {}).unwrap();
    let csv = dir.join(format!("{name}.csv"));
    merge(std::slice::from_ref(&fe), &csv).unwrap();
    SnapshotSet::read(&csv).unwrap()
}

/// `runner`'s outputs at 1, 2, 3 bar of the 9 recorded designs (N 9, 11, 13; T 1.6, 2.0,
/// 2.4 mm) at `truth`, with `settings`.
pub fn true_outputs(
    runner: &dyn CaseRunner,
    settings: &PlanSettings,
    truth: &OgdenSet,
) -> Vec<TrueOutputs> {
    let mut out = Vec::new();
    for n in [9, 11, 13] {
        for t in [1.6, 2.0, 2.4] {
            let o = runner.run(&case_at(0, n, t, truth), settings);
            for (s, &p) in o.steps.iter().zip(&settings.pressures_bar) {
                if [1.0, 2.0, 3.0].contains(&p) {
                    out.push(TrueOutputs {
                        n_bellows: n,
                        wall_thickness_mm: t,
                        pressure_bar: p,
                        tip_uz_mm: s.tip_uz_mm,
                        tip_uy_mm: s.tip_uy_mm,
                        angle_deg: s.angle_deg,
                        force_n: s.force_n,
                    });
                }
            }
        }
    }
    out
}

/// Noisy recordings (seed 5, the shipped experiments' scatter) of `runner` at `truth`.
pub fn recordings(
    runner: &dyn CaseRunner,
    settings: &PlanSettings,
    truth: &OgdenSet,
) -> Recordings {
    noisy_recordings(
        &true_outputs(runner, settings, truth),
        &Recordings::shipped().unwrap(),
        5,
        "analytic",
    )
    .unwrap()
}

/// A surrogate trained (`cfg`) on `plan` run by `training_runner` in `dir/base/`, and its
/// training set.
pub fn trained_model(
    plan: Plan,
    dir: &Path,
    training_runner: &dyn CaseRunner,
    cfg: &TrainConfig,
) -> (Surrogate, TrainingSet) {
    let snapshots = run_plan(&plan, dir, "base", training_runner);
    let cases = snapshots.clone().into_cases().unwrap();
    let model = train(&cases, "analytic", 0, cfg, &|_, _| {})
        .unwrap()
        .surrogate;
    let training = TrainingSet {
        snapshots,
        plan,
        high: None,
    };
    (model, training)
}
