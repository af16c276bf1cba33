//! The model-form error: how far the calibrated model misses the recorded actuators.
//!
//! The surrogate's own standard deviation (`surrogate predict --std`) is its error against
//! the FE model it was trained on. The FE model itself misses real actuators: after its
//! material is calibrated on recordings, the residuals (predicted − recorded) that remain are
//! the model's *form* error, which no material removes. `surrogate model-form` learns it from
//! a calibration report and stores it in the model file; `surrogate export` writes it beside
//! the exported tables as `pub static MODEL_FORM: Option<ModelFormTables>`.
//!
//! Per output `o` (tip Uz, tip Uy, angle, force: the outputs the calibration recorded), the
//! table holds one value per recorded pressure level `P_j`,
//! `e_o(P_j) = max(rms_o, rms_o(P_j))`: the root mean square residual of the level, never below
//! the output's rms residual over all levels. Between levels `e_o` is linear in `P`; outside the
//! recorded levels it is held at the nearer end ([`model_form_at`]). It is an rms (mean bias
//! included), in the output's unit, to be read beside — not instead of — the surrogate's std.
//!
//! ```
//! use surrogate_predict::{ModelFormTables, ANGLE, FORCE, TIP_UZ};
//!
//! static PRESSURES: [f64; 2] = [1.0, 3.0];
//! static OUTPUTS: [u8; 1] = [ANGLE as u8];
//! static VALUES: [f64; 2] = [8.0, 12.0]; // degrees at 1 and 3 bar
//! static MODEL_FORM: ModelFormTables<'static> =
//!     ModelFormTables { pressures: &PRESSURES, outputs: &OUTPUTS, values: &VALUES };
//!
//! assert_eq!(MODEL_FORM.error(ANGLE, 2.0), Some(10.0));
//! assert_eq!(MODEL_FORM.error(ANGLE, 0.5), Some(8.0)); // held below the lowest level
//! assert_eq!(MODEL_FORM.error(FORCE, 2.0), None); // not recorded: nothing learned
//! assert_eq!(MODEL_FORM.error(TIP_UZ, f64::NAN), None);
//! ```

/// The model-form error of an exported model ([module docs](self)).
#[derive(Debug, Clone, Copy)]
pub struct ModelFormTables<'a> {
    /// Recorded pressure levels, bar, increasing (at least one).
    pub pressures: &'a [f64],
    /// The outputs with a model-form error (indices among the 22: [`crate::TIP_UZ`] …).
    pub outputs: &'a [u8],
    /// Output-major: `values[i * pressures.len() + j]` is the error of `outputs[i]` at level
    /// `j`, in the output's unit.
    pub values: &'a [f64],
}

impl ModelFormTables<'_> {
    /// The model-form error of output `output` (an index among the 22) at `p_bar`: `None`
    /// when the calibration recorded no such output, for a non-finite pressure, or for
    /// inconsistent tables.
    pub fn error(&self, output: usize, p_bar: f64) -> Option<f64> {
        let levels = self.pressures.len();
        if levels == 0 || self.values.len() != self.outputs.len() * levels {
            return None;
        }
        let i = self
            .outputs
            .iter()
            .position(|&o| usize::from(o) == output)?;
        model_form_at(
            self.pressures,
            &self.values[i * levels..(i + 1) * levels],
            p_bar,
        )
    }
}

/// Piecewise-linear interpolation of one output's model-form error `at_levels` over the
/// recorded `pressures` (increasing), held at the nearer end outside them: the one rule of
/// the library and of exported models. `None` for a non-finite pressure or tables of
/// unequal or zero length.
pub fn model_form_at(pressures: &[f64], at_levels: &[f64], p_bar: f64) -> Option<f64> {
    let n = pressures.len();
    if n == 0 || at_levels.len() != n || !p_bar.is_finite() {
        return None;
    }
    if p_bar <= pressures[0] {
        return Some(at_levels[0]);
    }
    let mut j = 1;
    while j < n {
        if p_bar <= pressures[j] {
            let w = (p_bar - pressures[j - 1]) / (pressures[j] - pressures[j - 1]);
            return Some(at_levels[j - 1] + w * (at_levels[j] - at_levels[j - 1]));
        }
        j += 1;
    }
    Some(at_levels[n - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_between_levels_and_holds_the_ends() {
        let p = [1.0, 2.0, 3.0];
        let v = [4.0, 8.0, 10.0];
        assert_eq!(model_form_at(&p, &v, 1.0), Some(4.0));
        assert_eq!(model_form_at(&p, &v, 1.5), Some(6.0));
        assert_eq!(model_form_at(&p, &v, 2.5), Some(9.0));
        assert_eq!(model_form_at(&p, &v, 0.0), Some(4.0));
        assert_eq!(model_form_at(&p, &v, 3.5), Some(10.0));
        assert_eq!(model_form_at(&p, &v, f64::INFINITY), None);
        assert_eq!(model_form_at(&p, &v[..2], 2.0), None);
        assert_eq!(model_form_at(&[2.0], &[5.0], 0.3), Some(5.0));
    }

    #[test]
    fn tables_find_their_outputs_and_refuse_inconsistent_sizes() {
        let t = ModelFormTables {
            pressures: &[1.0, 3.0],
            outputs: &[crate::TIP_UZ as u8, crate::FORCE as u8],
            values: &[2.0, 4.0, 0.5, 0.7],
        };
        assert_eq!(t.error(crate::TIP_UZ, 2.0), Some(3.0));
        assert_eq!(t.error(crate::FORCE, 3.0), Some(0.7));
        assert_eq!(t.error(crate::ANGLE, 2.0), None);
        let bad = ModelFormTables {
            values: &[2.0, 4.0, 0.5],
            ..t
        };
        assert_eq!(bad.error(crate::TIP_UZ, 2.0), None);
    }
}
