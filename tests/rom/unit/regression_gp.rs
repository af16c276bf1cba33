//! The unit tests of `src/rom/regression/gp/mod.rs`.

use surrogate::rom::regression::gp::*;

#[test]
fn group_bounds_must_cover_all_columns_in_order() {
    assert!(valid_group_bounds(&[0, 5], 5));
    assert!(valid_group_bounds(&[0, 2, 5], 5));
    assert!(!valid_group_bounds(&[0], 5));
    assert!(!valid_group_bounds(&[1, 5], 5));
    assert!(!valid_group_bounds(&[0, 4], 5));
    assert!(!valid_group_bounds(&[0, 3, 3, 5], 5));
    assert!(!valid_group_bounds(&[0, 4, 2, 5], 5));
}
