//! Issue item 6: large rotation of a slender cantilever under a dead tip load against the
//! elastica (see `common::cantilever`).

use crate::common;

use crate::common::cantilever::{elastica, run, tip_displacements_with, ASSERTED};

#[test]
fn elastica_shooting_reproduces_small_load_beam_theory() {
    // k → 0: δ/L = k/3, shortening/L = k²/15 (from y = k(s²/2 − s³/6)), rotation k/2
    let k = 1e-3;
    let (rotation, deflection, shortening) = elastica(k);
    assert!((rotation / (k / 2.0) - 1.0).abs() < 1e-3, "{rotation}");
    assert!((deflection / (k / 3.0) - 1.0).abs() < 1e-3, "{deflection}");
    assert!(
        (shortening / (k * k / 15.0) - 1.0).abs() < 1e-3,
        "{shortening}"
    );
}

#[test]
fn cantilever_tip_follows_the_elastica_at_large_rotation() {
    common::assert_checks(&run(ASSERTED.0, ASSERTED.1));
}

/// The solver's predictor (quadratic extrapolation along the load path) changes the number of
/// Newton iterations of this large-rotation ramp, not its solution.
#[test]
fn predictor_saves_iterations_not_accuracy() {
    let (with, it_with) = tip_displacements_with(ASSERTED.0, ASSERTED.1, true);
    let (without, it_without) = tip_displacements_with(ASSERTED.0, ASSERTED.1, false);
    for (a, b) in with.iter().zip(&without) {
        let scale = b.0.abs().max(b.1.abs());
        assert!(
            (a.0 - b.0).abs().max((a.1 - b.1).abs()) <= 1e-7 * scale,
            "tip {a:?} vs {b:?}"
        );
    }
    assert!(
        it_with < it_without,
        "Newton iterations with the predictor {it_with}, without {it_without}"
    );
}
