//! The test helper of `src/diagnose/cells.rs` (no tests of its own): a fitted cell from its
//! standardised residual, which the unit tests of the later stages build tables from.

use surrogate::calibrate::objective::Output;
use surrogate::diagnose::cells::{Cell, Family};

/// [`Cell::unit`], for the tests (an extension trait, so that the tests call it as before).
pub(crate) trait UnitCell {
    /// A fitted cell of `σ = 1` whose prediction is its standardised residual `z` (tests).
    fn unit(
        n_bellows: u32,
        wall_thickness_mm: f64,
        pressure_bar: f64,
        output: Output,
        z: f64,
    ) -> Self;
}

impl UnitCell for Cell {
    fn unit(
        n_bellows: u32,
        wall_thickness_mm: f64,
        pressure_bar: f64,
        output: Output,
        z: f64,
    ) -> Self {
        Cell {
            n_bellows,
            wall_thickness_mm,
            pressure_bar,
            output,
            family: Family::of(output),
            marker: None,
            recorded: 0.0,
            predicted: z,
            sigma: 1.0,
            standardised: z,
            chi2_share: 0.0,
            fitted: true,
            fit_chi2_share: None,
        }
    }
}
