//! `surrogate calibrate --extend-box`: its help, its refusals before any FE, and a dry run of
//! the rounds with the analytic runner on a small model.
use std::path::Path;

use surrogate::calibrate::extend::BoxExtension;
use surrogate::rom::data::SnapshotSet;
use surrogate::rom::{train, TrainConfig};
use surrogate::snapshots::merge::merge;
use surrogate::snapshots::plan::{Plan, Ranges};
use surrogate::snapshots::run::{run_shard, AnalyticRunner, RunOptions};
use surrogate::snapshots::shard::Shard;

use crate::common::{outcome as run, scratch as tmp};

#[test]
fn the_help_documents_the_extension_flags() {
    let (ok, stdout, stderr) = run(&["calibrate", "--help"]);
    assert!(ok, "{stderr}");
    for flag in [
        "--extend-box <K>",
        "--extend-step",
        "--extend-cases",
        "--extend-seed",
        "--runner",
        "physical limit",
        "<out>/extend/",
    ] {
        assert!(stdout.contains(flag), "{flag}: {stdout}");
    }
}

#[test]
fn bad_extension_input_is_refused_by_name_before_any_fe() {
    let dir = tmp("extend_bad");
    let out = dir.to_str().unwrap();
    let coarse = [
        "calibrate",
        "--model",
        "models/as_modelled/actuator_coarse.json",
    ];
    let refused = |extra: &[&str], needle: &str| {
        let args: Vec<&str> = coarse
            .iter()
            .chain(extra)
            .chain(&["--out", out])
            .copied()
            .collect();
        let (ok, _, stderr) = run(&args);
        assert!(!ok, "{extra:?}");
        assert!(stderr.contains(needle), "{extra:?}: {stderr}");
    };
    refused(
        &["--extend-box", "1", "--extend-step", "0"],
        "--extend-step 0: expected a finite fraction > 0",
    );
    refused(
        &["--extend-box", "1", "--extend-step=-0.5"],
        "--extend-step -0.5",
    );
    refused(
        &["--extend-box", "1", "--extend-cases", "3"],
        "--extend-cases 3: expected",
    );
    refused(&["--extend-box", "2", "--refine", "1"], "one at a time");
    refused(
        &["--extend-box", "1", "--training", "no/such/snapshots.csv"],
        "no/such/snapshots.csv",
    );
    // a multi-fidelity model with one of its sets
    let (ok, _, stderr) = run(&[
        "calibrate",
        "--model",
        "models/as_modelled/actuator.json",
        "--extend-box",
        "1",
        "--training",
        "training_data/snapshots_coarse.csv",
        "--out",
        out,
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("retraining without it would drop the correction"),
        "{stderr}"
    );
    assert!(!dir.join("extend/extend_1").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A surrogate of 24 analytic cases over a narrow material box, saved in `dir/model.json`, its
/// snapshots in `dir/train.csv` (the plan beside them).
fn small_model(dir: &Path) {
    let shipped = Plan::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("training_data/snapshots_coarse.plan.json"),
    )
    .unwrap();
    let ranges = Ranges {
        n_bellows: vec![9, 11, 13],
        mu0_mpa: [2.0, 4.0],
        term1_share: [0.3, 0.7],
        alpha1: [2.0, 4.0],
        alpha2: [-1.5, -0.5],
        ..shipped.ranges
    };
    let plan = Plan::generate(24, 3, ranges, shipped.settings).unwrap();
    let fe = dir.join("base");
    let opts = RunOptions {
        shard: Shard::ALL,
        threads: None,
        retry_failed: false,
    };
    run_shard(&plan, &fe, &opts, &AnalyticRunner::default(), &|_| {}).unwrap();
    let csv = dir.join("train.csv");
    merge(&[fe], &csv).unwrap();
    let cases = SnapshotSet::read(&csv).unwrap().into_cases().unwrap();
    let cfg = TrainConfig {
        folds: 4,
        ..TrainConfig::default()
    };
    let report = train(&cases, &csv.display().to_string(), 0, &cfg, &|_, _| {}).unwrap();
    report.surrogate.save(&dir.join("model.json")).unwrap();
}

#[test]
fn a_dry_run_extends_the_box_and_writes_its_report() {
    let dir = tmp("extend_dry");
    small_model(&dir);
    let out = dir.join("out");
    let (ok, stdout, stderr) = run(&[
        "calibrate",
        "--model",
        dir.join("model.json").to_str().unwrap(),
        "--training",
        dir.join("train.csv").to_str().unwrap(),
        "--extend-box",
        "1",
        "--extend-cases",
        "12",
        "--runner",
        "analytic",
        "--starts",
        "3",
        "--profile-points",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    println!("{stdout}");
    assert!(stdout.contains("## Box extension"), "{stdout}");
    assert!(stdout.contains("Stopped: "), "{stdout}");
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains("## Box extension"));
    let text = std::fs::read_to_string(out.join("extend/extension.json")).unwrap();
    let e = BoxExtension::from_json(&text).unwrap();
    assert!(out.join("extend/extension.md").is_file());
    assert!(out.join("report.json").is_file());
    for r in &e.rounds {
        assert_eq!(r.cases, 12);
        assert!(r.model.is_file());
        assert!(out
            .join(format!("extend/extend_{}/plan.json", r.round))
            .is_file());
    }
    // a rerun reads every case back
    let (ok, _, stderr) = run(&[
        "calibrate",
        "--model",
        dir.join("model.json").to_str().unwrap(),
        "--training",
        dir.join("train.csv").to_str().unwrap(),
        "--extend-box",
        "1",
        "--extend-cases",
        "12",
        "--runner",
        "analytic",
        "--starts",
        "3",
        "--profile-points",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let again = BoxExtension::from_json(
        &std::fs::read_to_string(out.join("extend/extension.json")).unwrap(),
    )
    .unwrap();
    assert!(again.rounds.iter().all(|r| r.cases_run == 0));
    let _ = std::fs::remove_dir_all(&dir);
}
