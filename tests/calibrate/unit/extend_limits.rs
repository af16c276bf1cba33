//! The unit tests of `src/calibrate/extend/limits.rs`.

use surrogate::calibrate::extend::PhysicalLimits;
use surrogate::case::material::COORD_NAMES;

#[test]
fn the_default_limits_hold_the_literature_sets_and_bad_ones_are_named() {
    let l = PhysicalLimits::default();
    l.validate().unwrap();
    for name in ["ogden_002", "ogden_005"] {
        let c = surrogate::case::OgdenSet::literature(name)
            .unwrap()
            .coords();
        for (i, v) in c.as_array().into_iter().enumerate() {
            let [lo, hi] = l.range(i);
            assert!(lo < v && v < hi, "{name}: {} = {v}", COORD_NAMES[i]);
        }
    }
    let bad = PhysicalLimits {
        term1_share: [0.0, 1.0],
        ..l
    };
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("physical limits of term1_share = [0, 1]"), "{e}");
    let bad = PhysicalLimits {
        alpha2: [-20.0, f64::NAN],
        ..l
    };
    assert!(bad.validate().unwrap_err().to_string().contains("alpha2"));
}
