//! # surrogate-predict
//!
//! The embedded predictor of the `surrogate` crate: evaluates a soft-actuator surrogate exported
//! by `surrogate export --rust OUT.rs` with **`core` only**: `#![no_std]`, no allocation, no
//! dependencies, no `std` maths, no `unsafe`. A controller adds this crate to its `Cargo.toml`
//! and compiles the exported file as one of its modules; the exported file brings the model's
//! `static` tables, `pub static MODEL` (or `RAMP`) and a C entry point (`README.md` of this
//! crate: the Rust and the C controller side).
//!
//! The evaluation mirrors the library's `surrogate::rom::Surrogate`:
//!
//! 1. features `z = (N, T, ln μ0, α₁, s, α₂)` (μ0 = ½(μ₁α₁ + μ₂α₂), s = μ₁α₁/(2μ0)), scaled `x_d = (z_d − c_d)·s_d`;
//! 2. POD coefficients `a = f(x)` from a Matérn-5/2 Gaussian process (posterior mean
//!    `a_c = Σᵢ k(x, xᵢ) αᵢc`) or a polynomial (`a_c = Σ_p x^{e_p} β_pc`);
//! 3. per output block, the snapshot ramp at the pressure nodes of a cubic Hermite stencil,
//!    `y_{j,q} = m_{j,q} + s_{j,q} Σ_k a_k Φ_{(j,q),k}`, interpolated in pressure:
//!    `y_q(P) = Σ_j w_j(P) y_{j,q}`.
//!
//! Transcendentals (`exp`, `ln`, `sqrt`) are evaluated in `f64` by the portable routines below
//! (accurate to a few ulp); the Gaussian-process sum is always `f64` (see [`GpTables`]); the
//! polynomial and the POD reconstruction run in the model's precision `F` (`f32` or `f64`).
//!
//! An exported ramp (`surrogate export --ramp`: one design and one material) is evaluated by
//! [`evaluate_ramp`]; only the pressure stencil is left:
//!
//! ```
//! use surrogate_predict::{evaluate_ramp, EmbeddedError, RampTables, FORCE, N_QUANTITIES};
//!
//! // the shape of an exported ramp: a pressure grid (bar) and the 22 quantities at each node
//! static PRESSURES: [f64; 2] = [0.0, 2.0];
//! static VALUES: [f32; 2 * N_QUANTITIES] = {
//!     let mut v = [0.0f32; 2 * N_QUANTITIES];
//!     v[N_QUANTITIES + FORCE] = 1.2; // blocked force 1.2 N at 2 bar
//!     v
//! };
//! static RAMP: RampTables<'static, f32> = RampTables { pressures: &PRESSURES, values: &VALUES };
//!
//! let mut out = [0.0f32; N_QUANTITIES];
//! evaluate_ramp(&RAMP, 1.0, &mut out)?;
//! assert!((out[FORCE] - 0.6).abs() < 1e-6);
//! // outside the grid the pressure is clamped to its ends
//! evaluate_ramp(&RAMP, 5.0, &mut out)?;
//! assert_eq!(out[FORCE], 1.2);
//! assert_eq!(evaluate_ramp(&RAMP, f32::NAN, &mut out), Err(EmbeddedError::NonFinite(2)));
//! # Ok::<(), EmbeddedError>(())
//! ```
//!
//! Beside the tables, an exported file carries the model-form error learned from a calibration
//! (`pub static MODEL_FORM: Option<ModelFormTables>`, [`ModelFormTables::error`]): how far the
//! calibrated model misses the recorded actuators, per output and pressure. The surrogate's
//! own error against the FE model is much smaller; the model-form error is the one a designer
//! should read as the prediction's accuracy.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// index loops mirror the equations and the table layouts
#![allow(clippy::needless_range_loop)]

use core::ops::{Add, Div, Mul, Neg, Sub};

mod model_form;
pub use model_form::{model_form_at, ModelFormTables};

/// Number of raw regression features: `N, T, ln μ0, α₁, s, α₂`.
pub const N_FEATURES: usize = 6;
/// Number of query inputs: `N, T, P, μ₁, α₁, μ₂, α₂`.
pub const N_INPUTS: usize = 7;
/// Number of predicted quantities: 18 marker components (`m1_uz, m1_uy, …, m9_uy`), then
/// `tip_uz, tip_uy, angle, force`; each has a named index ([`TIP_UZ`], [`ANGLE`], [`M1_UZ`],
/// [`marker_uz`] …) and a name ([`OUTPUT_NAMES`]).
pub const N_QUANTITIES: usize = 22;
/// Names of the 22 outputs in storage order (the columns of `surrogate predict`, with their
/// units as suffix: mm, degrees, N); `OUTPUT_NAMES[TIP_UZ] == "tip_uz_mm"`.
pub const OUTPUT_NAMES: [&str; N_QUANTITIES] = [
    "m1_uz_mm",
    "m1_uy_mm",
    "m2_uz_mm",
    "m2_uy_mm",
    "m3_uz_mm",
    "m3_uy_mm",
    "m4_uz_mm",
    "m4_uy_mm",
    "m5_uz_mm",
    "m5_uy_mm",
    "m6_uz_mm",
    "m6_uy_mm",
    "m7_uz_mm",
    "m7_uy_mm",
    "m8_uz_mm",
    "m8_uy_mm",
    "m9_uz_mm",
    "m9_uy_mm",
    "tip_uz_mm",
    "tip_uy_mm",
    "angle_deg",
    "force_n",
];

/// Index of marker `k`'s Uz (mm) among the outputs, `k = 1 … 9` as in the columns `m1` … `m9`
/// (marker 9 is the tip): `2 (k − 1)`.
///
/// # Panics
/// `k` outside `1 … 9` (at compile time in a `const`).
pub const fn marker_uz(k: usize) -> usize {
    assert!(k >= 1 && k <= 9, "markers are numbered 1 … 9");
    2 * (k - 1)
}

/// Index of marker `k`'s Uy (mm) among the outputs, `k = 1 … 9`: `2 (k − 1) + 1`.
///
/// # Panics
/// `k` outside `1 … 9`.
pub const fn marker_uy(k: usize) -> usize {
    marker_uz(k) + 1
}

macro_rules! output_indices {
    ($($name:ident = $index:expr, $column:literal;)*) => {
        $(
            #[doc = concat!("Index of `", $column, "` among the 22 outputs.")]
            pub const $name: usize = $index;
        )*
    };
}

output_indices! {
    M1_UZ = 0, "m1_uz_mm";
    M1_UY = 1, "m1_uy_mm";
    M2_UZ = 2, "m2_uz_mm";
    M2_UY = 3, "m2_uy_mm";
    M3_UZ = 4, "m3_uz_mm";
    M3_UY = 5, "m3_uy_mm";
    M4_UZ = 6, "m4_uz_mm";
    M4_UY = 7, "m4_uy_mm";
    M5_UZ = 8, "m5_uz_mm";
    M5_UY = 9, "m5_uy_mm";
    M6_UZ = 10, "m6_uz_mm";
    M6_UY = 11, "m6_uy_mm";
    M7_UZ = 12, "m7_uz_mm";
    M7_UY = 13, "m7_uy_mm";
    M8_UZ = 14, "m8_uz_mm";
    M8_UY = 15, "m8_uy_mm";
    M9_UZ = 16, "m9_uz_mm";
    M9_UY = 17, "m9_uy_mm";
    TIP_UZ = 18, "tip_uz_mm";
    TIP_UY = 19, "tip_uy_mm";
    ANGLE = 20, "angle_deg";
    FORCE = 21, "force_n";
}

/// Largest number of regression outputs (POD coefficients over all blocks) an embedded model may have.
pub const MAX_COEFS: usize = 96;

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

/// Cubic Hermite interpolation weights on a pressure grid: `y(P) = Σ_{i<len} w[i] y[start + i]`,
/// `dy/dP = Σ dw[i] y[start + i]`. Slopes at the nodes are 3-point finite differences
/// (one-sided at the ends), so the weights are linear in the nodal values. `P` is clamped to
/// the grid (zero derivative outside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stencil<F> {
    /// First node of the stencil.
    pub start: usize,
    /// Number of nodes used (2..=4).
    pub len: usize,
    /// Weights.
    pub w: [F; 4],
    /// Derivatives of the weights with respect to `P`.
    pub dw: [F; 4],
}

/// Slope weights at node `j`: `m_j = Σ c[i] y[j0 + i]`.
fn slope_weights(grid: &[f64], j: usize) -> (usize, [f64; 3], usize) {
    let n = grid.len();
    if n == 2 {
        let h = grid[1] - grid[0];
        return (0, [-1.0 / h, 1.0 / h, 0.0], 2);
    }
    if j == 0 {
        let (h1, h2) = (grid[1] - grid[0], grid[2] - grid[1]);
        let c0 = -(2.0 * h1 + h2) / (h1 * (h1 + h2));
        let c1 = (h1 + h2) / (h1 * h2);
        let c2 = -h1 / (h2 * (h1 + h2));
        return (0, [c0, c1, c2], 3);
    }
    if j == n - 1 {
        let (h1, h2) = (grid[n - 2] - grid[n - 3], grid[n - 1] - grid[n - 2]);
        let c0 = h2 / (h1 * (h1 + h2));
        let c1 = -(h1 + h2) / (h1 * h2);
        let c2 = (2.0 * h2 + h1) / (h2 * (h1 + h2));
        return (n - 3, [c0, c1, c2], 3);
    }
    let (hl, hr) = (grid[j] - grid[j - 1], grid[j + 1] - grid[j]);
    let c0 = -hr / (hl * (hl + hr));
    let c1 = (hr - hl) / (hl * hr);
    let c2 = hl / (hr * (hl + hr));
    (j - 1, [c0, c1, c2], 3)
}

/// Hermite stencil at pressure `p` on the sorted grid (at least 2 nodes), computed in `f64`.
pub fn stencil(grid: &[f64], p: f64) -> Stencil<f64> {
    let n = grid.len();
    let (p, inside) = if p <= grid[0] {
        (grid[0], false)
    } else if p >= grid[n - 1] {
        (grid[n - 1], false)
    } else {
        (p, true)
    };
    let mut i = 0;
    while i + 2 < n && p >= grid[i + 1] {
        i += 1;
    }
    let h = grid[i + 1] - grid[i];
    let s = (p - grid[i]) / h;
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    let d00 = (6.0 * s2 - 6.0 * s) / h;
    let d10 = (3.0 * s2 - 4.0 * s + 1.0) / h;
    let d01 = (-6.0 * s2 + 6.0 * s) / h;
    let d11 = (3.0 * s2 - 2.0 * s) / h;
    let start = i.saturating_sub(1).min(n.saturating_sub(4));
    let len = (n - start).min(4);
    let mut st = Stencil {
        start,
        len,
        w: [0.0; 4],
        dw: [0.0; 4],
    };
    st.w[i - start] += h00;
    st.w[i + 1 - start] += h01;
    st.dw[i - start] += d00;
    st.dw[i + 1 - start] += d01;
    for (node, hv, dv) in [(i, h10 * h, d10 * h), (i + 1, h11 * h, d11 * h)] {
        let (j0, c, len_c) = slope_weights(grid, node);
        let mut k = 0;
        while k < len_c {
            st.w[j0 + k - start] += hv * c[k];
            st.dw[j0 + k - start] += dv * c[k];
            k += 1;
        }
    }
    if !inside {
        st.dw = [0.0; 4];
    }
    st
}

/// Gaussian-process tables of an embedded model (Matérn 5/2, zero prior mean).
///
/// Always `f64`, also in `f32` models: the weights of an interpolating GP cancel
/// (`|α|` is 10³–10⁵ times the outputs), so `f32` weights would lose 4–5 digits.
#[derive(Debug, Clone, Copy)]
pub struct GpTables<'a> {
    /// Column groups with a kernel each, as boundaries `[0, b₁, …, n_coefs]`; empty: one
    /// kernel for all columns.
    pub groups: &'a [u16],
    /// Inverse length scales `1/ℓ_d` (scaled features), length `d` per group.
    pub inv_len: &'a [f64],
    /// Training inputs divided by the length scales, row-major `n × d` per group.
    pub xs: &'a [f64],
    /// Weights `α = R⁻¹Y`, row-major `n × n_coefs`.
    pub alpha: &'a [f64],
}

/// Polynomial tables of an embedded model.
#[derive(Debug, Clone, Copy)]
pub struct PolyTables<'a, F> {
    /// Exponents, row-major `n_terms × d`.
    pub exponents: &'a [u8],
    /// Coefficients, row-major `n_terms × n_coefs`.
    pub coef: &'a [F],
}

/// One POD block of an embedded model.
#[derive(Debug, Clone, Copy)]
pub struct BlockTables<'a, F> {
    /// Number of quantities per pressure node.
    pub n_quantities: usize,
    /// Number of POD modes.
    pub n_modes: usize,
    /// Offset of this block's coefficients among the regression outputs.
    pub coef_offset: usize,
    /// 0: Gaussian process, 1: polynomial.
    pub regressor: u8,
    /// Mean snapshot, `n_pressures × n_quantities`.
    pub mean: &'a [F],
    /// Scale of each entry, same layout as `mean`.
    pub scale: &'a [F],
    /// Modes, row-major `(n_pressures · n_quantities) × n_modes`.
    pub modes: &'a [F],
}

/// A complete exported model: const tables, no allocation.
#[derive(Debug, Clone, Copy)]
pub struct EmbeddedModel<'a, F> {
    /// Numbers of bellows the model was trained on.
    pub n_allowed: &'a [u32],
    /// Indices of the active raw features (`0..6`), length `d`.
    pub feature_index: &'a [u8],
    /// Centre of each active feature.
    pub feature_center: &'a [F],
    /// Inverse half-width of each active feature.
    pub feature_inv_half: &'a [F],
    /// Pressure grid (bar), sorted.
    pub pressures: &'a [f64],
    /// Number of regression outputs.
    pub n_coefs: usize,
    /// Gaussian process (empty tables when unused).
    pub gp: GpTables<'a>,
    /// Polynomial (empty tables when unused).
    pub poly: PolyTables<'a, F>,
    /// POD blocks.
    pub blocks: &'a [BlockTables<'a, F>],
    /// For each of the 22 quantities, the block that predicts it.
    pub output_block: &'a [u8],
    /// For each of the 22 quantities, its index among the block's quantities.
    pub output_slot: &'a [u8],
}

/// Why an embedded evaluation was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmbeddedError {
    /// An input is NaN or infinite (index into `N, T, P, μ₁, α₁, μ₂, α₂`).
    NonFinite(usize),
    /// `N` is not one of the trained numbers of bellows.
    UnknownN,
    /// `μ₁α₁ ≤ 0` or `μ₂α₂ ≤ 0`.
    Inadmissible,
    /// The model tables are inconsistent (too many coefficients, bad indices).
    BadModel,
}

impl EmbeddedError {
    /// Status code of the C entry point (`0` is success).
    pub fn code(self) -> i32 {
        match self {
            EmbeddedError::NonFinite(_) => 1,
            EmbeddedError::UnknownN => 2,
            EmbeddedError::Inadmissible => 3,
            EmbeddedError::BadModel => 4,
        }
    }
}

impl core::fmt::Display for EmbeddedError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        const INPUTS: [&str; N_INPUTS] = ["N", "T", "P", "mu1", "alpha1", "mu2", "alpha2"];
        match *self {
            EmbeddedError::NonFinite(i) => match INPUTS.get(i) {
                Some(name) => write!(f, "input {name} is not finite"),
                None => write!(f, "input {i} is not finite"),
            },
            EmbeddedError::UnknownN => f.write_str("N is not a trained number of bellows"),
            EmbeddedError::Inadmissible => {
                f.write_str("inadmissible Ogden material (mu1*alpha1 <= 0 or mu2*alpha2 <= 0)")
            }
            EmbeddedError::BadModel => f.write_str("inconsistent model tables"),
        }
    }
}

impl core::error::Error for EmbeddedError {}

/// Raw features `(N, T, ln μ0, α₁, s, α₂)` of a query `[N, T, P, μ₁, α₁, μ₂, α₂]`.
pub fn raw_features(input: &[f64; N_INPUTS]) -> Result<[f64; N_FEATURES], EmbeddedError> {
    let mut i = 0;
    while i < N_INPUTS {
        if !input[i].is_finite() {
            return Err(EmbeddedError::NonFinite(i));
        }
        i += 1;
    }
    let (k1, k2) = (input[3] * input[4], input[5] * input[6]);
    if !(k1 > 0.0 && k2 > 0.0) {
        return Err(EmbeddedError::Inadmissible);
    }
    Ok([
        input[0],
        input[1],
        ln(0.5 * (k1 + k2)),
        input[4],
        k1 / (k1 + k2),
        input[6],
    ])
}

/// Evaluates all 22 quantities (markers, tip, angle, force) of `model` at
/// `input = [N, T (mm), P (bar), μ₁ (MPa), α₁, μ₂ (MPa), α₂]`. No allocation.
///
/// # Errors
/// Non-finite input, `N` not trained, inadmissible material, or inconsistent tables.
pub fn evaluate<F: Real>(
    model: &EmbeddedModel<'_, F>,
    input: &[F; N_INPUTS],
    out: &mut [F; N_QUANTITIES],
) -> Result<(), EmbeddedError> {
    let mut q64 = [0.0f64; N_INPUTS];
    let mut i = 0;
    while i < N_INPUTS {
        q64[i] = input[i].to_f64();
        i += 1;
    }
    let z = raw_features(&q64)?;
    let n = q64[0];
    if !model.n_allowed.iter().any(|&a| a as f64 == n) {
        return Err(EmbeddedError::UnknownN);
    }
    let d = model.feature_index.len();
    if d > N_FEATURES || model.n_coefs > MAX_COEFS {
        return Err(EmbeddedError::BadModel);
    }
    let mut x = [F::ZERO; N_FEATURES];
    let mut x64 = [0.0f64; N_FEATURES];
    for (j, &fi) in model.feature_index.iter().enumerate() {
        let zf = *z.get(fi as usize).ok_or(EmbeddedError::BadModel)?;
        x64[j] = (zf - model.feature_center[j].to_f64()) * model.feature_inv_half[j].to_f64();
        x[j] = F::from_f64(x64[j]);
    }
    let mut use_gp = false;
    let mut use_poly = false;
    for b in model.blocks {
        if b.regressor == 0 {
            use_gp = true;
        } else {
            use_poly = true;
        }
    }
    let mut coef_gp = [F::ZERO; MAX_COEFS];
    let mut coef_poly = [F::ZERO; MAX_COEFS];
    let m = model.n_coefs;
    if use_gp {
        let mut c64 = [0.0f64; MAX_COEFS];
        gp_mean(&model.gp, &x64[..d], m, &mut c64[..m])?;
        for k in 0..m {
            coef_gp[k] = F::from_f64(c64[k]);
        }
    }
    if use_poly {
        poly_mean(&model.poly, &x[..d], m, &mut coef_poly[..m]);
    }
    let st = stencil(model.pressures, q64[2]);
    for q in 0..N_QUANTITIES {
        let b = model
            .blocks
            .get(model.output_block[q] as usize)
            .ok_or(EmbeddedError::BadModel)?;
        let coef = if b.regressor == 0 {
            &coef_gp
        } else {
            &coef_poly
        };
        let slot = model.output_slot[q] as usize;
        let r = b.n_modes;
        let mut acc = F::ZERO;
        for s in 0..st.len {
            let e = (st.start + s) * b.n_quantities + slot;
            let row = &b.modes[e * r..(e + 1) * r];
            let mut v = F::ZERO;
            for k in 0..r {
                v = v + coef[b.coef_offset + k] * row[k];
            }
            acc = acc + F::from_f64(st.w[s]) * (b.mean[e] + b.scale[e] * v);
        }
        out[q] = acc;
    }
    Ok(())
}

fn gp_mean(gp: &GpTables<'_>, x: &[f64], m: usize, out: &mut [f64]) -> Result<(), EmbeddedError> {
    let d = x.len();
    let n = gp.alpha.len().checked_div(m).unwrap_or(0);
    let n_groups = gp.groups.len().saturating_sub(1).max(1);
    if gp.inv_len.len() != n_groups * d || gp.xs.len() != n_groups * n * d {
        return Err(EmbeddedError::BadModel);
    }
    for g in 0..n_groups {
        let (lo, hi) = if gp.groups.is_empty() {
            (0, m)
        } else {
            (gp.groups[g] as usize, gp.groups[g + 1] as usize)
        };
        if lo >= hi || hi > m {
            return Err(EmbeddedError::BadModel);
        }
        let inv_len = &gp.inv_len[g * d..(g + 1) * d];
        let xs = &gp.xs[g * n * d..(g + 1) * n * d];
        let mut xq = [0.0f64; N_FEATURES];
        for j in 0..d {
            xq[j] = x[j] * inv_len[j];
        }
        for i in 0..n {
            let xi = &xs[i * d..(i + 1) * d];
            let mut r2 = 0.0;
            for j in 0..d {
                let t = xq[j] - xi[j];
                r2 += t * t;
            }
            let (k, _) = matern52(sqrt(r2));
            let a = &gp.alpha[i * m + lo..i * m + hi];
            for (o, ac) in out[lo..hi].iter_mut().zip(a) {
                *o += k * ac;
            }
        }
    }
    Ok(())
}

fn poly_mean<F: Real>(poly: &PolyTables<'_, F>, x: &[F], m: usize, out: &mut [F]) {
    let d = x.len();
    let n_terms = poly.exponents.len().checked_div(d).unwrap_or(1);
    for t in 0..n_terms {
        let mut mono = F::ONE;
        for j in 0..d {
            let mut e = poly.exponents[t * d + j];
            while e > 0 {
                mono = mono * x[j];
                e -= 1;
            }
        }
        let c = &poly.coef[t * m..(t + 1) * m];
        for (o, ck) in out[..m].iter_mut().zip(c) {
            *o = *o + mono * *ck;
        }
    }
}

/// One design and one material exported as its reconstructed pressure ramp
/// (`surrogate export --ramp`): for a controller whose actuator and calibrated material are
/// fixed, no regression is left to evaluate, only the pressure stencil.
#[derive(Debug, Clone, Copy)]
pub struct RampTables<'a, F> {
    /// Pressure grid, bar (sorted, at least 2 nodes).
    pub pressures: &'a [f64],
    /// The 22 quantities at each node, node-major: `values[j * 22 + q]`.
    pub values: &'a [F],
}

/// The 22 quantities of an exported ramp at `p_bar` (clamped to the grid, as the library
/// does); no allocation. In `f64` it is the library's `Ramp::predict_into` operation for
/// operation.
///
/// # Errors
/// [`EmbeddedError::NonFinite`] (index 2, the pressure) or [`EmbeddedError::BadModel`] for
/// inconsistent tables.
pub fn evaluate_ramp<F: Real>(
    ramp: &RampTables<'_, F>,
    p_bar: F,
    out: &mut [F; N_QUANTITIES],
) -> Result<(), EmbeddedError> {
    let p = p_bar.to_f64();
    if !p.is_finite() {
        return Err(EmbeddedError::NonFinite(2));
    }
    let n = ramp.pressures.len();
    if n < 2 || ramp.values.len() != n * N_QUANTITIES {
        return Err(EmbeddedError::BadModel);
    }
    let st = stencil(ramp.pressures, p);
    let mut q = 0;
    while q < N_QUANTITIES {
        let mut v = F::ZERO;
        let mut s = 0;
        while s < st.len {
            v = v + F::from_f64(st.w[s]) * ramp.values[(st.start + s) * N_QUANTITIES + q];
            s += 1;
        }
        out[q] = v;
        q += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    // the tests compare with std's maths
    extern crate std;

    use super::*;

    #[test]
    fn named_outputs_index_their_columns() {
        let named = [
            (TIP_UZ, "tip_uz_mm"),
            (TIP_UY, "tip_uy_mm"),
            (ANGLE, "angle_deg"),
            (FORCE, "force_n"),
            (M1_UZ, "m1_uz_mm"),
            (M1_UY, "m1_uy_mm"),
            (M5_UY, "m5_uy_mm"),
            (M9_UZ, "m9_uz_mm"),
            (M9_UY, "m9_uy_mm"),
        ];
        for (i, name) in named {
            assert_eq!(OUTPUT_NAMES[i], name);
        }
        for k in 1..=9 {
            assert_eq!(OUTPUT_NAMES[marker_uz(k)], std::format!("m{k}_uz_mm"));
            assert_eq!(OUTPUT_NAMES[marker_uy(k)], std::format!("m{k}_uy_mm"));
        }
        // every index once, in order
        let all = [
            M1_UZ, M1_UY, M2_UZ, M2_UY, M3_UZ, M3_UY, M4_UZ, M4_UY, M5_UZ, M5_UY, M6_UZ, M6_UY,
            M7_UZ, M7_UY, M8_UZ, M8_UY, M9_UZ, M9_UY, TIP_UZ, TIP_UY, ANGLE, FORCE,
        ];
        assert!(all.iter().enumerate().all(|(i, &q)| i == q));
        assert!(std::panic::catch_unwind(|| marker_uz(0)).is_err());
        assert!(std::panic::catch_unwind(|| marker_uy(10)).is_err());
    }

    #[test]
    fn errors_have_c_codes_and_messages() {
        use std::string::ToString;
        let cases = [
            (EmbeddedError::NonFinite(2), 1, "input P is not finite"),
            (EmbeddedError::NonFinite(9), 1, "input 9 is not finite"),
            (
                EmbeddedError::UnknownN,
                2,
                "N is not a trained number of bellows",
            ),
            (
                EmbeddedError::Inadmissible,
                3,
                "inadmissible Ogden material",
            ),
            (EmbeddedError::BadModel, 4, "inconsistent model tables"),
        ];
        for (e, code, text) in cases {
            assert_eq!(e.code(), code);
            assert!(e.to_string().starts_with(text), "{e}");
        }
    }

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

    #[test]
    fn stencil_reproduces_cubics_inside_and_its_derivative() {
        let grid = [0.0, 0.25, 0.5, 0.8, 1.0, 1.5, 2.0];
        let f = |p: f64| 1.0 + 2.0 * p - 0.5 * p * p;
        let df = |p: f64| 2.0 - p;
        for k in 0..=40 {
            let p = 2.0 * k as f64 / 40.0;
            let st = stencil(&grid, p);
            let (mut y, mut dy) = (0.0, 0.0);
            for s in 0..st.len {
                y += st.w[s] * f(grid[st.start + s]);
                dy += st.dw[s] * f(grid[st.start + s]);
            }
            // 3-point slopes are exact for quadratics, so the Hermite cubic reproduces them
            assert!((y - f(p)).abs() < 1e-12, "p={p}: {y} vs {}", f(p));
            if p > 0.0 && p < 2.0 {
                assert!((dy - df(p)).abs() < 1e-10, "p={p}: {dy} vs {}", df(p));
            }
        }
    }
}
