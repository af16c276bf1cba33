//! Generalised least squares against the diagnosing model's own error: with `Γ̃` its
//! covariance over the used cells (in the cells' σ), every vector and matrix of the Name stage
//! is multiplied by `L⁻¹`, `LLᵀ = I + Γ̃`.

use nalgebra::{DMatrix, DVector};

use crate::diagnose::approx_error::ErrorSpread;
use crate::diagnose::cells::Cell;
use crate::diagnose::DiagnoseError;

/// The lower Cholesky factor `L` of `I + D̃D̃ᵀ` over the used cells (`D̃` the spread's
/// deviations over each cell's σ), or none without a spread; `L⁻¹` whitens.
pub(crate) fn whitening(
    spread: Option<&ErrorSpread>,
    cells: &[Cell],
    rows: &[(&Cell, Vec<f64>)],
    row_cell: &[usize],
) -> Result<Option<DMatrix<f64>>, DiagnoseError> {
    let Some(spread) = spread else {
        return Ok(None);
    };
    if let Some(d) = spread.deviations.iter().find(|d| d.len() != cells.len()) {
        return Err(DiagnoseError::input(
            "error spread",
            format!("{} values per sample", d.len()),
            &format!("one value per cell of the table ({})", cells.len()),
        ));
    }
    let n = rows.len();
    let d = DMatrix::from_fn(n, spread.deviations.len(), |i, k| {
        spread.deviations[k][row_cell[i]] / rows[i].0.sigma
    });
    let gamma = DMatrix::identity(n, n) + &d * d.transpose();
    let chol = gamma.cholesky().ok_or_else(|| {
        DiagnoseError::input(
            "error spread",
            "not finite",
            "finite deviations (I + DDᵀ is then positive definite)",
        )
    })?;
    Ok(Some(chol.l()))
}

/// `L⁻¹` of [`whitening`], applied to a vector or to the columns of a matrix; the identity
/// without a spread.
pub(crate) struct Whitening(Option<DMatrix<f64>>);

impl Whitening {
    /// [`whitening`] over the used cells `rows` (`row_cell`: each one's index in `cells`).
    ///
    /// # Errors
    /// As [`whitening`].
    pub(crate) fn of(
        spread: Option<&ErrorSpread>,
        cells: &[Cell],
        rows: &[(&Cell, Vec<f64>)],
        row_cell: &[usize],
    ) -> Result<Self, DiagnoseError> {
        whitening(spread, cells, rows, row_cell).map(Whitening)
    }

    /// `L⁻¹ v`.
    pub(crate) fn vector(&self, v: DVector<f64>) -> DVector<f64> {
        match &self.0 {
            Some(l) => l
                .solve_lower_triangular(&v)
                .expect("a Cholesky factor of I + DDᵀ is regular"),
            None => v,
        }
    }

    /// `L⁻¹ M`.
    pub(crate) fn matrix(&self, m: DMatrix<f64>) -> DMatrix<f64> {
        match &self.0 {
            Some(l) => l
                .solve_lower_triangular(&m)
                .expect("a Cholesky factor of I + DDᵀ is regular"),
            None => m,
        }
    }
}
