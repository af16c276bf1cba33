//! The cells the Name stage uses: those of the residual table the sweep has sensitivities
//! for, each with its derivatives by every parameter of the sweep in its own σ,
//! `S_ij = (∂ŷᵢ/∂θⱼ) / σᵢ`.

use nalgebra::DVector;

use crate::calibrate::baseline::SweepSensitivities;
use crate::diagnose::cells::Cell;
use crate::diagnose::signature::{cell_spike, derivative_of, sensitivity_step, LocalMaterial};
use crate::diagnose::sweep::{COMPUTE_MISSING, MIN_NAME_CELLS};
use crate::diagnose::DiagnoseError;

/// Every parameter's derivative of `c`'s output in the sweep, σ-scaled.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn derivs_of(sens: &SweepSensitivities, c: &Cell) -> Option<Vec<f64>> {
    sensitivity_step(sens, c).and_then(|(se, i)| {
        se.steps[i]
            .derivatives
            .iter()
            .map(|d| derivative_of(d, c.output).map(|v| v / c.sigma))
            .collect::<Option<Vec<f64>>>()
    })
}

/// The used cells: rows of the signature matrix, one per cell with sensitivities.
pub(crate) struct UsedCells<'a> {
    /// Each used cell, with its σ-scaled derivatives by every parameter of the sweep.
    pub(crate) rows: Vec<(&'a Cell, Vec<f64>)>,
    /// Each used cell's index in the residual table.
    pub(crate) row_cell: Vec<usize>,
    /// Used cells whose FE derivatives spike, in words.
    pub(crate) spikes: Vec<String>,
    /// With a nonlinear material re-fit: each used cell's residual after it and the
    /// material's four directions there.
    pub(crate) refitted: Vec<(f64, [f64; 4])>,
    /// Cells without sensitivities, in words.
    pub(crate) unmatched: Vec<String>,
}

impl<'a> UsedCells<'a> {
    /// The cells of `cells` with sensitivities in `sens` (and, with `local`, a re-fitted
    /// residual).
    ///
    /// # Errors
    /// [`DiagnoseError::Input`] with fewer than [`MIN_NAME_CELLS`] of them.
    pub(crate) fn of(
        cells: &'a [Cell],
        sens: &SweepSensitivities,
        local: Option<&LocalMaterial>,
    ) -> Result<Self, DiagnoseError> {
        // rows: cells with sensitivities; columns: every parameter (σ-scaled)
        let mut rows: Vec<(&Cell, Vec<f64>)> = Vec::new();
        let mut row_cell: Vec<usize> = Vec::new();
        let mut spikes: Vec<String> = Vec::new();
        let mut refitted: Vec<(f64, [f64; 4])> = Vec::new();
        let mut unmatched = Vec::new();
        for (ci, c) in cells.iter().enumerate() {
            let derivs = match local {
                Some(l) => match l.get(ci).copied().flatten() {
                    Some(v) => {
                        refitted.push(v);
                        derivs_of(sens, c)
                    }
                    None => None,
                },
                None => derivs_of(sens, c),
            };
            match derivs {
                Some(d) => {
                    if let Some((p, ratio)) = cell_spike(sens, c) {
                        spikes.push(format!(
                            "N = {}, T = {} mm, {} bar, {}: its FE derivative by {p} is {ratio:.0} \
                             times its largest at the ramp's other pressures",
                            c.n_bellows,
                            c.wall_thickness_mm,
                            c.pressure_bar,
                            c.output.name()
                        ));
                    }
                    rows.push((c, d));
                    row_cell.push(ci);
                }
                None => {
                    if local.is_some() && refitted.len() > rows.len() {
                        refitted.pop();
                    }
                    unmatched.push(format!(
                        "N = {}, T = {} mm, {} bar, {}",
                        c.n_bellows,
                        c.wall_thickness_mm,
                        c.pressure_bar,
                        c.output.name(),
                    ))
                }
            }
        }
        let n = rows.len();
        if n < MIN_NAME_CELLS {
            return Err(DiagnoseError::input(
                "cells with sensitivities",
                n,
                &format!(
                    "at least {MIN_NAME_CELLS} (the sweep must cover the recorded designs and \
                     pressures: {})",
                    COMPUTE_MISSING
                ),
            ));
        }
        Ok(UsedCells {
            rows,
            row_cell,
            spikes,
            refitted,
            unmatched,
        })
    }

    /// The number of used cells.
    pub(crate) fn len(&self) -> usize {
        self.rows.len()
    }

    /// Column `j` of the signature matrix: every used cell's derivative by parameter `j`.
    pub(crate) fn column(&self, j: usize) -> DVector<f64> {
        DVector::from_iterator(self.len(), self.rows.iter().map(|(_, d)| d[j]))
    }
}
