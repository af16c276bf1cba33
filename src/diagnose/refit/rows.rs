//! The used cells of a refit and their linearised effect columns.

use crate::calibrate::baseline::SweepSensitivities;
use crate::calibrate::objective::ObservationSet;
use crate::diagnose::cells::Cell;
use crate::diagnose::signature::{derivative_of, sensitivity_step};
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;
use crate::fe::sensitivity::Parameter;

/// The used cells and their linearised effect columns.
// public for the tests in tests/diagnose/
#[doc(hidden)]
#[derive(Clone, Debug)]
pub struct Rows {
    /// The sweep's value of each effect ([`SweepSensitivities::base`]): the effect sizes `θ`
    /// of the fit are measured from it, `[k]`.
    pub base: Vec<f64>,
    pub cells: Vec<Cell>,
    /// `∂yᵢ/∂θₖ` (unit of the output per unit of the effect), `[i][k]`.
    pub d: Vec<Vec<f64>>,
    /// FE correction `cᵢ` (unit of the output).
    pub offset: Vec<f64>,
}

impl Rows {
    /// The cells of `cells` that `sens` covers, with their effect columns.
    pub(crate) fn of(
        cells: &[Cell],
        sens: &SweepSensitivities,
        effects: &[Effect],
    ) -> Result<Self, DiagnoseError> {
        let mut out = Rows {
            base: effects.iter().map(|&e| sens.base(e)).collect(),
            cells: Vec::new(),
            d: Vec::new(),
            offset: Vec::new(),
        };
        for c in cells {
            let Some((s, step)) = sensitivity_step(sens, c) else {
                continue;
            };
            let mut row = Vec::with_capacity(effects.len());
            for e in effects {
                let Some(j) = s
                    .parameters
                    .iter()
                    .position(|p| p.parameter == Parameter::Effect(*e))
                else {
                    return Err(DiagnoseError::input(
                        "sensitivities",
                        format!("without {}", e.name()),
                        "a sweep with the sensitivities of every refitted effect",
                    ));
                };
                match derivative_of(&s.steps[step].derivatives[j], c.output) {
                    Some(v) => row.push(v),
                    None => break,
                }
            }
            if row.len() == effects.len() {
                out.cells.push(c.clone());
                out.d.push(row);
                out.offset.push(0.0);
            }
        }
        Ok(out)
    }

    pub(crate) fn subset(&self, keep: impl Fn(&Cell) -> bool) -> Rows {
        let idx: Vec<usize> = (0..self.cells.len())
            .filter(|&i| keep(&self.cells[i]))
            .collect();
        Rows {
            base: self.base.clone(),
            cells: idx.iter().map(|&i| self.cells[i].clone()).collect(),
            d: idx.iter().map(|&i| self.d[i].clone()).collect(),
            offset: idx.iter().map(|&i| self.offset[i]).collect(),
        }
    }

    /// The value of effect `k` at size `theta` from the sweep's.
    pub(crate) fn value(&self, k: usize, theta: f64) -> f64 {
        self.base[k] + theta
    }

    pub(crate) fn observations(&self) -> ObservationSet {
        crate::diagnose::cells::observations(&self.cells)
    }
}
