//! The fast paths of the surrogate: the scalar path of [`super::Surrogate::predict_scalars_into`]
//! (tip Uz, tip Uy, angle and force with the POD basis folded into the regression weights) and
//! the GP kernel vector from the training inputs stored by feature (every prediction).
//!
//! A quantity `q` of a block is `y_q(P) = Σ_s w_s(P) (ȳ_e + s_e Σ_k Φ_ek a_k(x))` with
//! `e = j_s·|Q| + slot_q` and coefficients linear in the regressor's basis,
//! `a_k(x) = Σ_b φ_b(x) W_{b,k}` (the GP's kernel vector and `α`, or the polynomial's monomials
//! and coefficients). So `y_q(P) = Σ_s w_s (ȳ_e + Σ_b φ_b(x) C_{b,j_s,q})` with the folded table
//! `C_{b,j,q} = s_e Σ_k Φ_ek W_{b,k}`: per basis function, 4 stencil nodes × 4 quantities instead
//! of all the modes of the four scalar blocks (32 columns for the shipped models). Same algebra,
//! so the same values up to rounding (tested to 1e-12 relative).
//!
//! With GP column groups (a kernel per block) each group's sources are folded apart and get
//! the kernel vector of their group.
//!
//! The GP kernel vector is computed from the training inputs stored by feature (`d × n`), so
//! that the distance loop and the branch-free Matérn both run over contiguous vectors; on
//! x86-64 with AVX2 and FMA (detected at run time) the same code is compiled for 4-wide lanes.
//! No fused multiply-adds are formed, so every path gives bit-identical kernel values.
//!
//! The tables are derived from the model on first use (never stored in the model file).

use std::sync::OnceLock;

use super::pod::PodBasis;
use super::regression::gp::Gp;
use super::regression::poly::Poly;
use super::regression::RegressorKind;
use surrogate_predict::Stencil;

/// Quantities of the fast path: tip Uz, tip Uy, angle, force.
pub const SCALARS: std::ops::Range<usize> = super::Q_TIP_UZ..22;
const NS: usize = 4;

/// Derived tables, built once per model (`OnceLock`), equal for every equal model: the
/// comparison of two surrogates ignores them.
#[derive(Debug, Clone, Default)]
pub struct Derived(OnceLock<ScalarPath>);

impl PartialEq for Derived {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Derived {
    /// The tables, built on first call.
    pub fn get_or_build(&self, build: impl FnOnce() -> ScalarPath) -> &ScalarPath {
        self.0.get_or_init(build)
    }
}

/// One regressor's part of the fast path.
#[derive(Debug, Clone)]
struct Part {
    /// Output indices served (in 18..22), at most 4.
    quantities: Vec<usize>,
    /// `ȳ` at each pressure node, `n_p × |quantities|`.
    mean: Vec<f64>,
    /// `C`, `n_p × n_basis × |quantities|` (node-major: the rows of one stencil node are
    /// contiguous).
    table: Vec<f64>,
    n_basis: usize,
}

/// Folded tables of the scalar quantities, per regressor kind (and per GP column group).
#[derive(Debug, Clone)]
pub struct ScalarPath {
    /// GP parts with their column group.
    gp: Vec<(usize, Part)>,
    poly: Option<Part>,
    /// GP training inputs / length scales by feature, `d × n` per column group.
    gp_xs_t: Vec<f64>,
    gp_n: usize,
    gp_groups: usize,
}

/// Where each scalar quantity comes from: its block and slot.
pub struct Source<'a> {
    /// Output index.
    pub quantity: usize,
    /// Block's POD basis.
    pub pod: &'a PodBasis,
    /// Block's regressor.
    pub regressor: RegressorKind,
    /// First coefficient column of the block.
    pub coef_offset: usize,
    /// Index of the quantity among the block's quantities.
    pub slot: usize,
}

fn fold(
    sources: &[&Source<'_>],
    weights: &[f64],
    m: usize,
    n_basis: usize,
    n_p: usize,
) -> Option<Part> {
    if sources.is_empty() {
        return None;
    }
    let nq = sources.len();
    let mut mean = vec![0.0; n_p * nq];
    let mut table = vec![0.0; n_basis * n_p * nq];
    for (j, s) in sources.iter().enumerate() {
        let (qb, r) = (s.pod.quantities.len(), s.pod.n_modes);
        for node in 0..n_p {
            let e = node * qb + s.slot;
            mean[node * nq + j] = s.pod.mean[e];
            let phi = &s.pod.modes[e * r..(e + 1) * r];
            for b in 0..n_basis {
                let w = &weights[b * m + s.coef_offset..b * m + s.coef_offset + r];
                let v: f64 = phi.iter().zip(w).map(|(p, w)| p * w).sum();
                table[(node * n_basis + b) * nq + j] = s.pod.scale[e] * v;
            }
        }
    }
    Some(Part {
        quantities: sources.iter().map(|s| s.quantity).collect(),
        mean,
        table,
        n_basis,
    })
}

impl ScalarPath {
    /// Folds the POD bases of `sources` into the regressors' weights.
    pub fn build(gp: &Gp, poly: &Poly, sources: &[Source<'_>], n_p: usize) -> Self {
        let of = |k: RegressorKind| -> Vec<&Source<'_>> {
            sources.iter().filter(|s| s.regressor == k).collect()
        };
        let (d, n) = (gp.d, gp.n);
        let mut gp_xs_t = vec![0.0; gp.n_groups() * d * n];
        for g in 0..gp.n_groups() {
            let xs = gp.group_xs(g);
            for i in 0..n {
                for j in 0..d {
                    gp_xs_t[(g * d + j) * n + i] = xs[i * d + j];
                }
            }
        }
        let gp_sources = of(RegressorKind::Gp);
        let gp_parts = (0..gp.n_groups())
            .filter_map(|g| {
                let cols = gp.group_columns(g);
                let mine: Vec<&Source<'_>> = gp_sources
                    .iter()
                    .copied()
                    .filter(|s| cols.contains(&s.coef_offset))
                    .collect();
                fold(&mine, &gp.alpha, gp.m, gp.n, n_p).map(|p| (g, p))
            })
            .collect();
        ScalarPath {
            gp: gp_parts,
            poly: fold(
                &of(RegressorKind::Poly),
                &poly.coef,
                poly.m,
                poly.n_terms(),
                n_p,
            ),
            gp_xs_t,
            gp_n: n,
            gp_groups: gp.n_groups(),
        }
    }

    /// The GP's coefficients `cols` at the scaled features `x` (the kernel vector from the
    /// inputs stored by feature): the same values as [`Regressor::predict_cols_into`].
    ///
    /// [`Regressor::predict_cols_into`]: super::regression::Regressor::predict_cols_into
    pub fn gp_coefficients_into(
        &self,
        gp: &Gp,
        x: &[f64],
        cols: std::ops::Range<usize>,
        out: &mut [f64],
        scratch: &mut [f64],
    ) {
        let k = &mut scratch[..gp.n];
        for g in 0..gp.n_groups() {
            let r = gp.group_columns(g);
            let (lo, hi) = (cols.start.max(r.start), cols.end.min(r.end));
            if lo < hi {
                kernel_vector(self.group_xs_t(g), gp.group_inv_len(g), x, k);
                gp.combine_into(k, lo..hi, out);
            }
        }
    }

    /// Training inputs of GP column group `g` by feature, `d × n`.
    fn group_xs_t(&self, g: usize) -> &[f64] {
        let len = self.gp_xs_t.len() / self.gp_groups.max(1);
        &self.gp_xs_t[g * len..(g + 1) * len]
    }

    /// Length of the scratch buffer [`Self::predict_into`] needs.
    pub fn scratch_len(&self) -> usize {
        let gp = self.gp.iter().map(|(_, p)| p.n_basis).max().unwrap_or(0);
        gp.max(self.poly.as_ref().map_or(0, |p| p.n_basis))
            .max(self.gp_n)
    }

    /// The scalar quantities at the scaled features `x` and the pressure stencil `st` into
    /// `values` (indexed by output). No allocation.
    pub fn predict_into(
        &self,
        gp: &Gp,
        poly: &Poly,
        x: &[f64],
        st: &Stencil<f64>,
        values: &mut [f64],
        scratch: &mut [f64],
    ) {
        for (g, part) in &self.gp {
            let k = &mut scratch[..part.n_basis];
            kernel_vector(self.group_xs_t(*g), gp.group_inv_len(*g), x, k);
            part.apply(k, st, values);
        }
        if let Some(part) = &self.poly {
            let phi = &mut scratch[..part.n_basis];
            poly.basis_values_into(x, phi);
            part.apply(phi, st, values);
        }
    }
}

impl Part {
    fn apply(&self, phi: &[f64], st: &Stencil<f64>, values: &mut [f64]) {
        let nq = self.quantities.len();
        let block = self.n_basis * nq;
        let mut acc = [[0.0; NS]; NS];
        if st.len == NS && nq == 4 {
            // the usual case: the four stencil nodes in one pass over the basis functions
            let t = &self.table[st.start * block..(st.start + NS) * block];
            acc = accumulate_nodes(t, block, phi);
        } else {
            for (s, a) in acc.iter_mut().enumerate().take(st.len) {
                let t = &self.table[(st.start + s) * block..(st.start + s + 1) * block];
                *a = match nq {
                    4 => accumulate::<4>(t, phi),
                    3 => accumulate::<3>(t, phi),
                    2 => accumulate::<2>(t, phi),
                    _ => accumulate::<1>(t, phi),
                };
            }
        }
        for (j, &q) in self.quantities.iter().enumerate() {
            let mut v = 0.0;
            for s in 0..st.len {
                v += st.w[s] * (self.mean[(st.start + s) * nq + j] + acc[s][j]);
            }
            values[q] = v;
        }
    }
}

/// [`accumulate`]`::<4>` of the four consecutive node tables of `t` (each `block` long) in
/// one pass over the basis functions: eight independent sums instead of two, so the additions
/// no longer wait for each other, and every sum adds its terms in the same order as
/// [`accumulate`] (bit-identical results).
fn accumulate_nodes(t: &[f64], block: usize, phi: &[f64]) -> [[f64; NS]; NS] {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports the features the function is compiled for.
            return unsafe { accumulate_nodes_avx2(t, block, phi) };
        }
    }
    accumulate_nodes_body(t, block, phi)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn accumulate_nodes_avx2(t: &[f64], block: usize, phi: &[f64]) -> [[f64; NS]; NS] {
    accumulate_nodes_body(t, block, phi)
}

#[inline(always)]
fn accumulate_nodes_body(t: &[f64], block: usize, phi: &[f64]) -> [[f64; NS]; NS] {
    const Q: usize = 4;
    let n = phi.len();
    let (t0, rest) = t.split_at(block);
    let (t1, rest) = rest.split_at(block);
    let (t2, t3) = rest.split_at(block);
    let tables = [&t0[..n * Q], &t1[..n * Q], &t2[..n * Q], &t3[..n * Q]];
    let (mut a0, mut a1) = ([[0.0; Q]; NS], [[0.0; Q]; NS]);
    let pairs = n / 2;
    for b in 0..pairs {
        let (p0, p1) = (phi[2 * b], phi[2 * b + 1]);
        for s in 0..NS {
            let r = &tables[s][2 * b * Q..2 * b * Q + 2 * Q];
            for l in 0..Q {
                a0[s][l] += p0 * r[l];
                a1[s][l] += p1 * r[Q + l];
            }
        }
    }
    if n % 2 == 1 {
        let ph = phi[n - 1];
        for s in 0..NS {
            let r = &tables[s][(n - 1) * Q..n * Q];
            for l in 0..Q {
                a0[s][l] += ph * r[l];
            }
        }
    }
    let mut out = [[0.0; NS]; NS];
    for s in 0..NS {
        for l in 0..Q {
            out[s][l] = a0[s][l] + a1[s][l];
        }
    }
    out
}

/// `Σ_b φ_b t[b·Q .. (b+1)·Q]` (the first `Q` entries of the result; `Q ≤ 4`).
fn accumulate<const Q: usize>(t: &[f64], phi: &[f64]) -> [f64; NS] {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports the features the function is compiled for.
            return unsafe { accumulate_avx2::<Q>(t, phi) };
        }
    }
    accumulate_body::<Q>(t, phi)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn accumulate_avx2<const Q: usize>(t: &[f64], phi: &[f64]) -> [f64; NS] {
    accumulate_body::<Q>(t, phi)
}

#[inline(always)]
fn accumulate_body<const Q: usize>(t: &[f64], phi: &[f64]) -> [f64; NS] {
    // two interleaved sums (even and odd basis functions) so that consecutive additions do
    // not wait for each other
    let (mut a0, mut a1) = ([0.0; Q], [0.0; Q]);
    let mut rows = t.chunks_exact(2 * Q);
    let mut pairs = phi.chunks_exact(2);
    for (r, p) in rows.by_ref().zip(pairs.by_ref()) {
        for l in 0..Q {
            a0[l] += p[0] * r[l];
            a1[l] += p[1] * r[Q + l];
        }
    }
    if let [ph] = pairs.remainder() {
        let r = rows.remainder();
        for l in 0..Q {
            a0[l] += ph * r[l];
        }
    }
    let mut out = [0.0; NS];
    for l in 0..Q {
        out[l] = a0[l] + a1[l];
    }
    out
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

/// Matérn-5/2 correlation at scaled distance `r` (the same expression as the GP's).
#[inline(always)]
fn matern52(r: f64) -> f64 {
    const S5: f64 = 2.236_067_977_499_79;
    let e = surrogate_predict::exp_nonpos(-S5 * r);
    (1.0 + S5 * r + 5.0 / 3.0 * r * r) * e
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass four-node sums equal the per-node sums bit for bit (odd and even counts).
    #[test]
    fn four_node_pass_is_bit_identical_to_per_node_sums() {
        for n in [1usize, 2, 7, 300, 301] {
            let block = 4 * n;
            let t: Vec<f64> = (0..NS * block)
                .map(|i| ((i as f64) * 0.7311).sin() * 1e3)
                .collect();
            let phi: Vec<f64> = (0..n).map(|i| ((i as f64) * 1.37).cos()).collect();
            let all = accumulate_nodes(&t, block, &phi);
            let body = accumulate_nodes_body(&t, block, &phi);
            for s in 0..NS {
                let one = accumulate::<4>(&t[s * block..(s + 1) * block], &phi);
                for l in 0..4 {
                    assert_eq!(
                        all[s][l].to_bits(),
                        one[l].to_bits(),
                        "n {n} node {s} q {l}"
                    );
                    assert_eq!(
                        body[s][l].to_bits(),
                        one[l].to_bits(),
                        "n {n} node {s} q {l}"
                    );
                }
            }
        }
    }
}
