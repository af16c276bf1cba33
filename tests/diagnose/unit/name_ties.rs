//! The unit tests of `src/diagnose/name/ties.rs`.

use nalgebra::DVector;

use surrogate::diagnose::name::PairFit;

/// The separation test on vectors made by hand: two signatures 0.8 apart in cosine, a
/// residual along the first with unit noise elsewhere.
#[test]
fn a_pair_is_tied_unless_the_better_one_adds_significantly_beyond_the_other() {
    let n = 60;
    let e = |k: usize| DVector::from_fn(n, |i, _| if i == k { 1.0 } else { 0.0 });
    let sa = e(0);
    let sb = e(0) * 0.8 + e(1) * 0.6;
    // unit noise on the other 58 numbers: χ² per degree of freedom about 1
    let noise = DVector::from_fn(n, |i, _| {
        if i < 2 {
            0.0
        } else if i % 2 == 0 {
            1.0
        } else {
            -1.0
        }
    });
    // the fit of a residual that holds everything the material left
    fn pair_fit(r: &DVector<f64>) -> PairFit<'_> {
        PairFit {
            residual: r,
            chi2_material: r.norm_squared(),
            dof: r.len() as f64 - 5.0,
            alpha: 0.05,
            collinear: 0.95,
        }
    }
    let fit = |size: f64| pair_fit(&(&sa * size + &noise)).p_separation(&sa, &sb);
    // a strong residual along `sa`: b explains 64 % of it, a all of it, 36 % beyond b
    // is 0.36 × 100 = 36 χ² units, far beyond the noise
    assert!(fit(10.0) < 1e-6, "{}", fit(10.0));
    // a weak one: 0.36 × 4 = 1.44 beyond b, within the noise
    assert!(fit(2.0) > 0.05, "{}", fit(2.0));
    // the order of the two does not matter
    let r = &sa * 2.0 + &noise;
    let f = pair_fit(&r);
    assert!((f.p_separation(&sa, &sb) - f.p_separation(&sb, &sa)).abs() < 1e-12);
    // Vuong: antisymmetric, and decided only by a strong residual
    assert!((f.vuong_z(&sa, &sb) + f.vuong_z(&sb, &sa)).abs() < 1e-12);
    assert!(f.tied(f.p_separation(&sa, &sb), f.vuong_z(&sa, &sb)));
    let r = &sa * 10.0 + &noise;
    let strong = pair_fit(&r);
    // D = 100 − 64, |ŷ_a − ŷ_b| = |3.6, −4.8| = 6: z ≈ 36 / 12 = 3, told apart
    let z = strong.vuong_z(&sa, &sb);
    assert!((z - 3.0).abs() < 0.2, "{z}");
    assert!(!strong.tied(strong.p_separation(&sa, &sb), z));
    assert_eq!(strong.vuong_z(&sa, &sa), 0.0);
}
