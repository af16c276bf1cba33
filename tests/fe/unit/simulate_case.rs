//! The unit tests of `src/fe/simulate/case.rs`.

use surrogate::fe::simulate::case::*;
use surrogate::fe::simulate::SimulateError;

#[test]
fn max_step_lists_every_level_rounded_to_a_nanobar() {
    assert_eq!(parse_pressures("3:0.1").unwrap()[3], 0.3);
    assert_eq!(
        parse_pressures("1:0.25").unwrap(),
        [0.0, 0.25, 0.5, 0.75, 1.0]
    );
    assert_eq!(parse_pressures(" 0, 1.5 ,2").unwrap(), [0.0, 1.5, 2.0]);
}

#[test]
fn malformed_lists_name_the_entry() {
    let message = |s: &str| parse_pressures(s).unwrap_err().to_string();
    assert!(message("0,1,x").contains("entry 3 'x' is not a number"));
    assert!(message("3:0").contains("expected max ≥ 0 and step > 0"));
    assert!(message("a:1").contains("expected max:step, two numbers"));
}

#[test]
fn pressures_are_nonnegative_increasing_and_bounded() {
    assert!(validate_pressures(&[0.0, 1.0, MAX_PRESSURE_BAR]).is_ok());
    let index = |p: &[f64]| match validate_pressures(p) {
        Err(SimulateError::Pressure { index, .. }) => Some(index),
        _ => None,
    };
    assert_eq!(index(&[]), Some(0));
    assert_eq!(index(&[0.0, 1.0, -2.0]), Some(2));
    assert_eq!(index(&[2.0, 1.0]), Some(1));
    assert_eq!(index(&[0.0, f64::NAN]), Some(1));
    assert_eq!(index(&[MAX_PRESSURE_BAR + 0.5]), Some(0));
}
