//! Snapshot store and distribution: merged shards == single run (byte for byte), parallel ==
//! serial, resume after a kill (no duplicate, no gap), a directory refuses another plan, merge
//! errors, failure records. Everything uses the cheap analytic runner, so it runs in seconds;
//! plans are tested in `snapshots_plan.rs`, the real FE runner in `snapshots_fe.rs`.

use crate::common::{bin, outcome, scratch};
use crate::snapshots_common::plan;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use surrogate::rom::data::SnapshotSet;
use surrogate::snapshots::merge::merge_with;
use surrogate::snapshots::run::{shard_status, AnalyticRunner, Progress};
use surrogate::snapshots::store::{case_csv, header_line};
use surrogate::snapshots::{
    merge, run_shard, CaseOutcome, CaseRunner, Plan, PlanSettings, PlannedCase, RunOptions, Shard,
    SnapshotError,
};

const FAILING: AnalyticRunner = AnalyticRunner {
    delay: Duration::ZERO,
    fail_every: 4,
};

fn quiet(_: Progress) {}

fn run(plan: &Plan, dir: &Path, shard: Shard, threads: usize, runner: &dyn CaseRunner) {
    let options = RunOptions {
        shard,
        threads: Some(threads),
        retry_failed: false,
    };
    run_shard(plan, dir, &options, runner, &quiet).unwrap();
}

/// Runs the whole plan in one directory and merges it.
fn single_run(plan: &Plan, root: &Path) -> Vec<u8> {
    let dir = root.join("single");
    run(plan, &dir, Shard::ALL, 1, &FAILING);
    let out = root.join("single.csv");
    merge(&[dir], &out).unwrap();
    std::fs::read(out).unwrap()
}

fn shard(s: &str) -> Shard {
    s.parse().unwrap()
}

#[test]
fn merged_shards_equal_a_single_run_byte_for_byte() {
    let root = scratch("snapshots_merge");
    let p = plan(23, 4);
    let single = single_run(&p, &root);
    let dirs: Vec<PathBuf> = (1..=3).map(|k| root.join(format!("shard{k}"))).collect();
    for (k, d) in dirs.iter().enumerate() {
        run(
            &p,
            d,
            Shard {
                index: k + 1,
                count: 3,
            },
            2,
            &FAILING,
        );
    }
    let out = root.join("merged.csv");
    let summary = merge(&dirs, &out).unwrap();
    assert_eq!(std::fs::read(&out).unwrap(), single);
    assert_eq!(summary.cases, 23);
    assert_eq!(summary.rows, 23 * 6);
    assert_eq!(summary.failed_cases, 5); // ids 3, 7, 11, 15, 19
                                         // the trainer's reader accepts it, skipping the unconverged rows
    let set = SnapshotSet::from_reader(single.as_slice(), "merged").unwrap();
    assert_eq!(set.skipped_unconverged, summary.unconverged_rows);
    assert_eq!(set.rows.len(), 23 * 6 - summary.unconverged_rows);
    // the plan copy beside the merged file is the plan
    let copy = Plan::read(&root.join("merged.plan.json")).unwrap();
    assert_eq!(copy.hash(), p.hash());
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn values_round_trip_exactly_and_rows_are_sorted() {
    let root = scratch("snapshots_roundtrip");
    let p = plan(7, 9);
    let text = String::from_utf8(single_run(&p, &root)).unwrap();
    let set = SnapshotSet::from_reader(text.as_bytes(), "x").unwrap();
    let mut last = (String::new(), -1.0);
    for row in &set.rows {
        let case = &p.cases[row.case_id[5..].parse::<usize>().unwrap()];
        let want = FAILING.run(case, &p.settings);
        let j = p
            .settings
            .pressures_bar
            .iter()
            .position(|&x| x == row.pressure_bar)
            .unwrap();
        let step = &want.steps[j];
        assert_eq!(row.values[18].to_bits(), step.tip_uz_mm.to_bits());
        assert_eq!(row.values[17].to_bits(), step.markers[8][1].to_bits());
        assert_eq!(
            row.inputs.material.mu2_mpa.to_bits(),
            case.material.mu2_mpa.to_bits()
        );
        let key = (row.case_id.clone(), row.pressure_bar);
        assert!(key > last, "rows out of order at {key:?}");
        last = key;
    }
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn parallel_case_files_equal_serial_ones() {
    let root = scratch("snapshots_parallel");
    let p = plan(12, 5);
    run(&p, &root.join("serial"), Shard::ALL, 1, &FAILING);
    run(&p, &root.join("parallel"), Shard::ALL, 4, &FAILING);
    for c in &p.cases {
        let name = format!("cases/case_{:06}.csv", c.id);
        let a = std::fs::read(root.join("serial").join(&name)).unwrap();
        let b = std::fs::read(root.join("parallel").join(&name)).unwrap();
        assert_eq!(a, b, "{name}");
    }
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn resume_reruns_only_missing_cases_and_cleans_temporaries() {
    let root = scratch("snapshots_resume");
    let p = plan(10, 6);
    let dir = root.join("d");
    run(&p, &dir, Shard::ALL, 2, &FAILING);
    // a "kill" left two cases unwritten, one with a half-written temporary file
    for id in [2, 7] {
        std::fs::remove_file(dir.join(format!("cases/case_{id:06}.csv"))).unwrap();
    }
    std::fs::write(dir.join("cases/.case_000007.csv.999.tmp"), "case_id,n_bel").unwrap();
    let calls = AtomicUsize::new(0);
    let counting = |c: &PlannedCase, s: &PlanSettings| {
        calls.fetch_add(1, Ordering::SeqCst);
        FAILING.run(c, s)
    };
    let options = RunOptions {
        shard: Shard::ALL,
        threads: Some(2),
        retry_failed: false,
    };
    let summary = run_shard(&p, &dir, &options, &counting, &quiet).unwrap();
    assert_eq!(calls.load(Ordering::SeqCst), 2);
    assert_eq!((summary.skipped, summary.done), (8, 2));
    let names: Vec<String> = std::fs::read_dir(dir.join("cases"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 10, "{names:?}");
    assert!(names.iter().all(|n| !n.ends_with(".tmp")));
    // a third run does nothing
    let summary = run_shard(&p, &dir, &options, &counting, &quiet).unwrap();
    assert_eq!(
        (summary.skipped, summary.done, calls.load(Ordering::SeqCst)),
        (10, 0, 2)
    );
    merge(&[dir], &root.join("m.csv")).unwrap();
    assert_eq!(
        std::fs::read(root.join("m.csv")).unwrap(),
        single_run(&p, &root)
    );
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn retry_failed_reruns_only_failed_cases() {
    let root = scratch("snapshots_retry");
    let p = plan(10, 6);
    let dir = root.join("d");
    run(&p, &dir, Shard::ALL, 2, &FAILING);
    // cases 3 and 7 failed (fail_every = 4); a fixed runner fills them in
    let calls = std::sync::Mutex::new(Vec::new());
    let fixed = AnalyticRunner {
        delay: Duration::ZERO,
        fail_every: 0,
    };
    let counting = |c: &PlannedCase, s: &PlanSettings| {
        calls.lock().unwrap().push(c.id);
        fixed.run(c, s)
    };
    let options = RunOptions {
        shard: Shard::ALL,
        threads: Some(2),
        retry_failed: true,
    };
    // the status lists them with the runner's message before the retry
    let st = shard_status(&p, &dir, Shard::ALL).unwrap();
    assert_eq!((st.cases, st.finished), (10, 10));
    let failed: Vec<usize> = st.failed.iter().map(|f| f.0).collect();
    assert_eq!(failed, vec![3, 7]);
    assert!(
        st.failed.iter().all(|f| f.1.contains("non-convergence")),
        "{st:?}"
    );
    assert!(st.unconverged_rows > 0);
    let summary = run_shard(&p, &dir, &options, &counting, &quiet).unwrap();
    let st = shard_status(&p, &dir, Shard::ALL).unwrap();
    assert!(st.failed.is_empty() && st.unconverged_rows == 0, "{st:?}");
    let mut ids = calls.lock().unwrap().clone();
    ids.sort_unstable();
    assert_eq!(ids, vec![3, 7]);
    assert_eq!((summary.skipped, summary.done, summary.failed), (8, 2, 0));
    // the directory now equals a run of the fixed runner
    let other = root.join("fixed");
    run(&p, &other, Shard::ALL, 1, &fixed);
    assert_eq!(case_files(&dir), case_files(&other));
    for name in case_files(&dir) {
        assert_eq!(
            std::fs::read(dir.join("cases").join(&name)).unwrap(),
            std::fs::read(other.join("cases").join(&name)).unwrap(),
            "{name}"
        );
    }
    std::fs::remove_dir_all(root).unwrap();
}

fn case_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir.join("cases"))
        .map(|rd| {
            rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn a_run_killed_mid_way_resumes_without_duplicate_or_gap() {
    let root = scratch("snapshots_kill");
    let p = plan(30, 8);
    let plan_path = root.join("plan.json");
    std::fs::write(&plan_path, p.pretty_json()).unwrap();
    let dir = root.join("d");
    let (plan_s, dir_s) = (plan_path.to_str().unwrap(), dir.to_str().unwrap());
    let mut child = bin()
        .args([
            "snapshots",
            "--plan",
            plan_s,
            "--out",
            dir_s,
            "--threads",
            "2",
            "--quiet",
        ])
        .args([
            "--runner",
            "analytic",
            "--delay-ms",
            "150",
            "--fail-every",
            "4",
        ])
        .spawn()
        .unwrap();
    let start = Instant::now();
    while case_files(&dir)
        .iter()
        .filter(|n| n.ends_with(".csv"))
        .count()
        < 6
    {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the run does not progress"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = case_files(&dir)
        .iter()
        .filter(|n| n.ends_with(".csv"))
        .count();
    assert!(
        (6..30).contains(&before),
        "killed after {before} cases: not mid-way"
    );
    let (ok, _, err) = outcome(&[
        "snapshots",
        "run",
        "--plan",
        plan_s,
        "--out",
        dir_s,
        "--runner",
        "analytic",
        "--fail-every",
        "4",
        "--quiet",
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains(&format!("{} cases done", 30 - before)),
        "{err}"
    );
    assert!(err.contains(&format!("{before} already done")), "{err}");
    let names = case_files(&dir);
    let expected: Vec<String> = (0..30).map(|i| format!("case_{i:06}.csv")).collect();
    assert_eq!(names, expected, "no duplicate, no gap, no temporary left");
    merge(&[dir], &root.join("m.csv")).unwrap();
    assert_eq!(
        std::fs::read(root.join("m.csv")).unwrap(),
        single_run(&p, &root)
    );
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn a_directory_of_another_plan_is_refused() {
    let root = scratch("snapshots_other_plan");
    let (a, b) = (plan(6, 1), plan(6, 2));
    let dir = root.join("d");
    run(&a, &dir, Shard::ALL, 1, &FAILING);
    let options = RunOptions {
        shard: Shard::ALL,
        threads: Some(1),
        retry_failed: false,
    };
    let err = run_shard(&b, &dir, &options, &FAILING, &quiet).unwrap_err();
    assert!(matches!(err, SnapshotError::PlanMismatch { .. }), "{err}");
    let msg = err.to_string();
    assert!(msg.contains(&a.hash()) && msg.contains(&b.hash()), "{msg}");
    // through the CLI
    let plan_b = root.join("b.json");
    std::fs::write(&plan_b, b.pretty_json()).unwrap();
    let (ok, _, err) = outcome(&[
        "snapshots",
        "--plan",
        plan_b.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--runner",
        "analytic",
    ]);
    assert!(!ok && err.contains("different plan"), "{err}");
    // merging directories of two plans
    let dir_b = root.join("e");
    run(&b, &dir_b, Shard::ALL, 1, &FAILING);
    let err = merge(&[dir, dir_b], &root.join("m.csv"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("holds plan"), "{err}");
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn merge_reports_missing_and_duplicate_cases() {
    let root = scratch("snapshots_merge_errors");
    let p = plan(9, 3);
    let (d1, d2, d1b) = (root.join("1"), root.join("2"), root.join("1b"));
    run(&p, &d1, shard("1/3"), 1, &FAILING);
    run(&p, &d2, shard("2/3"), 1, &FAILING);
    run(&p, &d1b, shard("1/3"), 1, &FAILING);
    let err = merge(&[d1.clone(), d2.clone()], &root.join("m.csv"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("3 cases missing (case_000002, case_000005, case_000008)"),
        "{err}"
    );
    let err = merge(&[d1, d2, d1b], &root.join("m.csv"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("3 cases in more than one directory"), "{err}");
    assert!(!root.join("m.csv").exists(), "no output on error");
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn a_partial_merge_holds_the_finished_cases_of_a_full_one() {
    let root = scratch("snapshots_merge_partial");
    let p = plan(9, 3);
    let (d1, d2, d3) = (root.join("1"), root.join("2"), root.join("3"));
    run(&p, &d1, shard("1/3"), 1, &FAILING);
    run(&p, &d2, shard("2/3"), 1, &FAILING);
    let s = merge_with(&[d1.clone(), d2.clone()], &root.join("part.csv"), true).unwrap();
    assert_eq!((s.cases, s.missing_cases), (6, 3));
    // duplicates stay an error
    run(&p, &d3, shard("1/3"), 1, &FAILING);
    let err = merge_with(&[d1.clone(), d3.clone()], &root.join("x.csv"), true)
        .unwrap_err()
        .to_string();
    assert!(err.contains("more than one directory"), "{err}");
    // the partial file is the full one without the rows of the missing cases
    let full_dir = root.join("full");
    run(&p, &full_dir, Shard::ALL, 1, &FAILING);
    merge(&[full_dir], &root.join("full.csv")).unwrap();
    let missing = ["case_000002,", "case_000005,", "case_000008,"];
    let expected: Vec<String> = std::fs::read_to_string(root.join("full.csv"))
        .unwrap()
        .lines()
        .filter(|l| !missing.iter().any(|m| l.starts_with(m)))
        .map(str::to_owned)
        .collect();
    let got: Vec<String> = std::fs::read_to_string(root.join("part.csv"))
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect();
    assert_eq!(got, expected);
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn a_tampered_case_file_is_reported_not_overwritten() {
    let root = scratch("snapshots_tampered");
    let p = plan(4, 3);
    let dir = root.join("d");
    run(&p, &dir, Shard::ALL, 1, &FAILING);
    let f = dir.join("cases/case_000001.csv");
    let text = std::fs::read_to_string(&f).unwrap();
    let cut: Vec<&str> = text.lines().take(3).collect();
    std::fs::write(&f, cut.join("\n") + "\n").unwrap();
    let options = RunOptions {
        shard: Shard::ALL,
        threads: Some(1),
        retry_failed: false,
    };
    let err = run_shard(&p, &dir, &options, &FAILING, &quiet)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("case_000001.csv")
            && err.contains("2 rows, expected one per plan pressure (6)"),
        "{err}"
    );
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn failed_cases_are_recorded_with_their_error() {
    let root = scratch("snapshots_failures");
    let p = plan(3, 1);
    let runner = |c: &PlannedCase, s: &PlanSettings| match c.id {
        0 => panic!("mesh exploded\nat step 3"),
        1 => CaseOutcome {
            steps: FAILING.run(c, s).steps[..2].to_vec(),
            error: Some("solver: no convergence at 1.0 bar".into()),
        },
        _ => FAILING.run(c, s),
    };
    let dir = root.join("d");
    run(&p, &dir, Shard::ALL, 1, &runner);
    let read = |id: usize| -> Vec<csv::StringRecord> {
        let mut r = csv::Reader::from_path(dir.join(format!("cases/case_{id:06}.csv"))).unwrap();
        r.records().map(|x| x.unwrap()).collect()
    };
    let error_col = header_line().split(',').position(|c| c == "error").unwrap();
    let rows = read(0);
    assert_eq!(rows.len(), 6);
    assert!(rows
        .iter()
        .all(|r| &r[8] == "false"
            && r[error_col].contains("runner panicked: mesh exploded; at step 3")));
    let rows = read(1);
    assert_eq!(
        rows.iter().map(|r| r[8].to_string()).collect::<Vec<_>>(),
        ["true", "true", "false", "false", "false", "false"]
    );
    assert_eq!(&rows[1][error_col], "");
    assert_eq!(&rows[2][error_col], "solver: no convergence at 1.0 bar");
    assert_eq!(&rows[2][9], "NaN");
    // a runner that forgets the error still leaves a trace
    let bytes = case_csv(&p.cases[2], &p.settings, &CaseOutcome::default());
    assert!(String::from_utf8(bytes)
        .unwrap()
        .contains("runner returned 0 of 6 steps without an error"));
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn verify_re_runs_random_cases_and_finds_changed_values() {
    use surrogate::snapshots::verify::resimulate;
    let root = scratch("snapshots_verify");
    let p = plan(8, 2);
    single_run(&p, &root);
    let data = root.join("single.csv");
    let checks = resimulate(&data, &p, 3, 1, &FAILING).unwrap();
    assert_eq!(checks.len(), 3);
    assert!(checks
        .iter()
        .all(|c| c.max_abs_diff == 0.0 && c.same_convergence));
    // the same 3 cases for the same seed, all cases when asking for more
    let ids: Vec<usize> = checks.iter().map(|c| c.id).collect();
    let again: Vec<usize> = resimulate(&data, &p, 3, 1, &FAILING)
        .unwrap()
        .iter()
        .map(|c| c.id)
        .collect();
    assert_eq!(ids, again);
    assert_eq!(resimulate(&data, &p, 50, 1, &FAILING).unwrap().len(), 8);
    // a runner that differs is caught, through the CLI too
    let shifted = |c: &PlannedCase, s: &PlanSettings| {
        let mut o = FAILING.run(c, s);
        o.steps.iter_mut().for_each(|st| st.tip_uy_mm += 1e-6);
        o
    };
    let checks = resimulate(&data, &p, 8, 1, &shifted).unwrap();
    assert!(
        checks
            .iter()
            .all(|c| c.max_abs_diff > 9e-7 && c.max_abs_diff < 2e-6),
        "{checks:?}"
    );
    let d = data.to_str().unwrap();
    let (ok, _, err) = outcome(&[
        "snapshots",
        "verify",
        "--data",
        d,
        "--runner",
        "analytic",
        "--fail-every",
        "4",
    ]);
    assert!(ok && err.contains("3 cases reproduce within 1e-9"), "{err}");
    let (ok, _, err) = outcome(&[
        "snapshots",
        "verify",
        "--data",
        d,
        "--runner",
        "analytic",
        "--cases",
        "8",
    ]);
    assert!(
        !ok && err.contains("DIFFER"),
        "the failing cases' flags differ: {err}"
    );
    // stored inputs that are not the plan's: an error before anything runs
    let text = std::fs::read_to_string(&data).unwrap();
    let t = format!("{:?}", p.cases[0].wall_thickness_mm);
    std::fs::write(&data, text.replace(&t, "2.0")).unwrap();
    let err = resimulate(&data, &p, 8, 1, &FAILING)
        .unwrap_err()
        .to_string();
    assert!(err.contains("case_000000: stored inputs"), "{err}");
    std::fs::remove_dir_all(root).unwrap();
}
