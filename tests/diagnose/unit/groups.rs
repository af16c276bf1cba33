//! The unit tests of `src/diagnose/groups.rs`.

use surrogate::diagnose::groups::holm;

#[test]
fn holm_steps_down_and_stops_at_the_first_failure() {
    // thresholds 0.05/4, 0.05/3, 0.05/2, 0.05
    assert_eq!(
        holm(&[0.01, 0.04, 0.012, 0.3], 0.05),
        [true, false, true, false]
    );
    assert_eq!(holm(&[0.001, 0.02, 0.03], 0.05), [true, true, true]);
    assert_eq!(holm(&[0.03, f64::NAN], 0.05), [false, false]);
    assert!(holm(&[], 0.05).is_empty());
}
