//! An exported model's tables and their evaluation: features, Gaussian process or polynomial,
//! POD reconstruction, interpolation in pressure.

use crate::error::EmbeddedError;
use crate::maths::{ln, matern52, sqrt, Real};
use crate::outputs::{N_FEATURES, N_INPUTS, N_QUANTITIES};
use crate::stencil::stencil;

/// Largest number of regression outputs (POD coefficients over all blocks) an embedded model may have.
pub const MAX_COEFS: usize = 96;

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
