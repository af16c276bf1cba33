//! The unit tests of `src/calibrate/extend/plan.rs`.

use surrogate::calibrate::extend::{extension_case_id, high_fidelity_cases};

#[test]
fn high_fidelity_share_follows_the_training_set() {
    // the shipped sets: 300 coarse, 36 standard
    assert_eq!(high_fidelity_cases(36, 300, 36, 3), 5);
    assert_eq!(high_fidelity_cases(36, 300, 36, 9), 9);
    assert_eq!(high_fidelity_cases(6, 30, 30, 3), 6);
    assert_eq!(extension_case_id(1, 0), 15_000);
    assert_eq!(extension_case_id(2, 4_999), 29_999);
}
