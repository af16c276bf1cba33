//! The unit tests of `src/fe/material/ogden.rs`.

use surrogate::case::OgdenSet;
use surrogate::fe::material::ogden::*;

#[test]
fn conversions_with_the_case_set_keep_every_parameter() {
    let set = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);
    let p = OgdenParams::from(set);
    assert_eq!(
        p,
        OgdenParams {
            mu: [1.13, -13.17],
            alpha: [3.11, -0.6]
        }
    );
    assert_eq!(OgdenSet::from(p), set);
    let law = Ogden2::try_from(set).unwrap();
    assert_eq!(OgdenSet::from(&law), set);
    let bad = OgdenSet {
        alpha1: -3.11,
        ..set
    };
    assert!(Ogden2::try_from(bad).is_err());
}
