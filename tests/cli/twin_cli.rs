//! `surrogate twin` and `validate --effect` from the command line: every flag's bad value is a
//! named error before any FE run (the twin itself is tested in `tests/calibrate/twin.rs`).
use crate::common::{outcome, repo, scratch};

#[test]
fn twin_refuses_bad_flags_before_running_anything() {
    let dir = scratch("twin_cli");
    let out = dir.join("twin");
    let out_s = out.to_str().unwrap();
    let key_inside = out.join("key.json");
    let cache_inside = out.join("cache");
    let base = [
        "twin",
        "--material",
        "ogden_002",
        "--mesh",
        "coarse",
        "--seed",
        "3",
        "--out",
        out_s,
    ];
    let cases: [(&[&str], &str); 7] = [
        (&["--effect", "wal_bias=0.1"], "unknown effect \"wal_bias\""),
        (
            &["--effect", "wall_bias=0.9"],
            "effect wall_bias = 0.9 mm: expected a value in [-0.4, 0.4] mm",
        ),
        (
            &["--effect", "density=1.1", "--effect", "density=1.2"],
            "effect density given twice",
        ),
        (
            &["--key", key_inside.to_str().unwrap()],
            "expected a file outside the twin's directory",
        ),
        (
            &["--cache", cache_inside.to_str().unwrap()],
            "expected a directory outside the twin's directory",
        ),
        (
            &["--noise-from", "no_such_dir"],
            "no_such_dir/bending_experiments.csv",
        ),
        (
            &["--element-size", "0.1"],
            "--element-size 0.1: expected an element size in (0.2, 50] mm",
        ),
    ];
    for (extra, want) in cases {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let (ok, _, stderr) = outcome(&args);
        assert!(!ok && stderr.contains(want), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?}: nothing written");
    }
    let (ok, _, stderr) = outcome(&["twin", "--seed", "1", "--out", out_s]);
    assert!(!ok && stderr.contains("--material"), "{stderr}");
    let (ok, _, stderr) = outcome(&[
        "twin",
        "--material",
        "ogden_002",
        "--mesh",
        "fine2",
        "--seed",
        "1",
        "--out",
        out_s,
    ]);
    assert!(!ok && stderr.contains("fine2"), "{stderr}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn validate_refuses_a_bad_effect_before_running_anything() {
    let dir = scratch("validate_cli");
    let out = dir.join("baseline.csv");
    let (ok, _, stderr) = outcome(&[
        "validate",
        "--mesh",
        "coarse",
        "--effect",
        "clamp_compliance=-1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        !ok && stderr.contains("clamp_compliance = -1 mm/MPa: expected a value in [0, 0.5]"),
        "{stderr}"
    );
    assert!(!dir.join("baseline_ramps").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn twin_study_refuses_bad_flags_and_plans() {
    let dir = scratch("twin_study");
    let out = dir.join("study");
    let out_s = out.to_str().unwrap();
    let (ok, _, stderr) = outcome(&["twin-study", "--out", out_s, "--stage", "fe"]);
    assert!(
        !ok && stderr.contains("--stage fe: expected twins, diagnose, all or loop"),
        "{stderr}"
    );
    assert!(!out.exists());
    let (ok, _, stderr) = outcome(&[
        "twin-study",
        "--out",
        out_s,
        "--stage",
        "loop",
        "--loop-k",
        "4",
    ]);
    assert!(
        !ok && stderr.contains("--loop-k") && stderr.contains("measurements to plan = 4"),
        "{stderr}"
    );
    assert!(!out.exists());
    // the standard plan is written where none is, and a group it lacks is named
    let (ok, _, stderr) = outcome(&[
        "twin-study",
        "--out",
        out_s,
        "--stage",
        "twins",
        "--groups",
        "null_9",
    ]);
    assert!(
        !ok && stderr.contains("--groups of")
            && stderr.contains("group = null_9: expected a group of the plan")
            && stderr.contains("null_6"),
        "{stderr}"
    );
    let plan = std::fs::read_to_string(out.join("plan.json")).unwrap();
    assert!(plan.contains("\"format\": \"surrogate.twin-study-plan\""));
    // the committed plan is that plan: same draws, same groups
    let committed =
        std::fs::read_to_string(repo().join("fe_reference/diagnosis/blind/plan.json")).unwrap();
    assert_eq!(plan, committed);
    // a plan of another format or version is refused, naming the file
    std::fs::write(
        out.join("plan.json"),
        plan.replace("\"version\": 1", "\"version\": 4"),
    )
    .unwrap();
    let (ok, _, stderr) = outcome(&["twin-study", "--out", out_s, "--stage", "diagnose"]);
    assert!(
        !ok && stderr.contains("plan.json: version = 4: expected 1"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn approximation_error_refuses_bad_settings_before_any_fe() {
    let dir = scratch("approx");
    let out = dir.join("e.json");
    let o = out.to_str().unwrap();
    let d = dir.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (&["--materials", "1"], "--materials 1: expected at least 2"),
        (&["--mesh", "finest"], "--mesh finest"),
        (&["--element-size", "0.01"], "--element-size 0.01: expected"),
        (&["--model", "no_such_model.json"], "no_such_model.json"),
    ];
    for (extra, want) in cases {
        let args: Vec<&str> = ["approximation-error", "--out", o]
            .iter()
            .chain(extra)
            .copied()
            .collect();
        let (ok, _, stderr) = outcome(&args);
        assert!(!ok && stderr.contains(want), "{extra:?}: {stderr}");
    }
    let (ok, _, stderr) = outcome(&["approximation-error", "--out", d]);
    assert!(
        !ok && stderr.contains("a directory (expected the file"),
        "{stderr}"
    );
    assert!(!out.exists() && !dir.join("approximation_fe_ramps").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
