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
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn derivative_of(o: &Outputs, output: Output) -> Option<f64> {
    match output {
        Output::TipUz => Some(o.tip_uz_mm),
        Output::TipUy => Some(o.tip_uy_mm),
        Output::Angle => Some(o.angle_deg),
        Output::Force => o.force_n,
        Output::MarkerUz(k) => o.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[0]),
        Output::MarkerUy(k) => o.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[1]),
    }
}

/// A derivative larger than this many times the largest of the same derivative at the
/// ramp's other (non-zero) pressures is a spike.
pub(crate) const SPIKE_RATIO: f64 = 10.0;

/// The first parameter whose derivative of `output` at step `i` of `s` is a spike: more than
/// [`SPIKE_RATIO`] times its largest magnitude at the other non-zero pressures of the ramp.
/// Such a derivative (seen in the force rig at a contact switch: a force of 0.6 N whose
/// derivative by the gravity factor is −25 N while it is −0.16 N one bar later) predicts
/// changes the effect cannot make: the Name stage lists such cells. Returns the parameter's
/// name and the ratio.
pub(crate) fn spike(s: &Sensitivities, i: usize, output: Output) -> Option<(String, f64)> {
    for (j, p) in s.parameters.iter().enumerate() {
        let d = derivative_of(&s.steps[i].derivatives[j], output)?.abs();
        let others = s
            .steps
            .iter()
            .enumerate()
            .filter(|(k, st)| *k != i && st.pressure_bar > 0.0)
            .filter_map(|(_, st)| derivative_of(&st.derivatives[j], output))
            .map(f64::abs)
            .fold(0.0, f64::max);
        if others > 0.0 && d > SPIKE_RATIO * others {
            return Some((p.parameter.name().to_string(), d / others));
        }
    }
    None
}

/// The derivative spike of a cell, if its sensitivities have one ([`spike`]).
pub(crate) fn cell_spike(sens: &SweepSensitivities, c: &Cell) -> Option<(String, f64)> {
    let (s, i) = step_of(sens, c)?;
    spike(s, i, c.output)
}

/// The sensitivities of a cell's ramp and the index of its step.
pub(crate) fn sensitivity_step<'a>(
    sens: &'a SweepSensitivities,
    c: &Cell,
) -> Option<(&'a Sensitivities, usize)> {
    step_of(sens, c)
}

/// The rig that records `output`: the blocked force in the force rig, the rest in bending.
pub(crate) fn rig(output: Output) -> Mode {
    if output == Output::Force {
        Mode::Force
    } else {
        Mode::Bending
    }
}

fn step_of<'a>(sens: &'a SweepSensitivities, c: &Cell) -> Option<(&'a Sensitivities, usize)> {
    let s = sens.design(c.n_bellows as usize, c.wall_thickness_mm, rig(c.output))?;
    let i = s
        .steps
        .iter()
        .position(|st| (st.pressure_bar - c.pressure_bar).abs() < 1e-9)?;
    Some((s, i))
}
