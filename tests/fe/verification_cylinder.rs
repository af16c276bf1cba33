//! Issue item 5: follower-pressure inflation of a thick-walled, nearly incompressible
//! neo-Hookean cylinder against the analytic pressure–stretch relation (see
//! `common::cylinder`).

use crate::common;

use crate::common::cylinder::{pressure, pressure_by_quadrature, run, ASSERTED, STRETCHES};

#[test]
fn closed_form_pressure_matches_the_integral() {
    for l in STRETCHES {
        let (closed, quad) = (pressure(l), pressure_by_quadrature(l, 2000));
        assert!(
            (closed - quad).abs() <= 1e-10 * closed,
            "a/A = {l}: closed form {closed} vs Simpson {quad}"
        );
    }
}

#[test]
fn inflated_cylinder_follows_the_analytic_pressure_stretch_relation() {
    common::assert_checks(&run(ASSERTED.0, ASSERTED.1));
}
