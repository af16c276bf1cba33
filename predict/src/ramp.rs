//! An exported ramp (one design, one material): only the pressure stencil is left.

use crate::error::EmbeddedError;
use crate::maths::Real;
use crate::outputs::N_QUANTITIES;
use crate::stencil::stencil;

/// One design and one material exported as its reconstructed pressure ramp
/// (`surrogate export --ramp`): for a controller whose actuator and calibrated material are
/// fixed, no regression is left to evaluate, only the pressure stencil.
#[derive(Debug, Clone, Copy)]
pub struct RampTables<'a, F> {
    /// Pressure grid, bar (sorted, at least 2 nodes).
    pub pressures: &'a [f64],
    /// The 22 quantities at each node, node-major: `values[j * 22 + q]`.
    pub values: &'a [F],
}

/// The 22 quantities of an exported ramp at `p_bar` (clamped to the grid, as the library
/// does); no allocation. In `f64` it is the library's `Ramp::predict_into` operation for
/// operation.
///
/// # Errors
/// [`EmbeddedError::NonFinite`] (index 2, the pressure) or [`EmbeddedError::BadModel`] for
/// inconsistent tables.
pub fn evaluate_ramp<F: Real>(
    ramp: &RampTables<'_, F>,
    p_bar: F,
    out: &mut [F; N_QUANTITIES],
) -> Result<(), EmbeddedError> {
    let p = p_bar.to_f64();
    if !p.is_finite() {
        return Err(EmbeddedError::NonFinite(2));
    }
    let n = ramp.pressures.len();
    if n < 2 || ramp.values.len() != n * N_QUANTITIES {
        return Err(EmbeddedError::BadModel);
    }
    let st = stencil(ramp.pressures, p);
    let mut q = 0;
    while q < N_QUANTITIES {
        let mut v = F::ZERO;
        let mut s = 0;
        while s < st.len {
            v = v + F::from_f64(st.w[s]) * ramp.values[(st.start + s) * N_QUANTITIES + q];
            s += 1;
        }
        out[q] = v;
        q += 1;
    }
    Ok(())
}
