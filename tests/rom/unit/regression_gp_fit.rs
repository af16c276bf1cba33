//! The unit tests of `src/rom/regression/gp/fit.rs`.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use surrogate::rom::regression::gp::{assemble, checked_bounds, fit, group_outputs, GpParams};
use surrogate::rom::regression::Data;
use surrogate::rom::regression::Regressor;

/// The sparse weights on every training point (`Z = X`) against the exact fit with the same
/// hyperparameters (fitted, one kernel and one per column): the means at random queries
/// within 10⁻⁸ relative (to the larger of the mean and the column's RMS, so that a mean
/// near zero does not divide), the process variances and the stored factor. The fitted
/// nugget is the smallest allowed (10⁻⁸) with long length scales: an ill-conditioned `R`,
/// the hard case of the least-squares solve.
#[test]
fn sparse_fit_on_every_point_is_the_exact_process() {
    let (n, d, m) = (40, 3, 2);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(17);
    let x: Vec<f64> = (0..n * d).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let y: Vec<f64> = (0..n)
        .flat_map(|i| {
            let p = &x[i * d..(i + 1) * d];
            [(1.5 * p[0]).sin() + p[1] * p[2], 3.0 * (p[0] - p[2]).exp()]
        })
        .collect();
    let data = Data {
        x: &x,
        y: &y,
        n,
        d,
        m,
        weights: &[],
    };
    let rms: Vec<f64> = (0..m)
        .map(|c| ((0..n).map(|i| y[i * m + c].powi(2)).sum::<f64>() / n as f64).sqrt())
        .collect();
    let every: Vec<usize> = (0..n).collect();
    for groups in [vec![], vec![0, 1, 2]] {
        let params = GpParams {
            groups,
            ..Default::default()
        };
        let exact = fit(&data, &params).unwrap();
        let bounds = checked_bounds(&data, &params).unwrap();
        let ys: Vec<Vec<f64>> = bounds
            .windows(2)
            .map(|w| group_outputs(&data, w[0]..w[1]))
            .collect();
        let sparse = assemble(&data, bounds, exact.theta.clone(), &ys, Some(&every)).unwrap();
        assert_eq!(sparse.chol, exact.chol);
        assert_eq!(sparse.xs, exact.xs);
        for (a, b) in sparse.sigma2.iter().zip(&exact.sigma2) {
            assert!((a - b).abs() <= 1e-8 * b.abs(), "σ² {a} vs {b}");
        }
        let mut scratch = vec![0.0; exact.scratch_len()];
        let (mut ps, mut pe) = (vec![0.0; m], vec![0.0; m]);
        let mut worst = 0.0f64;
        for _ in 0..50 {
            let q: Vec<f64> = (0..d).map(|_| rng.gen_range(-1.0..1.0)).collect();
            sparse.predict_into(&q, &mut ps, &mut scratch);
            exact.predict_into(&q, &mut pe, &mut scratch);
            for c in 0..m {
                worst = worst.max((ps[c] - pe[c]).abs() / pe[c].abs().max(rms[c]));
            }
        }
        assert!(worst <= 1e-8, "worst relative difference {worst:e}");
    }
}
