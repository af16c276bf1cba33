//! The precision of a model and the transcendentals it needs, with `core` only.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// Floating-point type the embedded predictor runs in (`f32` or `f64`).
pub trait Real:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// Conversion from `f64` (rounding).
    fn from_f64(x: f64) -> Self;
    /// Conversion to `f64` (exact).
    fn to_f64(self) -> f64;
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
}

const LN2: f64 = core::f64::consts::LN_2;

/// `eˣ` with `core` only: `x = k ln2 + r`, `|r| ≤ ln2/2`, degree-13 Taylor series in `r`
/// (relative error ≲ 3·10⁻¹⁶ for normal results).
pub fn exp(x: f64) -> f64 {
    if x.is_nan() {
        return x;
    }
    if x > 709.0 {
        return f64::INFINITY;
    }
    if x < -745.0 {
        return 0.0;
    }
    let k = round_half_away(x / LN2);
    // Cody–Waite reduction: ln 2 split so that k·LN2_HI is exact (fdlibm constants)
    const LN2_HI: f64 = 6.931_471_803_691_238e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    // Taylor coefficients 1/i!, i = 13 … 1, evaluated by Horner's rule
    const C: [f64; 13] = [
        1.0 / 6_227_020_800.0,
        1.0 / 479_001_600.0,
        1.0 / 39_916_800.0,
        1.0 / 3_628_800.0,
        1.0 / 362_880.0,
        1.0 / 40_320.0,
        1.0 / 5_040.0,
        1.0 / 720.0,
        1.0 / 120.0,
        1.0 / 24.0,
        1.0 / 6.0,
        0.5,
        1.0,
    ];
    let mut p = C[0];
    let mut i = 1;
    while i < 13 {
        p = p * r + C[i];
        i += 1;
    }
    scale_pow2(p * r + 1.0, k as i32)
}

/// `eˣ` for `x ≤ 0`, branch-free so that a loop over it vectorises: the same Cody–Waite
/// reduction and degree-13 series as [`exp`], with `2ᵏ` built from the bits of
/// `x/ln2 + 1.5·2⁵²` (round to nearest). Arguments below −708 are clamped (result ≈ 3·10⁻³⁰⁸
/// instead of a smaller number or 0); positive arguments are not allowed (debug assertion).
#[inline(always)]
pub fn exp_nonpos(x: f64) -> f64 {
    debug_assert!(x <= 0.0 || x.is_nan());
    const LN2_HI: f64 = 6.931_471_803_691_238e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    const LOG2E: f64 = core::f64::consts::LOG2_E;
    const ROUND: f64 = 6_755_399_441_055_744.0; // 1.5 · 2^52
    let x = if x < -708.0 { -708.0 } else { x };
    let t = x * LOG2E + ROUND;
    let k = t - ROUND;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    let mut p = 1.0 / 6_227_020_800.0;
    p = p * r + 1.0 / 479_001_600.0;
    p = p * r + 1.0 / 39_916_800.0;
    p = p * r + 1.0 / 3_628_800.0;
    p = p * r + 1.0 / 362_880.0;
    p = p * r + 1.0 / 40_320.0;
    p = p * r + 1.0 / 5_040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    // the low mantissa bits of t hold k (two's complement, k ∈ [−1022, 0]); adding the
    // exponent bias and shifting by 52 leaves exactly the biased exponent k + 1023
    let scale = f64::from_bits(t.to_bits().wrapping_add(1023) << 52);
    (p * r + 1.0) * scale
}

/// `ln x` with `core` only: `x = m·2ᵉ`, `m ∈ [√½, √2)`, `ln m = 2 atanh((m−1)/(m+1))`.
/// Returns NaN for `x ≤ 0` or NaN.
pub fn ln(x: f64) -> f64 {
    if x.is_nan() || x <= 0.0 || x == f64::INFINITY {
        return if x == f64::INFINITY { x } else { f64::NAN };
    }
    let mut x = x;
    let mut e = 0i32;
    if x < f64::MIN_POSITIVE {
        x *= 18014398509481984.0; // 2^54
        e -= 54;
    }
    let bits = x.to_bits();
    e += ((bits >> 52) & 0x7ff) as i32 - 1023;
    let mut m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    if m > core::f64::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    // atanh series Σ s^(2k+1)/(2k+1), k = 0..19, by Horner's rule in s² (|s| ≤ 0.172)
    let mut p = 1.0 / 39.0;
    let mut k = 37.0;
    while k > 0.0 {
        p = p * s2 + 1.0 / k;
        k -= 2.0;
    }
    2.0 * s * p + e as f64 * LN2
}

/// `√x` with `core` only: reciprocal square root by Newton's rule `y ← y(3 − xy²)/2` from the
/// exponent-halving guess (multiplications only), then `√x = x·y` with one correction.
pub fn sqrt(x: f64) -> f64 {
    if x <= 0.0 || x.is_nan() || x == f64::INFINITY {
        return if x == 0.0 || x == f64::INFINITY {
            x
        } else {
            f64::NAN
        };
    }
    if x < f64::MIN_POSITIVE {
        // subnormal: scale by 2^54
        return sqrt(x * 18014398509481984.0) / 134217728.0;
    }
    let mut y = f64::from_bits(0x5fe6_eb50_c7b5_37a9 - (x.to_bits() >> 1));
    let mut i = 0;
    while i < 4 {
        y = y * (1.5 - 0.5 * x * y * y);
        i += 1;
    }
    let s = x * y;
    s + 0.5 * y * (x - s * s)
}

fn round_half_away(x: f64) -> f64 {
    let t = x as i64 as f64; // truncation; |x| < 1100 here
    if x - t >= 0.5 {
        t + 1.0
    } else if t - x >= 0.5 {
        t - 1.0
    } else {
        t
    }
}

fn scale_pow2(x: f64, k: i32) -> f64 {
    // split to stay within the normal exponent range
    let mut x = x;
    let mut k = k;
    while k > 1000 {
        x *= f64::from_bits(((1023 + 1000) as u64) << 52);
        k -= 1000;
    }
    while k < -1000 {
        x *= f64::from_bits(((1023 - 1000) as u64) << 52);
        k += 1000;
    }
    x * f64::from_bits(((1023 + k) as u64) << 52)
}

/// Matérn-5/2 correlation for scaled distance `r ≥ 0`: `(1 + √5 r + 5r²/3) e^{−√5 r}`.
/// Also returns `g(r) = −(1/r) dk/dr = (5/3)(1 + √5 r) e^{−√5 r}`, so that
/// `∂k/∂x_d = −g Δ_d / ℓ_d²` with `Δ = x − xᵢ`.
pub fn matern52(r: f64) -> (f64, f64) {
    const S5: f64 = 2.236_067_977_499_79;
    let e = exp_nonpos(-S5 * r);
    let k = (1.0 + S5 * r + 5.0 / 3.0 * r * r) * e;
    let g = 5.0 / 3.0 * (1.0 + S5 * r) * e;
    (k, g)
}

#[cfg(test)]
mod tests {
    // the tests compare with std's maths
    extern crate std;

    use super::*;

    #[test]
    fn core_maths_match_std() {
        let mut x = -700.0; // normal results (subnormals lose digits, as in libm)
        while x < 705.0 {
            let (a, b) = (exp(x), x.exp());
            assert!((a - b).abs() <= 4e-16 * b, "exp({x}): {a} vs {b}");
            x += 0.37;
        }
        let mut v = 1e-300;
        while v < 1e300 {
            assert!(
                (ln(v) - v.ln()).abs() <= 4e-16 * v.ln().abs().max(1.0),
                "ln({v})"
            );
            assert!(
                (sqrt(v) - v.sqrt()).abs() <= 4e-16 * v.sqrt(),
                "sqrt({v}): {} vs {}",
                sqrt(v),
                v.sqrt()
            );
            v *= 3.7;
        }
        assert_eq!(sqrt(0.0), 0.0);
        assert!(exp(-740.0) < 1e-320 && exp(-800.0) == 0.0);
        // the branch-free variant on x ≤ 0, including the ends of each reduction interval
        let mut x = -708.0;
        while x <= 0.0 {
            for y in [x, x - 0.5 * LN2, x + 1e-9] {
                if (-708.0..=0.0).contains(&y) {
                    let (a, b) = (exp_nonpos(y), y.exp());
                    assert!((a - b).abs() <= 4e-16 * b, "exp_nonpos({y}): {a} vs {b}");
                }
            }
            x += 0.173;
        }
        assert_eq!(exp_nonpos(0.0), 1.0);
        assert!(exp_nonpos(-1e4) > 0.0 && exp_nonpos(-1e4) < 1e-307);
        assert!(ln(-1.0).is_nan() && sqrt(-1.0).is_nan());
        assert!((sqrt(4e-320) - 4e-320f64.sqrt()).abs() <= 1e-15 * 4e-320f64.sqrt());
    }
}
