//! Helpers shared by the snapshot tests.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

use surrogate::snapshots::{Plan, PlanSettings, Ranges};

/// A fresh scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("surrogate_snapshots_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn small_settings() -> PlanSettings {
    PlanSettings {
        pressures_bar: vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5],
        ..PlanSettings::default()
    }
}

pub fn plan(cases: usize, seed: u64) -> Plan {
    Plan::generate(cases, seed, Ranges::default(), small_settings()).unwrap()
}

/// Runs the binary; (success, stderr).
pub fn cli(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_surrogate"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
