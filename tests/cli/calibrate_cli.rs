//! `surrogate calibrate` from the command line: outputs, markers, bad input.
use std::path::Path;

use crate::common::{outcome, outcome_in, repo, scratch};

#[test]
fn writes_the_report_and_the_plots() {
    let dir = scratch("cal_out");
    let out = dir.to_str().unwrap();
    let (ok, stdout, stderr) = outcome(&[
        "calibrate",
        "--objective",
        "tip=1,force=0.5",
        "--starts",
        "3",
        "--profile-points",
        "6",
        "--exclude-flagged",
        "--out",
        out,
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("Objective `tip=1,force=0.5`"), "{stdout}");
    assert!(
        stdout.contains("## Excluded") && stdout.contains("N=11 T=1.6 P=1"),
        "{stdout}"
    );
    for f in [
        "report.json",
        "summary.md",
        "configurations.csv",
        "tips.svg",
        "forces.svg",
        "residuals.svg",
        "correlation.svg",
        "profiles.svg",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    // the 3 Latin-hypercube starts; the literature set, outside the shipped model's domain, is
    // not one
    assert_eq!(report["calibration"]["starts"].as_array().unwrap().len(), 3);
    // the three rows of N = 11, T = 1.6 the data checks flag (a length at 1 bar, tips too far
    // out for their angles at 2 and 3 bar)
    assert_eq!(
        report["calibration"]["excluded"].as_array().unwrap().len(),
        3
    );
    let csv = std::fs::read_to_string(dir.join("configurations.csv")).unwrap();
    assert_eq!(csv.lines().count(), 28);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn marker_recordings_enter_the_objective() {
    let dir = scratch("cal_markers");
    // markers 9 = the tip of the shipped bending rows, std 2 mm
    let bending =
        std::fs::read_to_string(repo().join("training_data/bending_experiments.csv")).unwrap();
    let mut m =
        String::from("n_bellows,wall_thickness_mm,pressure_bar,marker,uz_mm,uy_mm,std_mm\n");
    for line in bending.lines().skip(1) {
        let v: Vec<&str> = line.split(',').collect();
        m.push_str(&format!(
            "{},{},{},9,{},{},2\n",
            v[0], v[1], v[2], v[3], v[4]
        ));
    }
    let mf = dir.join("markers.csv");
    std::fs::write(&mf, m).unwrap();
    let (ok, stdout, stderr) = outcome(&[
        "calibrate",
        "--objective",
        "markers",
        "--bending",
        "training_data/bending_experiments.csv",
        "--markers",
        mf.to_str().unwrap(),
        "--starts",
        "2",
        "--profile-points",
        "4",
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("54 observations at 27 configurations"),
        "{stdout}"
    );
    let (ok, _, stderr) = outcome(&[
        "calibrate",
        "--objective",
        "markers",
        "--out",
        dir.join("o2").to_str().unwrap(),
    ]);
    assert!(
        !ok && stderr.contains("marker recordings (none were given)"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_recordings_name_file_line_and_column() {
    let dir = scratch("cal_bad");
    let f = dir.join("bending.csv");
    std::fs::write(
        &f,
        "n_bellows,wall_thickness_mm,pressure_bar,tip_uz_mm,tip_uy_mm,angle_deg,angle_std_deg,tip_uz_in\n9,1.6,1,9.4,-35.9,23.57,1.95,0.37\n",
    )
    .unwrap();
    let (ok, _, stderr) = outcome(&[
        "calibrate",
        "--bending",
        f.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("bending.csv, line 1, column tip_uz_in: unexpected column"),
        "{stderr}"
    );
    std::fs::write(
        &f,
        "n_bellows,wall_thickness_mm,pressure_bar,tip_uz_mm,tip_uy_mm,angle_deg,angle_std_deg\n9,1.6,1,9.4,-35.9,23.57,1.95\n9,1.6,1,9.5,-35.9,23.57,1.95\n",
    )
    .unwrap();
    let (ok, _, stderr) = outcome(&[
        "calibrate",
        "--bending",
        f.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        !ok && stderr.contains("line 3, column row: duplicate of line 2"),
        "{stderr}"
    );
    for (args, want) in [
        (vec!["--objective", "speed"], "objective = speed"),
        (vec!["--exclude", "11,1.6"], "--exclude = 11,1.6"),
        (vec!["--literature", "rubber"], "material = rubber"),
        (vec!["--verify-fe", "medium"], "medium"),
    ] {
        let mut a = vec!["calibrate", "--out", dir.to_str().unwrap()];
        a.extend(args);
        let (ok, _, stderr) = outcome(&a);
        assert!(!ok && stderr.contains(want), "{a:?}: {stderr}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let dest = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &dest);
        } else {
            std::fs::copy(&p, &dest).unwrap();
        }
    }
}

#[test]
fn refinement_reads_its_committed_round_and_reports_it() {
    let dir = scratch("cal_refine");
    // the committed FE of round 1: the command finds it and runs no FE
    copy_dir(
        &repo().join("fe_reference/calibration/refine_coarse/refine/round_1"),
        &dir.join("refine/round_1"),
    );
    let out = dir.to_str().unwrap();
    let (ok, stdout, stderr) = outcome(&[
        "calibrate",
        "--model",
        "models/as_modelled/actuator_coarse.json",
        "--refine",
        "3",
        "--out",
        out,
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("Stopped: surrogate and FE agree"),
        "{stdout}"
    );
    assert!(
        stdout.contains("| 1 | 300 | 1.761 | 5.996 | -0.2839 | -1.996 |"),
        "{stdout}"
    );
    assert!(stdout.contains("none (read back)"), "{stdout}");
    for f in [
        "refinement.md",
        "refinement.json",
        "refinement.svg",
        "summary.md",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let svg = std::fs::read_to_string(dir.join("refinement.svg")).unwrap();
    assert!(svg.contains("round 1 (300 training cases)"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn refinement_refuses_a_second_mesh_and_a_missing_training_set() {
    let dir = scratch("cal_refine_bad");
    let out = dir.to_str().unwrap();
    let (ok, _, stderr) = outcome(&[
        "calibrate",
        "--refine",
        "2",
        "--verify-fe",
        "standard",
        "--out",
        out,
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("--verify-fe standard with --refine 2"),
        "{stderr}"
    );
    let (ok, _, stderr) = outcome(&[
        "calibrate",
        "--model",
        "models/as_modelled/actuator_coarse.json",
        "--refine",
        "1",
        "--training",
        "no/such/snapshots.csv",
        "--out",
        out,
    ]);
    assert!(!ok);
    assert!(stderr.contains("no/such/snapshots.csv"), "{stderr}");
    let (ok, _, stderr) = outcome(&["calibrate", "--refine", "1", "--threads", "0", "--out", out]);
    assert!(!ok);
    assert!(stderr.contains("threads"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

fn repository(path: &str) -> String {
    repo().join(path).to_str().unwrap().to_string()
}

fn report_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

#[test]
fn only_the_recordings_named_are_read_and_every_input_is_listed() {
    let dir = scratch("cal_inputs");
    let mine = repository("tests/data/bad_recordings/three_rows.csv");
    let fast = ["--starts", "2", "--profile-points", "4"];
    // from a folder that is not the repository: the defaults are the repository's
    let out = dir.join("mine");
    let mut args = vec![
        "calibrate",
        "--bending",
        &mine,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(fast);
    let (ok, stdout, stderr) = outcome_in(&dir, &args);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("no --force: only the files named are read"),
        "{stderr}"
    );
    assert!(
        stdout.contains("6 observations at 3 configurations"),
        "{stdout}"
    );
    let inputs = report_json(&out)["calibration"]["inputs"].clone();
    let inputs = inputs.as_array().unwrap();
    let roles: Vec<&str> = inputs.iter().map(|f| f["role"].as_str().unwrap()).collect();
    assert_eq!(roles, ["model", "bending"], "no force file read");
    assert_eq!(inputs[0]["path"], repository("models/actuator.json"));
    assert_eq!(inputs[0]["default"], true);
    assert_eq!(inputs[1]["path"], mine.as_str());
    assert_eq!(inputs[1]["default"], false);
    assert_eq!(inputs[1]["rows"], 3);
    assert!(inputs[1]["checksum"]
        .as_str()
        .unwrap()
        .starts_with("crc32:"));
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains(&format!("| bending | `{mine}` | ")), "{md}");
    assert!(!md.contains("blocked_force"), "{md}");
    // the force is not taken from anywhere else
    let (ok, _, stderr) = outcome_in(
        &dir,
        &[
            "calibrate",
            "--bending",
            &mine,
            "--objective",
            "tip,force",
            "--out",
            "x",
        ],
    );
    assert!(
        !ok && stderr.contains("blocked-force recordings (none were given)"),
        "{stderr}"
    );
    let force = repository("training_data/blocked_force_experiments.csv");
    let (ok, _, stderr) = outcome_in(&dir, &["calibrate", "--force", &force, "--out", "x"]);
    assert!(
        !ok && stderr.contains("--force without --bending: the calibration needs bending"),
        "{stderr}"
    );
    // nothing named: both shipped files, listed as defaults
    let out = dir.join("defaults");
    let mut args = vec!["calibrate", "--out", out.to_str().unwrap()];
    args.extend(fast);
    let (ok, _, stderr) = outcome_in(&dir, &args);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("no recordings named: reading the shipped experiments"),
        "{stderr}"
    );
    let r = report_json(&out);
    let inputs = r["calibration"]["inputs"].as_array().unwrap();
    let files: Vec<(&str, bool)> = inputs
        .iter()
        .map(|f| (f["path"].as_str().unwrap(), f["default"].as_bool().unwrap()))
        .collect();
    let (b, m) = (
        repository("training_data/bending_experiments.csv"),
        repository("models/actuator.json"),
    );
    assert_eq!(
        files,
        [
            (m.as_str(), true),
            (b.as_str(), true),
            (force.as_str(), true)
        ]
    );
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("## Inputs") && md.contains("| default |"),
        "{md}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn recordings_in_other_units_or_signs_are_refused_by_name() {
    let dir = scratch("cal_units");
    let bad = |f: &str| repository(&format!("tests/data/bad_recordings/{f}"));
    let bending = repository("training_data/bending_experiments.csv");
    let cases: [(&[&str], &str); 6] = [
        (
            &["--bending", &bad("pressure_kpa.csv")],
            "column pressure_bar looks like kPa",
        ),
        (
            &["--bending", &bad("semicolons.csv")],
            "the file looks ;-separated",
        ),
        (
            &["--bending", &bad("n16.csv")],
            "9 recorded rows lie outside the surrogate's domain",
        ),
        (
            &["--bending", &bending, "--force", &bad("force_mn.csv")],
            "column force_n looks like mN",
        ),
        (
            &["--bending", &bad("sign_flip.csv")],
            "column tip_uy_mm has the other sign",
        ),
        (
            &["--bending", &bad("tip_cm.csv")],
            "columns tip_uz_mm and tip_uy_mm look like cm",
        ),
    ];
    let out = dir.join("out");
    for (extra, want) in cases {
        let mut args = vec!["calibrate", "--out", out.to_str().unwrap()];
        args.extend(extra);
        let (ok, _, stderr) = outcome_in(&dir, &args);
        assert!(!ok && stderr.contains(want), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?}: nothing written");
    }
    // the same file with its unit in the column name is converted and named in the report
    let kpa = std::fs::read_to_string(bad("pressure_kpa.csv"))
        .unwrap()
        .replacen("pressure_bar", "pressure_kpa", 1);
    let f = dir.join("kpa.csv");
    std::fs::write(&f, kpa).unwrap();
    let (ok, stdout, stderr) = outcome_in(
        &dir,
        &[
            "calibrate",
            "--bending",
            f.to_str().unwrap(),
            "--starts",
            "2",
            "--profile-points",
            "4",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("54 observations at 27 configurations"),
        "{stdout}"
    );
    assert!(
        stdout.contains("bending: column pressure_kpa → pressure_bar × 0.01"),
        "{stdout}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
