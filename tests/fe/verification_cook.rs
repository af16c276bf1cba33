//! Issue item 4: Cook's membrane, nearly incompressible neo-Hookean in plane strain
//! (see `common::cook`).

use crate::common;

use crate::common::cook::study;

#[test]
fn cook_membrane_corner_displacement_converges_to_reference() {
    let checks = study();
    common::assert_checks(&checks);
    // converging under refinement: successive changes shrink
    let u: Vec<f64> = checks.iter().map(|c| c.computed).collect();
    let changes: Vec<f64> = u.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    println!("successive changes {changes:?}");
    assert!(
        changes.windows(2).all(|w| w[1] < w[0]),
        "corner displacement not converging: {u:?}"
    );
}
