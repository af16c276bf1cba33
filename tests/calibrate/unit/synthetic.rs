//! The unit tests of `src/calibrate/synthetic.rs`.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;
use surrogate::calibrate::objective::{Recordings, FREE_LENGTH_MM};
use surrogate::calibrate::synthetic::*;
use surrogate::random::standard_normal;

#[test]
fn noise_has_the_stated_scale_and_is_reproducible() {
    let mut rng = Xoshiro256Plus::seed_from_u64(7);
    let v: Vec<f64> = (0..20_000).map(|_| standard_normal(&mut rng)).collect();
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64;
    assert!(
        mean.abs() < 0.03 && (var - 1.0).abs() < 0.05,
        "{mean} {var}"
    );
    let rec = Recordings::shipped().unwrap();
    let truth: Vec<TrueOutputs> = rec
        .bending
        .iter()
        .map(|r| TrueOutputs {
            n_bellows: r.n_bellows,
            wall_thickness_mm: r.wall_thickness_mm,
            pressure_bar: r.pressure_bar,
            tip_uz_mm: r.tip_uz_mm,
            tip_uy_mm: r.tip_uy_mm,
            angle_deg: r.angle_deg,
            force_n: 1.0,
        })
        .collect();
    let a = noisy_recordings(&truth, &rec, 3, "t").unwrap();
    let b = noisy_recordings(&truth, &rec, 3, "t").unwrap();
    assert_eq!(a.bending, b.bending);
    assert_eq!(a.force.len(), 27);
    let c = noisy_recordings(&truth, &rec, 4, "t").unwrap();
    assert_ne!(a.bending, c.bending);
    let mut bad = truth[0].clone();
    bad.pressure_bar = 2.5;
    assert!(noisy_recordings(&[bad], &rec, 3, "t").is_err());
}

#[test]
fn marker_noise_follows_the_chord_and_is_reproducible() {
    let rec = Recordings::shipped().unwrap();
    let b = &rec.bending[0];
    let truth = [TrueMarkers {
        n_bellows: b.n_bellows,
        wall_thickness_mm: b.wall_thickness_mm,
        pressure_bar: b.pressure_bar,
        markers: std::array::from_fn(|k| [0.0, -(k as f64)]),
    }];
    let a = noisy_markers(&truth, &rec, 5).unwrap();
    assert_eq!(a, noisy_markers(&truth, &rec, 5).unwrap());
    assert_ne!(a, noisy_markers(&truth, &rec, 6).unwrap());
    assert_eq!(a.len(), 9);
    let sa = b.angle_std_deg.to_radians();
    // marker 1 at z = Lf/9, no deflection: r = Lf/9; the tip: r = hypot(Lf, 8)
    assert!((a[0].std_mm - FREE_LENGTH_MM / 9.0 * sa).abs() < 1e-12);
    assert!((a[8].std_mm - FREE_LENGTH_MM.hypot(8.0) * sa).abs() < 1e-12);
    assert!(a
        .iter()
        .all(|m| m.std_mm > 0.0 && (1..=9).contains(&m.marker)));
    // an independent stream: the first deviate differs from the bending stream's
    let mut rng = Xoshiro256Plus::seed_from_u64(5);
    let first = standard_normal(&mut rng) * a[0].std_mm;
    assert_ne!(a[0].uz_mm, first);
}
