//! The Matérn-5/2 kernel: its value, its radial derivative, and the kernel vector from the
//! training inputs stored by feature (every prediction's hot path).

/// Matérn-5/2 value with the branch-free [`surrogate_predict::exp_nonpos`] (shared with the
/// embedded predictor) and `std`'s square root.
#[inline]
pub(super) fn kernel(r: f64) -> f64 {
    kernel_and_g(r).0
}

/// Matérn-5/2 value and `g = −(1/r) dk/dr` (see [`surrogate_predict::matern52`]).
#[inline]
pub(super) fn kernel_and_g(r: f64) -> (f64, f64) {
    const S5: f64 = 2.236_067_977_499_79;
    let e = surrogate_predict::exp_nonpos(-S5 * r);
    (
        (1.0 + S5 * r + 5.0 / 3.0 * r * r) * e,
        5.0 / 3.0 * (1.0 + S5 * r) * e,
    )
}

/// The Matérn-5/2 kernel vector `k_i = k(‖x ⊙ ℓ⁻¹ − xs_i‖)` from training inputs stored by
/// feature (`xs_t`, `d × n`).
pub fn kernel_vector(xs_t: &[f64], inv_len: &[f64], x: &[f64], k: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU supports the features the function is compiled for.
            unsafe { kernel_vector_avx512(xs_t, inv_len, x, k) };
            return;
        }
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports the features the function is compiled for.
            unsafe { kernel_vector_avx2(xs_t, inv_len, x, k) };
            return;
        }
    }
    kernel_vector_body(xs_t, inv_len, x, k);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn kernel_vector_avx512(xs_t: &[f64], inv_len: &[f64], x: &[f64], k: &mut [f64]) {
    kernel_vector_body(xs_t, inv_len, x, k);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn kernel_vector_avx2(xs_t: &[f64], inv_len: &[f64], x: &[f64], k: &mut [f64]) {
    kernel_vector_body(xs_t, inv_len, x, k);
}

#[inline(always)]
fn kernel_vector_body(xs_t: &[f64], inv_len: &[f64], x: &[f64], k: &mut [f64]) {
    let n = k.len();
    k.iter_mut().for_each(|v| *v = 0.0);
    for (j, (&xj, &il)) in x.iter().zip(inv_len).enumerate() {
        let q = xj * il;
        for (kv, &xs) in k.iter_mut().zip(&xs_t[j * n..(j + 1) * n]) {
            let t = q - xs;
            *kv += t * t;
        }
    }
    for kv in k.iter_mut() {
        *kv = matern52(kv.sqrt());
    }
}

/// Matérn-5/2 correlation at scaled distance `r` (the expression of [`kernel`]), inlined into
/// the kernel vector's instruction-set variants.
#[inline(always)]
fn matern52(r: f64) -> f64 {
    const S5: f64 = 2.236_067_977_499_79;
    let e = surrogate_predict::exp_nonpos(-S5 * r);
    (1.0 + S5 * r + 5.0 / 3.0 * r * r) * e
}
