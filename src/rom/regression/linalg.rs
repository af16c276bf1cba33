//! Dense kernels of the regressors' fits: Cholesky factor, triangular solves, SPD inverse.

/// Lower Cholesky factor in place (row-major `n × n`; the upper part is left as is).
///
/// Written here rather than taken from faer so that retraining reproduces the shipped models
/// bit for bit (faer's factor is faster but rounds differently: `docs/rom_notes.md`).
///
/// # Errors
/// The index of the first non-positive pivot.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> Result<(), usize> {
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
// public for the tests in tests/rom/
#[doc(hidden)]
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
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
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn solve_lower(l: &[f64], n: usize, b: &mut [f64]) {
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
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn solve_lower_t(l: &[f64], n: usize, b: &mut [f64]) {
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in (i + 1)..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Solves `L X = B` in place for the `m` columns of the row-major `n × m` matrix `b`.
///
/// Each column goes through the operations of [`solve_lower`] in the same order, so the result
/// is bit for bit that of `m` single solves; a row of `L` is read once for all columns.
/// `s` is scratch of length `m`.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn solve_lower_multi(l: &[f64], n: usize, b: &mut [f64], m: usize, s: &mut [f64]) {
    for i in 0..n {
        let (done, rest) = b.split_at_mut(i * m);
        s.copy_from_slice(&rest[..m]);
        for (k, lv) in l[i * n..i * n + i].iter().enumerate() {
            for (sc, bk) in s.iter_mut().zip(&done[k * m..(k + 1) * m]) {
                *sc -= lv * bk;
            }
        }
        let d = l[i * n + i];
        for (bi, sc) in rest[..m].iter_mut().zip(s.iter()) {
            *bi = sc / d;
        }
    }
}

/// Solves `Lᵀ X = B` in place for the `m` columns of `b`, each column bit for bit as
/// [`solve_lower_t`] solves it. `s` is scratch of length `m`.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn solve_lower_t_multi(l: &[f64], n: usize, b: &mut [f64], m: usize, s: &mut [f64]) {
    for i in (0..n).rev() {
        let (head, done) = b.split_at_mut((i + 1) * m);
        s.copy_from_slice(&head[i * m..]);
        for k in (i + 1)..n {
            let lv = l[k * n + i];
            let bk = &done[(k - i - 1) * m..(k - i) * m];
            for (sc, bkc) in s.iter_mut().zip(bk) {
                *sc -= lv * bkc;
            }
        }
        let d = l[i * n + i];
        for (bi, sc) in head[i * m..].iter_mut().zip(s.iter()) {
            *bi = sc / d;
        }
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

/// Least squares `min_X ‖A X − B‖²` by Householder QR, for `A` of full column rank.
///
/// `a` is column-major `rows × cols` (`rows ≥ cols`) and is overwritten by the reflections
/// (its upper triangle by `R`); `b` is column-major `rows × nrhs` and is overwritten by `QᵀB`
/// with its first `cols` rows then back-substituted: on return, rows `0..cols` of each column
/// hold the solution `x_c` and rows `cols..rows` the part of `Qᵀb_c` that `A` cannot reach,
/// whose squared norm is the residual `‖A x_c − b_c‖²`. Orthogonal transforms only: the error
/// grows with the condition number of `A`, not with its square as in the normal equations.
/// Hand-written, like [`cholesky_in_place`], so that a refit reproduces a model bit for bit.
///
/// # Errors
/// The index of the first column whose diagonal of `R` is zero or not finite (rank-deficient
/// or non-finite `A`).
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn householder_least_squares(
    a: &mut [f64],
    rows: usize,
    cols: usize,
    b: &mut [f64],
    nrhs: usize,
) -> Result<(), usize> {
    let mut v = vec![0.0; rows];
    for k in 0..cols {
        let col = &a[k * rows + k..(k + 1) * rows];
        let norm = dot(col, col).sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(k);
        }
        // reflector `H = I − 2vvᵀ/vᵀv` with `Hx = r_kk e_1`, `r_kk = −sign(x_0)‖x‖`
        let r_kk = if col[0] >= 0.0 { -norm } else { norm };
        let v = &mut v[..rows - k];
        v.copy_from_slice(col);
        v[0] -= r_kk;
        let vv = dot(v, v);
        let reflect = |y: &mut [f64]| {
            let w = 2.0 * dot(v, y) / vv;
            for (yi, vi) in y.iter_mut().zip(v.iter()) {
                *yi -= w * vi;
            }
        };
        for j in k + 1..cols {
            reflect(&mut a[j * rows + k..(j + 1) * rows]);
        }
        for c in 0..nrhs {
            reflect(&mut b[c * rows + k..(c + 1) * rows]);
        }
        a[k * rows + k] = r_kk;
    }
    for c in 0..nrhs {
        let x = &mut b[c * rows..c * rows + cols];
        for i in (0..cols).rev() {
            let mut s = x[i];
            for j in i + 1..cols {
                s -= a[j * rows + i] * x[j];
            }
            x[i] = s / a[i * rows + i];
        }
    }
    Ok(())
}
