//! The unit tests of `src/rom/warp.rs`.

use surrogate::rom::warp::*;
use surrogate::rom::Q_TIP_UZ;

#[test]
fn warping_by_one_is_the_identity_and_the_scale_is_recovered() {
    let grid: Vec<f64> = (0..15).map(|i| 0.25 * i as f64).collect();
    // a smooth ramp with a kink-like rise, as a contact onset
    let ramp = |s: f64| -> Vec<[f64; 22]> {
        grid.iter()
            .map(|&p| {
                let q = p / s;
                let mut v = [0.0; 22];
                v[Q_TIP_UZ] = 2.0 * q + 8.0 * (1.0 + ((q - 1.5) * 4.0).tanh());
                v[Q_TIP_UZ + 1] = -5.0 * q * q;
                v[Q_TIP_UZ + 2] = 10.0 * q + q * q * q;
                v
            })
            .collect()
    };
    let low = ramp(1.0);
    assert_eq!(warp_ramp(&grid, &low, 1.0), low);
    let high = ramp(1.12);
    let r = fit_scale(&grid, &low, &high);
    assert!((r - 1.12).abs() < 0.01, "r = {r}");
}
