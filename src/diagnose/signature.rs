//! Where a cell's FE sensitivities sit in a sweep, and the material re-fit's local residual
//! and directions per cell: what the Name and Model-and-show stages share.

use super::cells::Cell;
use crate::calibrate::baseline::SweepSensitivities;
use crate::calibrate::objective::Output;
use crate::fe::sensitivity::{Outputs, Sensitivities};
use crate::fe::simulate::Mode;

/// Per cell: the residual `z` after the material re-fit and its row of the material
/// Jacobian (σ-scaled), for the cells with sensitivities.
pub(crate) type LocalMaterial = Vec<Option<(f64, [f64; 4])>>;

/// The derivative (or value) of `output` in `o`.
pub(crate) fn derivative_of(o: &Outputs, output: Output) -> Option<f64> {
    match output {
        Output::TipUz => Some(o.tip_uz_mm),
        Output::TipUy => Some(o.tip_uy_mm),
        Output::Angle => Some(o.angle_deg),
        Output::Force => o.force_n,
        Output::MarkerUz(k) => o.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[0]),
        Output::MarkerUy(k) => o.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[1]),
    }
}

/// The sensitivities of a cell's ramp and the index of its step.
pub(crate) fn sensitivity_step<'a>(
    sens: &'a SweepSensitivities,
    c: &Cell,
) -> Option<(&'a Sensitivities, usize)> {
    let mode = if c.output == Output::Force {
        Mode::Force
    } else {
        Mode::Bending
    };
    let s = sens.design(c.n_bellows as usize, c.wall_thickness_mm, mode)?;
    let i = s
        .steps
        .iter()
        .position(|st| (st.pressure_bar - c.pressure_bar).abs() < 1e-9)?;
    Some((s, i))
}
