//! The unit tests of `src/rom/regression/linalg.rs`.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use surrogate::rom::regression::linalg::*;

/// The multi-column solves give each column's single solve bit for bit.
#[test]
fn multi_column_solves_are_the_single_solves_bit_for_bit() {
    let (n, m) = (23, 5);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let mut a: Vec<f64> = (0..n * n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    // A Aᵀ + n I: symmetric positive definite
    let mut spd = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            spd[i * n + j] = (0..n).map(|k| a[i * n + k] * a[j * n + k]).sum::<f64>();
        }
        spd[i * n + i] += n as f64;
    }
    a.copy_from_slice(&spd);
    cholesky_in_place(&mut a, n).unwrap();
    let b: Vec<f64> = (0..n * m).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let mut s = vec![0.0; m];
    let (mut fwd, mut both) = (b.clone(), b.clone());
    solve_lower_multi(&a, n, &mut fwd, m, &mut s);
    solve_lower_multi(&a, n, &mut both, m, &mut s);
    solve_lower_t_multi(&a, n, &mut both, m, &mut s);
    for c in 0..m {
        let mut col: Vec<f64> = (0..n).map(|i| b[i * m + c]).collect();
        solve_lower(&a, n, &mut col);
        assert!((0..n).all(|i| fwd[i * m + c].to_bits() == col[i].to_bits()));
        solve_lower_t(&a, n, &mut col);
        assert!((0..n).all(|i| both[i * m + c].to_bits() == col[i].to_bits()));
    }
}

/// The QR least squares against the normal equations on a small well-conditioned
/// problem, and its residual against `‖Ax − b‖²` computed directly.
#[test]
fn householder_least_squares_solves_the_normal_equations() {
    let (rows, cols, nrhs) = (7, 3, 2);
    let a: Vec<f64> = (0..rows * cols)
        .map(|e| ((e * 37 % 11) as f64 - 5.0) / 3.0 + if e % 8 == 0 { 2.0 } else { 0.0 })
        .collect();
    let b: Vec<f64> = (0..rows * nrhs)
        .map(|e| ((e * 13 % 7) as f64 - 3.0) / 2.0)
        .collect();
    let (mut qa, mut qb) = (a.clone(), b.clone());
    householder_least_squares(&mut qa, rows, cols, &mut qb, nrhs).unwrap();
    // normal equations AᵀA x = Aᵀb by Cholesky (row-major)
    let at = |i: usize, j: usize| a[j * rows + i];
    let mut ata = vec![0.0; cols * cols];
    for i in 0..cols {
        for j in 0..cols {
            ata[i * cols + j] = (0..rows).map(|r| at(r, i) * at(r, j)).sum();
        }
    }
    cholesky_in_place(&mut ata, cols).unwrap();
    for c in 0..nrhs {
        let bc = &b[c * rows..(c + 1) * rows];
        let mut x: Vec<f64> = (0..cols)
            .map(|i| (0..rows).map(|r| at(r, i) * bc[r]).sum())
            .collect();
        solve_lower(&ata, cols, &mut x);
        solve_lower_t(&ata, cols, &mut x);
        let xq = &qb[c * rows..c * rows + cols];
        for (u, w) in x.iter().zip(xq) {
            assert!((u - w).abs() < 1e-12 * (1.0 + u.abs()), "{u} vs {w}");
        }
        let resid: f64 = (0..rows)
            .map(|r| {
                let e = (0..cols).map(|i| at(r, i) * xq[i]).sum::<f64>() - bc[r];
                e * e
            })
            .sum();
        let tail = &qb[c * rows + cols..(c + 1) * rows];
        assert!((resid - dot(tail, tail)).abs() < 1e-12 * (1.0 + resid));
    }
}

#[test]
fn householder_least_squares_reports_a_rank_deficient_column() {
    // the second column is zero
    let mut a = vec![1.0, 2.0, 3.0, 0.0, 0.0, 0.0];
    let mut b = vec![1.0, 1.0, 1.0];
    assert_eq!(householder_least_squares(&mut a, 3, 2, &mut b, 1), Err(1));
}
