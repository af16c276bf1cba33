//! Dense kernels of the regressors' fits: Cholesky factor, triangular solves, SPD inverse.

/// Lower Cholesky factor in place (row-major `n × n`; the upper part is left as is).
///
/// Written here rather than taken from faer so that retraining reproduces the shipped models
/// bit for bit (faer's factor is faster but rounds differently: `docs/rom_notes.md`).
///
/// # Errors
/// The index of the first non-positive pivot.
pub(crate) fn cholesky_in_place(a: &mut [f64], n: usize) -> Result<(), usize> {
    for i in 0..n {
        let (head, tail) = a.split_at_mut(i * n);
        let row_i = &mut tail[..n];
        for j in 0..i {
            let row_j = &head[j * n..j * n + j + 1];
            let s = row_i[j] - dot(&row_i[..j], &row_j[..j]);
            row_i[j] = s / row_j[j];
        }
        let d = row_i[i] - dot(&row_i[..i], &row_i[..i]);
        if d <= 0.0 || !d.is_finite() {
            return Err(i);
        }
        row_i[i] = d.sqrt();
    }
    Ok(())
}

/// Dot product with 4 independent accumulators (vectorisable, fixed summation order).
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let chunks = a.len() / 4;
    for c in 0..chunks {
        for l in 0..4 {
            acc[l] += a[4 * c + l] * b[4 * c + l];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for k in 4 * chunks..a.len() {
        s += a[k] * b[k];
    }
    s
}

/// Solves `L v = b` in place (row-major lower `L`, `n × n`).
pub(crate) fn solve_lower(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + i];
        let mut s = b[i];
        for (k, lv) in row.iter().enumerate() {
            s -= lv * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Solves `Lᵀ v = b` in place.
pub(crate) fn solve_lower_t(l: &[f64], n: usize, b: &mut [f64]) {
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in (i + 1)..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Inverse `(LLᵀ)⁻¹` (full symmetric, row-major) from the lower factor.
///
/// Row `c` of `V = L⁻ᵀ` solves `L v = e_c` (contiguous dots), then `A⁻¹_ij = V_i · V_j`.
pub(crate) fn spd_inverse(l: &[f64], n: usize) -> Vec<f64> {
    let mut v = vec![0.0; n * n];
    for c in 0..n {
        let row = &mut v[c * n..(c + 1) * n];
        row[c] = 1.0 / l[c * n + c];
        for i in (c + 1)..n {
            let s = dot(&l[i * n + c..i * n + i], &row[c..i]);
            row[i] = -s / l[i * n + i];
        }
    }
    let mut inv = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s = dot(&v[i * n + i..(i + 1) * n], &v[j * n + i..(j + 1) * n]);
            inv[i * n + j] = s;
            inv[j * n + i] = s;
        }
    }
    inv
}
