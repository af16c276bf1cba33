//! The embedded export recipes of `README.md` (a ramp) and `predict/README.md` (the whole
//! model), run as written: every block marked `<!-- recipe: FILE -->` is written to FILE in a
//! scratch directory that holds this repository as `surrogate/`, the shell blocks run there
//! with the `surrogate` binary on the PATH, the Rust and the C controller are built with cargo
//! against the `surrogate-predict` crate, called, and give the library's values.
use std::path::{Path, PathBuf};
use std::process::Command;

use surrogate::case::{OgdenSet, Query};
use surrogate::rom::Surrogate;

use crate::common::{fresh, repo};

fn blocks(readme: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = readme;
    while let Some(i) = rest.find("<!-- recipe: ") {
        rest = &rest[i + "<!-- recipe: ".len()..];
        let (name, tail) = rest.split_once(" -->").unwrap();
        let open = tail.find("```").unwrap();
        let body_start = open + tail[open..].find('\n').unwrap() + 1;
        let body_len = tail[body_start..].find("```").unwrap();
        out.push((
            name.trim().to_string(),
            tail[body_start..body_start + body_len].to_string(),
        ));
        rest = &tail[body_start + body_len..];
    }
    out
}

fn sh(dir: &Path, script: &str) -> String {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_surrogate")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let o = Command::new("sh")
        .arg("-e")
        .arg(script)
        .current_dir(dir)
        .env("PATH", path)
        // the controllers depend on `surrogate-predict` by path only
        .env("CARGO_NET_OFFLINE", "true")
        .env_remove("CARGO_TARGET_DIR")
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{script}:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The four numbers of a line `tip Uz … mm, Uy … mm, angle … deg, force … N`.
fn numbers(line: &str) -> Vec<f64> {
    line.split([' ', ','])
        .filter_map(|t| t.parse().ok())
        .collect()
}

/// Writes the recipe blocks of `readme` (relative to the repository) into a fresh scratch
/// directory `name` beside a link `surrogate` to the repository, runs `export.sh`, and returns
/// the directory; the block names must be `expected`.
fn recipe(readme: &str, name: &str, expected: &[&str]) -> PathBuf {
    let root = repo();
    let text = std::fs::read_to_string(root.join(readme)).unwrap();
    let b = blocks(&text);
    let names: Vec<&str> = b.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, expected, "{readme}");
    let dir = fresh(PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name));
    std::os::unix::fs::symlink(root, dir.join("surrogate")).unwrap();
    for (name, body) in &b {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, body).unwrap();
    }
    sh(&dir, "export.sh");
    dir
}

/// Runs the Rust and (with a C compiler) the C build script of a recipe; each prints one line
/// `tip Uz … mm, Uy … mm, angle … deg, force … N` that must give `lib` to the printed digits.
fn check_rust_and_c(dir: &Path, lib: [f64; 4]) {
    let rust = sh(dir, "build_rust.sh");
    let c_ok = Command::new("cc").arg("--version").output().is_ok();
    let c = if c_ok {
        sh(dir, "build_c.sh")
    } else {
        eprintln!("no C compiler: the C half is skipped");
        rust.clone()
    };
    for out in [rust, c] {
        let v = numbers(out.trim());
        assert_eq!(v.len(), 4, "{out}");
        for k in 0..4 {
            // printed with 2–3 decimals
            assert!((v[k] - lib[k]).abs() <= 0.006, "{out}: {v:?} vs {lib:?}");
        }
    }
}

fn shipped_model() -> Surrogate {
    Surrogate::load(&repo().join("models/actuator.json")).unwrap()
}

/// The set calibrated through the shipped model, as its report stores it (the README's
/// material, `--material …/shipped_surrogate/report.json`).
fn calibrated() -> OgdenSet {
    let report = repo().join(crate::common::SHIPPED_REPORT);
    surrogate::rom::batch::material_params(report.to_str().unwrap()).unwrap()
}

#[test]
fn readme_export_recipe_builds_and_runs_in_rust_and_c() {
    let dir = recipe(
        "README.md",
        "readme_recipe",
        &[
            "export.sh",
            "controller/Cargo.toml",
            "controller/src/main.rs",
            "build_rust.sh",
            "ramp_c/Cargo.toml",
            "ramp_c/src/lib.rs",
            "ramp_c/main.c",
            "build_c.sh",
        ],
    );
    let m = shipped_model();
    let q = Query::new(11, 2.0, 0.0, calibrated());
    let mut pred = m.new_prediction();
    m.ramp(&q).unwrap().predict_into(2.0, &mut pred).unwrap();
    let lib = [
        pred.tip_uz_mm(),
        pred.tip_uy_mm(),
        pred.angle_deg(),
        pred.force_n(),
    ];
    check_rust_and_c(&dir, lib);
}

#[test]
fn predict_readme_recipe_builds_and_runs_in_rust_and_c() {
    let dir = recipe(
        "predict/README.md",
        "predict_readme_recipe",
        &[
            "export.sh",
            "controller/Cargo.toml",
            "controller/src/main.rs",
            "build_rust.sh",
            "actuator_c/Cargo.toml",
            "actuator_c/src/lib.rs",
            "actuator_c/main.c",
            "build_c.sh",
        ],
    );
    let m = shipped_model();
    let p = m
        .predict(&Query::new(
            11,
            2.0,
            2.0,
            // the predict README's input, as written there
            OgdenSet::from_array([0.2108, 18.1271, -1.2232, -1.9958]),
        ))
        .unwrap();
    let lib = [p.tip_uz_mm(), p.tip_uy_mm(), p.angle_deg(), p.force_n()];
    check_rust_and_c(&dir, lib);
}
