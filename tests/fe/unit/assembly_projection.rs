//! The unit tests of `src/fe/assembly/projection.rs`.

use surrogate::fe::assembly::projection::*;

#[test]
fn projection_keeps_psd_matrices_and_clips_negative_eigenvalues() {
    const N: usize = 6;
    // K = Q diag(λ) Qᵀ with a known rotation Q (Householder of a fixed vector)
    let w: [f64; N] = [0.3, -0.5, 0.2, 0.7, -0.1, 0.4];
    let ww: f64 = w.iter().map(|x| x * x).sum();
    let q = |i: usize, j: usize| f64::from(u8::from(i == j)) - 2.0 * w[i] * w[j] / ww;
    let build = |lam: &[f64; N]| {
        let mut k = vec![0.0; N * N];
        for i in 0..N {
            for j in 0..N {
                k[i * N + j] = (0..N).map(|m| lam[m] * q(i, m) * q(j, m)).sum();
            }
        }
        k
    };
    let psd = [3.0, 1.0, 0.5, 0.0, 2.0, 4.0];
    let mut k = build(&psd);
    let before = k.clone();
    assert!(!project_psd::<N>(&mut k));
    assert_eq!(k, before);
    let mut k = build(&[3.0, -1.0, 0.5, -2.0, 2.0, 4.0]);
    assert!(project_psd::<N>(&mut k));
    let want = build(&[3.0, 0.0, 0.5, 0.0, 2.0, 4.0]);
    for (a, b) in k.iter().zip(&want) {
        assert!((a - b).abs() < 1e-12, "{a} vs {b}");
    }
}
