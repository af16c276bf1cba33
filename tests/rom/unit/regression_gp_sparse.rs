//! The unit tests of `src/rom/regression/gp/sparse.rs`.

use surrogate::rom::regression::gp::select_inducing;

/// Inputs on a line, one length scale: the pivoted Cholesky starts at the first point
/// (all residuals equal, lowest index), then takes the point farthest from it.
#[test]
fn pivoted_cholesky_takes_the_first_point_then_the_farthest() {
    let x = [0.0, 0.1, 0.2, 0.5, 1.0];
    let theta = [(0.3f64).ln(), (1e-6f64).ln()];
    assert_eq!(select_inducing(&x, 5, 1, &theta, 2).unwrap(), vec![0, 4]);
    // the third point fills the largest gap
    assert_eq!(select_inducing(&x, 5, 1, &theta, 3).unwrap(), vec![0, 3, 4]);
}

/// With two groups the residuals are summed: group `a` sees only the first input, group
/// `b` only the second; alone each takes the point far along its own input, together they
/// take the point far along both.
#[test]
fn inducing_points_sum_the_groups_residuals() {
    let x = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.8, 0.8];
    let nugget = (1e-6f64).ln();
    let a = [(0.3f64).ln(), (100.0f64).ln(), nugget];
    let b = [(100.0f64).ln(), (0.3f64).ln(), nugget];
    assert_eq!(select_inducing(&x, 4, 2, &a, 2).unwrap(), vec![0, 1]);
    assert_eq!(select_inducing(&x, 4, 2, &b, 2).unwrap(), vec![0, 2]);
    let ab: Vec<f64> = a.iter().chain(&b).copied().collect();
    assert_eq!(select_inducing(&x, 4, 2, &ab, 2).unwrap(), vec![0, 3]);
}
