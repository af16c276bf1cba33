//! Issue item 2: homogeneous uniaxial, equibiaxial and planar stretch of one element of
//! Ogden "002" against the analytic nominal stress (see `common::homogeneous`).

use crate::common;

use crate::common::homogeneous::{run, Mode, STRETCHES};

#[test]
fn uniaxial_stretch_matches_analytic_ogden_stress() {
    for l in STRETCHES {
        common::assert_checks(&run(Mode::Uniaxial, l));
    }
}

#[test]
fn equibiaxial_stretch_matches_analytic_ogden_stress() {
    for l in STRETCHES {
        common::assert_checks(&run(Mode::Equibiaxial, l));
    }
}

#[test]
fn planar_stretch_matches_analytic_ogden_stress() {
    for l in STRETCHES {
        common::assert_checks(&run(Mode::Planar, l));
    }
}
