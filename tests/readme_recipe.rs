//! The README's embedded export recipe, run as written: every block marked
//! `<!-- recipe: FILE -->` is written to FILE in a scratch directory, the shell blocks run
//! there with the `surrogate` binary on the PATH, the Rust program and the C program are
//! built, called, and give the library's values.
use std::path::{Path, PathBuf};
use std::process::Command;

use surrogate::rom::{Query, Surrogate};

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

#[test]
fn readme_export_recipe_builds_and_runs_in_rust_and_c() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let b = blocks(&readme);
    let names: Vec<&str> = b.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "export.sh",
            "main.rs",
            "build_rust.sh",
            "lib.rs",
            "main.c",
            "build_c.sh"
        ]
    );
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_recipe");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // the recipe runs from the repository's root: its models and sources are reachable
    for link in ["models", "src"] {
        std::os::unix::fs::symlink(root.join(link), dir.join(link)).unwrap();
    }
    for (name, body) in &b {
        std::fs::write(dir.join(name), body).unwrap();
    }
    sh(&dir, "export.sh");
    let m = Surrogate::load(&root.join("models/actuator.json")).unwrap();
    let q = Query::new(11, 2.0, 0.0, [1.13, 3.11, -13.17, -0.6]);
    let mut pred = m.new_prediction();
    m.ramp(&q).unwrap().predict_into(2.0, &mut pred).unwrap();
    let lib = [
        pred.tip_uz_mm(),
        pred.tip_uy_mm(),
        pred.angle_deg(),
        pred.force_n(),
    ];
    let rust = sh(&dir, "build_rust.sh");
    let c_ok = Command::new("cc").arg("--version").output().is_ok();
    let c = if c_ok {
        sh(&dir, "build_c.sh")
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
