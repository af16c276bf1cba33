//! Issue item 3: patch test on a distorted, curved mesh (see `common::patch`).

use crate::common;

use crate::common::patch::{run, SCALES};

#[test]
fn distorted_patch_reproduces_small_linear_field_and_uniform_stress() {
    common::assert_checks(&run(3, SCALES[0]));
}

#[test]
fn distorted_patch_reproduces_large_linear_field_and_uniform_stress() {
    common::assert_checks(&run(3, SCALES[1]));
}
