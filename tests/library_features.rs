//! The library does not need the command-line program's dependencies (clap, indicatif, plotters,
//! anyhow): they are optional, enabled by the default feature `cli`, and no library source
//! refers to them.
use std::path::{Path, PathBuf};

const CLI_CRATES: [&str; 4] = ["clap", "indicatif", "plotters", "anyhow"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.rs` file under `dir`, except under `skip`.
fn rust_files(dir: &Path, skip: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.starts_with(skip) {
            continue;
        }
        if path.is_dir() {
            rust_files(&path, skip, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Whether `text` names `krate` as a path (`krate::`, `use krate`, `extern crate krate`).
fn names_crate(text: &str, krate: &str) -> bool {
    text.lines().any(|line| {
        let line = line.trim_start();
        !line.starts_with("//")
            && (line.contains(&format!("{krate}::"))
                || line.starts_with(&format!("use {krate}"))
                || line.contains(&format!("extern crate {krate}")))
    })
}

#[test]
fn library_sources_do_not_name_the_cli_crates() {
    let mut files = Vec::new();
    rust_files(&root().join("src"), &root().join("src/bin"), &mut files);
    assert!(files.len() > 20, "{files:?}");
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for krate in CLI_CRATES {
            assert!(
                !names_crate(&text, krate),
                "{} uses `{krate}`, a dependency of the `cli` feature only",
                f.display()
            );
        }
    }
    assert!(names_crate("use anyhow::Context;", "anyhow"));
    assert!(!names_crate("/// anyhow::Result in the binary", "anyhow"));
}

#[test]
fn cli_crates_are_optional_and_enabled_by_the_default_cli_feature() {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let deps = manifest
        .split("\n[dependencies]\n")
        .nth(1)
        .and_then(|t| t.split("\n[").next())
        .unwrap();
    for krate in CLI_CRATES {
        let line = deps
            .lines()
            .find(|l| l.starts_with(&format!("{krate} ")))
            .unwrap_or_else(|| panic!("{krate} is not a dependency"));
        assert!(line.contains("optional = true"), "{line}");
    }
    let lines: Vec<&str> = manifest.lines().collect();
    assert!(lines.contains(&"default = [\"cli\"]"));
    assert!(lines
        .contains(&"cli = [\"dep:clap\", \"dep:indicatif\", \"dep:plotters\", \"dep:anyhow\"]"));
    assert!(manifest.contains(
        "[[bin]]\nname = \"surrogate\"\npath = \"src/bin/surrogate/main.rs\"\nrequired-features = [\"cli\"]"
    ));
}

/// The library builds without the default features. Ignored in the ordinary run: in a target
/// directory of its own it compiles every dependency again (about 10 minutes on 2 cores;
/// the library alone, with warm dependencies, about 4 minutes in release). Run it with
/// `cargo test --release --test library_features library_builds_without_default_features -- --ignored`.
#[test]
#[ignore = "compiles the dependencies in a target directory of its own (minutes); run: cargo test --release --test library_features library_builds_without_default_features -- --ignored"]
fn library_builds_without_default_features() {
    let target = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("no_default_features");
    let out = std::process::Command::new(env!("CARGO"))
        .args(["check", "--lib", "--no-default-features", "--offline"])
        .arg("--manifest-path")
        .arg(root().join("Cargo.toml"))
        .arg("--target-dir")
        .arg(&target)
        .env_remove("CARGO_TARGET_DIR")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "cargo check --lib --no-default-features failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
