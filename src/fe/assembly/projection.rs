//! Projection of a symmetric element matrix onto the positive semi-definite cone:
//! `K⁺ = V max(Λ, 0) Vᵀ` from the eigen-decomposition `K = V Λ Vᵀ`, the nearest PSD matrix
//! in the Frobenius norm. Summed over the elements, the projected tangent is positive
//! semi-definite, so a Newton direction computed with it descends on the total potential
//! (the minimisation solver's fallback when the exact tangent is not positive definite).
//!
//! A Cholesky test of `K + τ I` (τ = 1e-10 · max |K_ii|) first: an element that passes is
//! (up to τ) already PSD and is left as it is; the others get cyclic Jacobi rotations
//! (deterministic, in place, no allocation), to a relative off-diagonal size of 1e-14.

// Index loops mirror the matrix notation (i, j: rows and columns; p, q: the rotated pair).
#![allow(clippy::needless_range_loop)]

/// Projects the symmetric `N × N` row-major matrix `k` (its lower triangle is read) onto the
/// PSD cone in place; returns whether it changed. `N ≤ 81`.
pub fn project_psd<const N: usize>(k: &mut [f64]) -> bool {
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
    let mut v = [[0.0f64; N]; N];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    jacobi(&mut a, &mut v);
    // K⁺ = Σ_m max(λ_m, 0) v_m v_mᵀ
    for i in 0..N {
        for j in 0..=i {
            let mut s = 0.0;
            for m in 0..N {
                let l = a[m][m];
                if l > 0.0 {
                    s += l * v[i][m] * v[j][m];
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

/// Cyclic Jacobi: `a ← Vᵀ a V` diagonal (the eigenvalues), `v ← v V` (the eigenvectors in
/// its columns).
fn jacobi<const N: usize>(a: &mut [[f64; N]; N], v: &mut [[f64; N]; N]) {
    let frob: f64 = a.iter().flatten().map(|x| x * x).sum();
    for _sweep in 0..60 {
        let mut off = 0.0;
        for p in 0..N {
            for q in p + 1..N {
                off += a[p][q] * a[p][q];
            }
        }
        if off <= 1e-28 * frob {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                let apq = a[p][q];
                if apq.abs() <= 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (rp, rq) = (a[p], a[q]);
                for m in 0..N {
                    a[p][m] = c * rp[m] - s * rq[m];
                    a[q][m] = s * rp[m] + c * rq[m];
                }
                for row in v.iter_mut() {
                    let (vkp, vkq) = (row[p], row[q]);
                    row[p] = c * vkp - s * vkq;
                    row[q] = s * vkp + c * vkq;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_keeps_psd_matrices_and_clips_negative_eigenvalues() {
        const N: usize = 6;
        // K = Q diag(λ) Qᵀ with a known rotation Q (Householder of a fixed vector)
        let w: [f64; N] = [0.3, -0.5, 0.2, 0.7, -0.1, 0.4];
        let ww: f64 = w.iter().map(|x| x * x).sum();
        let q = |i: usize, j: usize| f64::from(u8::from(i == j)) - 2.0 * w[i] * w[j] / ww;
        let build = |lam: &[f64; N]| {
            let mut k = vec![0.0; N * N];
            for i in 0..N {
                for j in 0..N {
                    k[i * N + j] = (0..N).map(|m| lam[m] * q(i, m) * q(j, m)).sum();
                }
            }
            k
        };
        let psd = [3.0, 1.0, 0.5, 0.0, 2.0, 4.0];
        let mut k = build(&psd);
        let before = k.clone();
        assert!(!project_psd::<N>(&mut k));
        assert_eq!(k, before);
        let mut k = build(&[3.0, -1.0, 0.5, -2.0, 2.0, 4.0]);
        assert!(project_psd::<N>(&mut k));
        let want = build(&[3.0, 0.0, 0.5, 0.0, 2.0, 4.0]);
        for (a, b) in k.iter().zip(&want) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
    }
}
