//! Full runs shared by the tests of this binary: a case that several tests compare with is
//! run once, by whichever test asks first, while the others wait for it.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use surrogate::fe::simulate::{simulate, Case, StepResult};

type Slot = Arc<OnceLock<Vec<StepResult>>>;

/// The steps of `case`, run once per test binary (cases are equal when their JSON is).
pub fn steps(case: &Case) -> Vec<StepResult> {
    static RUNS: OnceLock<Mutex<HashMap<String, Slot>>> = OnceLock::new();
    let key = serde_json::to_string(case).unwrap();
    let slot = RUNS
        .get_or_init(Default::default)
        .lock()
        .unwrap()
        .entry(key)
        .or_default()
        .clone();
    slot.get_or_init(|| simulate(case).unwrap().steps).clone()
}
