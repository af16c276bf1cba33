//! The small plans the snapshot tests share.
#![allow(dead_code)]

use surrogate::snapshots::{Plan, PlanSettings, Ranges};

pub fn small_settings() -> PlanSettings {
    PlanSettings {
        pressures_bar: vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5],
        ..PlanSettings::default()
    }
}

pub fn plan(cases: usize, seed: u64) -> Plan {
    Plan::generate(cases, seed, Ranges::default(), small_settings()).unwrap()
}
