//! The unit tests of `src/rom/regression/gp/likelihood.rs`.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::rom::regression::gp::likelihood::*;
use surrogate::rom::regression::Data;

#[test]
fn likelihood_gradient_matches_finite_differences() {
    let n = 12;
    let d = 2;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let x: Vec<f64> = (0..n * d).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let y: Vec<f64> = (0..n)
        .flat_map(|i| {
            [
                (2.0 * x[2 * i]).sin() + x[2 * i + 1],
                x[2 * i] * x[2 * i + 1],
            ]
        })
        .collect();
    let data = Data {
        x: &x,
        y: &y,
        n,
        d,
        m: 2,
        weights: &[],
    };
    let theta = vec![-0.3, 0.2, -6.0];
    let e = neg_log_likelihood(&data, &y, &theta).unwrap();
    for k in 0..3 {
        let h = 1e-5;
        let mut tp = theta.clone();
        tp[k] += h;
        let mut tm = theta.clone();
        tm[k] -= h;
        let fd = (neg_log_likelihood(&data, &y, &tp).unwrap().nll()
            - neg_log_likelihood(&data, &y, &tm).unwrap().nll())
            / (2.0 * h);
        assert!(
            (fd - e.grad()[k]).abs() < 1e-4 * (1.0 + fd.abs()),
            "k={k} fd={fd} an={}",
            e.grad()[k]
        );
    }
}
