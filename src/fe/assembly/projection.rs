//! Projection of a symmetric element matrix onto the positive semi-definite cone:
//! `K⁺ = V max(Λ, 0) Vᵀ` from the eigen-decomposition `K = V Λ Vᵀ`, the nearest PSD matrix
//! in the Frobenius norm. Summed over the elements, the projected tangent is positive
//! semi-definite, so a Newton direction computed with it descends on the total potential
//! (the minimisation solver's fallback when the exact tangent is not positive definite).
//!
//! A Cholesky test of `K + τ I` (τ = 1e-10 · max |K_ii|) first: an element that passes is
//! (up to τ) already PSD and is left as it is; the others are decomposed by nalgebra's
//! symmetric eigen-solver (Householder tridiagonalisation and implicit QR, deterministic, on
//! the stack: no allocation). What it costs against the alternative it replaced:
//! `docs/SOLVER_MEASUREMENTS.md`.

// Index loops mirror the matrix notation (i, j: rows and columns; p, q: the rotated pair).
#![allow(clippy::needless_range_loop)]

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, DimDiff, DimSub, SMatrix, U1};

/// Projects the symmetric `N × N` row-major matrix `k` (its lower triangle is read) onto the
/// PSD cone in place; returns whether it changed. `N ≤ 81`.
pub fn project_psd<const N: usize>(k: &mut [f64]) -> bool
where
    Const<N>: DimSub<U1>,
    DefaultAllocator: Allocator<Const<N>, DimDiff<Const<N>, U1>> + Allocator<DimDiff<Const<N>, U1>>,
{
    debug_assert!(k.len() == N * N);
    let mut a = [[0.0f64; N]; N];
    let mut dmax = 0.0f64;
    for i in 0..N {
        for j in 0..=i {
            a[i][j] = k[i * N + j];
            a[j][i] = k[i * N + j];
        }
        dmax = dmax.max(a[i][i].abs());
    }
    if dmax == 0.0 || is_psd(&a, 1e-10 * dmax) {
        return false;
    }
    // Householder tridiagonalisation and implicit symmetric QR (nalgebra, on the stack)
    let m = SMatrix::<f64, N, N>::from_fn(|i, j| a[i][j]);
    let eig = m.symmetric_eigen();
    // K⁺ = Σ_m max(λ_m, 0) v_m v_mᵀ
    for i in 0..N {
        for j in 0..=i {
            let mut s = 0.0;
            for (mm, &l) in eig.eigenvalues.iter().enumerate() {
                if l > 0.0 {
                    s += l * eig.eigenvectors[(i, mm)] * eig.eigenvectors[(j, mm)];
                }
            }
            k[i * N + j] = s;
            k[j * N + i] = s;
        }
    }
    true
}

/// Whether `a + τ I` has a Cholesky factor (dense, on a copy).
fn is_psd<const N: usize>(a: &[[f64; N]; N], tau: f64) -> bool {
    let mut l = *a;
    for j in 0..N {
        let mut d = l[j][j] + tau;
        for m in 0..j {
            d -= l[j][m] * l[j][m];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        l[j][j] = d;
        for i in j + 1..N {
            let mut s = l[i][j];
            for m in 0..j {
                s -= l[i][m] * l[j][m];
            }
            l[i][j] = s / d;
        }
    }
    true
}
