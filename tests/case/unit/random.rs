//! The unit tests of `src/random.rs`.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::random::*;

#[test]
fn splitmix64_matches_the_reference_sequence() {
    // the first outputs of the reference SplitMix64 generator seeded with 0 are the
    // finaliser applied to 1·γ, 2·γ, …; the finaliser here adds γ itself, so feeding it
    // 0, γ, 2γ gives them
    const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;
    assert_eq!(splitmix64(0), 0xE220_A839_7B1D_CDAF);
    assert_eq!(splitmix64(GAMMA), 0x6E78_9E6A_A1B9_65F4);
    assert_eq!(splitmix64(GAMMA.wrapping_mul(2)), 0x06C4_5D18_8009_454F);
}

#[test]
fn standard_normal_has_unit_moments() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let n = 200_000;
    let draws: Vec<f64> = (0..n).map(|_| standard_normal(&mut rng)).collect();
    let mean = draws.iter().sum::<f64>() / n as f64;
    let var = draws.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    // standard errors: 1/√n ≈ 2.2e-3 for the mean, √(2/n) ≈ 3.2e-3 for the variance
    assert!(mean.abs() < 0.01, "mean {mean}");
    assert!((var - 1.0).abs() < 0.015, "variance {var}");
    assert!(draws.iter().all(|x| x.is_finite()));
}
