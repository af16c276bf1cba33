//! The residual past the material: with `S_m` the material's four columns (whitened) and `Q`
//! an orthonormal basis of their span, `P⊥ = I − QQᵀ` takes out what a material re-fit on
//! every used cell absorbs; `r = P⊥ z` is the residual after that re-fit.

use nalgebra::{DMatrix, DVector};

use super::table::UsedCells;
use super::whiten::Whitening;
use crate::diagnose::discrimination::orthonormal;

/// The material re-fit on every used cell, linearised or nonlinear.
pub(crate) struct PastMaterial {
    /// The whitened standardised residual `z` of the used cells at the calibrated set.
    pub(crate) z: DVector<f64>,
    /// `Q`: an orthonormal basis of the material's whitened directions.
    q: DMatrix<f64>,
    /// `r`: the residual after the material re-fit.
    pub(crate) residual: DVector<f64>,
    /// `χ² = zᵀz`.
    pub(crate) chi2: f64,
    /// `χ² = rᵀr` after the material re-fit.
    pub(crate) chi2_material: f64,
}

impl PastMaterial {
    /// The re-fit on `used`: linearised with the sweep's material columns `material`, or, with
    /// `refitted`, the residual and the directions of the nonlinear re-fit.
    pub(crate) fn fit(
        used: &UsedCells<'_>,
        material: &[usize],
        refitted: bool,
        whiten: &Whitening,
    ) -> Self {
        let n = used.len();
        let z = whiten.vector(DVector::from_iterator(
            n,
            used.rows.iter().map(|(c, _)| c.standardised),
        ));
        let (sm, z_fit) = if refitted {
            (
                DMatrix::from_fn(n, 4, |i, k| used.refitted[i].1[k]),
                whiten.vector(DVector::from_iterator(n, used.refitted.iter().map(|v| v.0))),
            )
        } else {
            (
                DMatrix::from_columns(
                    &material.iter().map(|&j| used.column(j)).collect::<Vec<_>>(),
                ),
                z.clone(),
            )
        };
        let q = orthonormal(&whiten.matrix(sm));
        let residual = past(&q, &z_fit);
        PastMaterial {
            chi2: z.norm_squared(),
            chi2_material: residual.norm_squared(),
            z,
            q,
            residual,
        }
    }

    /// `P⊥ v`: `v` past the material's directions.
    pub(crate) fn project(&self, v: &DVector<f64>) -> DVector<f64> {
        past(&self.q, v)
    }

    /// Degrees of freedom of a one-effect fit: `n − 5`.
    pub(crate) fn dof(&self) -> f64 {
        self.z.len() as f64 - 5.0
    }

    /// The scale of the material-only fit, `ŝ² = χ²_material / (n − 4)`.
    pub(crate) fn scale0(&self) -> f64 {
        self.chi2_material / (self.z.len() as f64 - 4.0)
    }
}

/// `v − QQᵀv`.
fn past(q: &DMatrix<f64>, v: &DVector<f64>) -> DVector<f64> {
    v - q * (q.transpose() * v)
}
