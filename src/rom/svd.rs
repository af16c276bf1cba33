//! The thin singular value decomposition `A = U Σ Vᵀ` (`A`: `m × n`, `U`: `m × k`, `V`:
//! `n × k`, `k = min(m, n)`, singular values non-increasing) by faer, computed sequentially
//! (`Par::Seq`) so that the factors do not depend on the number of threads.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::svd::{svd, svd_scratch, ComputeSvdVectors, SvdError};
use faer::{Mat, MatRef};

/// The factors of a thin SVD.
pub(crate) struct ThinSvd {
    /// Left singular vectors, `m × k`.
    pub u: Mat<f64>,
    /// Singular values, `k`, non-increasing.
    pub s: Vec<f64>,
    /// Right singular vectors, `n × k`.
    pub v: Mat<f64>,
}

/// The thin SVD of `a`.
///
/// # Errors
/// faer's [`SvdError`] when the iteration does not converge (a matrix with non-finite entries).
pub(crate) fn thin_svd(a: MatRef<'_, f64>) -> Result<ThinSvd, SvdError> {
    let (m, n) = (a.nrows(), a.ncols());
    let k = m.min(n);
    let mut u = Mat::<f64>::zeros(m, k);
    let mut v = Mat::<f64>::zeros(n, k);
    let mut s = faer::diag::Diag::<f64>::zeros(k);
    let (par, thin) = (faer::Par::Seq, ComputeSvdVectors::Thin);
    let mut mem = MemBuffer::new(svd_scratch::<f64>(
        m,
        n,
        thin,
        thin,
        par,
        Default::default(),
    ));
    svd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )?;
    let s = s.column_vector().iter().copied().collect();
    Ok(ThinSvd { u, s, v })
}
