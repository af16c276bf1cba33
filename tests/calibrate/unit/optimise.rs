//! The unit tests of `src/calibrate/optimise.rs`.

use surrogate::calibrate::optimise::*;

#[test]
fn free_system_solves_the_free_block() {
    let a = [
        [4.0, 1.0, 0.0, 0.5],
        [1.0, 3.0, 0.2, 0.0],
        [0.0, 0.2, 2.0, 0.1],
        [0.5, 0.0, 0.1, 5.0],
    ];
    let b = [1.0, 2.0, 3.0, 4.0];
    let x = solve_free(&a, &b, &[true; 4]).unwrap();
    for i in 0..4 {
        let r: f64 = (0..4).map(|j| a[i][j] * x[j]).sum();
        assert!((r - b[i]).abs() < 1e-12);
    }
    let x = solve_free(&a, &b, &[true, false, true, false]).unwrap();
    assert_eq!((x[1], x[3]), (0.0, 0.0));
    assert!((4.0 * x[0] - 1.0).abs() < 1e-12 && (2.0 * x[2] - 3.0).abs() < 1e-12);
}

#[test]
fn minima_are_grouped() {
    let f = |u: [f64; 4], c: f64| LocalFit {
        start: u,
        u,
        chi2: c,
        iterations: 1,
        stop: Stop::Gradient,
        active: [None; 4],
        minimum: 9,
    };
    let mut fits = vec![
        f([0.5; 4], 1.0),
        f([0.5 + 1e-5, 0.5, 0.5, 0.5], 1.0 + 1e-9),
        f([0.1; 4], 2.0),
    ];
    group_minima(&mut fits);
    assert_eq!(
        fits.iter().map(|f| f.minimum).collect::<Vec<_>>(),
        vec![0, 0, 1]
    );
}
