//! `surrogate twin` and `validate --effect` from the command line: every flag's bad value is a
//! named error before any FE run (the twin itself is tested in `tests/calibrate/twin.rs`).
use std::process::Command;

fn run(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_surrogate"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn twin_refuses_bad_flags_before_running_anything() {
    let dir = std::env::temp_dir().join(format!("surrogate_twin_cli_{}", std::process::id()));
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
    let cases: [(&[&str], &str); 6] = [
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
    ];
    for (extra, want) in cases {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let (ok, stderr) = run(&args);
        assert!(!ok && stderr.contains(want), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?}: nothing written");
    }
    let (ok, stderr) = run(&["twin", "--seed", "1", "--out", out_s]);
    assert!(!ok && stderr.contains("--material"), "{stderr}");
    let (ok, stderr) = run(&[
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
}

#[test]
fn validate_refuses_a_bad_effect_before_running_anything() {
    let dir = std::env::temp_dir().join(format!("surrogate_validate_cli_{}", std::process::id()));
    let out = dir.join("baseline.csv");
    let (ok, stderr) = run(&[
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
}
