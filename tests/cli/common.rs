//! What every test of the program needs: the binary, run from the repository's root; what a
//! run printed; a failure that names its cause; and scratch directories.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The committed calibration report through the model of the geometry as modelled (a material
/// wherever one is taken with `models/as_modelled/`).
pub const REPORT: &str = "fe_reference/calibration/surrogate/report.json";
/// The committed calibration report through the shipped model (a material inside its domain,
/// wherever one is taken with the default model).
pub const SHIPPED_REPORT: &str = "fe_reference/identification/shipped_surrogate/report.json";

/// The repository's root, where the program runs unless a test says otherwise.
pub fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The program, to be run from the repository's root (`current_dir` moves it elsewhere).
pub fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_surrogate"));
    c.current_dir(repo());
    c
}

/// Runs the program from the repository's root.
pub fn run(args: &[&str]) -> Output {
    run_in(repo(), args)
}

/// Runs the program in the working directory `dir`.
pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    bin().current_dir(dir).args(args).output().unwrap()
}

/// What a run printed: (stdout, stderr).
pub fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Runs the program from the repository's root: (success, stdout, stderr).
pub fn outcome(args: &[&str]) -> (bool, String, String) {
    outcome_in(repo(), args)
}

/// Runs the program in the working directory `dir`: (success, stdout, stderr).
pub fn outcome_in(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let o = run_in(dir, args);
    let (out, err) = text(&o);
    (o.status.success(), out, err)
}

/// Asserts that the command failed and that its stderr names every one of `needles`.
pub fn fails_with(o: &Output, needles: &[&str]) {
    let err = text(o).1;
    assert!(
        !o.status.success() && needles.iter().all(|n| err.contains(n)),
        "expected a failure naming {needles:?}, got status {:?}: {err}",
        o.status.code()
    );
}

/// `dir`, emptied of whatever an earlier run left there, and created.
pub fn fresh(dir: PathBuf) -> PathBuf {
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A fresh, empty directory of one test, outside the repository and unique to this process;
/// `name` must be unique among the tests of this binary (they run in parallel).
pub fn scratch(name: &str) -> PathBuf {
    fresh(std::env::temp_dir().join(format!("surrogate_{name}_{}", std::process::id())))
}

/// A directory under cargo's scratch folder that the tests of one module share: created,
/// never emptied (those tests run in parallel and each writes its own files).
pub fn shared_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}
