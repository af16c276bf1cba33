//! The fast paths of the surrogate: the scalar path of [`super::Surrogate::predict_scalars_into`]
//! (tip Uz, tip Uy, angle and force with the POD basis folded into the regression weights) and
//! the GP kernel vector from the training inputs stored by feature (every prediction).
//!
//! A quantity `q` of a block is `y_q(P) = Σ_s w_s(P) (ȳ_e + s_e Σ_k Φ_ek a_k(x))` with
//! `e = j_s·|Q| + slot_q`, and a regressor with a linear basis ([`Regressor::linear_basis`]:
//! the GP's kernel vector and `α`, the polynomial's monomials and coefficients) has
//! coefficients `a_k(x) = Σ_b φ_b(x) W_{b,k}`. So `y_q(P) = Σ_s w_s (ȳ_e + Σ_b φ_b(x) C_{b,j_s,q})`
//! with the folded table `C_{b,j,q} = s_e Σ_k Φ_ek W_{b,k}`: per basis function, 4 stencil nodes
//! × 4 quantities instead of all the modes of the four scalar blocks (32 columns for the shipped
//! models). Same algebra, so the same values up to rounding (tested to 1e-12 relative).
//!
//! A regressor with column groups (the GP with a kernel per block) has each group's sources
//! folded apart, with the basis of their group. A scalar served by a regressor without a
//! linear basis makes the scalar path the general one.
//!
//! The GP kernel vector is computed from the training inputs stored by feature (`d × n`), so
//! that the distance loop and the branch-free Matérn both run over contiguous vectors; on
//! x86-64 with AVX2 and FMA (detected at run time) the same code is compiled for 4-wide lanes.
//! No fused multiply-adds are formed, so every path gives bit-identical kernel values.
//!
//! The tables are derived from the model on first use (never stored in the model file).
//!
//! [`Regressor::linear_basis`]: super::regression::Regressor::linear_basis

use std::sync::OnceLock;

use super::pod::PodBasis;
pub use super::regression::gp::kernel_vector;
use super::regression::Regressors;
use surrogate_predict::Stencil;

/// Quantities of the fast path: tip Uz, tip Uy, angle, force.
pub const SCALARS: std::ops::Range<usize> = super::Q_TIP_UZ..22;
// public for the tests in tests/rom/
#[doc(hidden)]
pub const NS: usize = 4;

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

/// One regressor's (one column group's) part of the fast path.
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

/// Folded tables of the scalar quantities, per regressor and column group, and the regressor
/// of each block.
#[derive(Debug, Clone)]
pub struct ScalarPath {
    /// Parts with their regressor (index in the model's regressors) and column group.
    parts: Vec<(usize, usize, Part)>,
    /// Whether the parts serve every scalar (else the general path serves them).
    complete: bool,
    /// Index of each block's regressor among the model's regressors.
    block_regressor: Vec<usize>,
}

/// Where each scalar quantity comes from: its block and slot.
pub struct Source<'a> {
    /// Output index.
    pub quantity: usize,
    /// Block's POD basis.
    pub pod: &'a PodBasis,
    /// Block's regressor (index in the model's regressors).
    pub regressor: usize,
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
    /// Folds the POD bases of `sources` into the weights of the regressors with a linear
    /// basis; `block_regressor` is the index of each block's regressor. Prepares every
    /// regressor ([`Regressor::prepare`](super::regression::Regressor::prepare)).
    pub fn build(
        regressors: &Regressors,
        sources: &[Source<'_>],
        n_p: usize,
        block_regressor: Vec<usize>,
    ) -> Self {
        let mut parts = Vec::new();
        let mut served = 0;
        for (r, reg) in regressors.iter().enumerate() {
            reg.prepare();
            let mine: Vec<&Source<'_>> = sources.iter().filter(|s| s.regressor == r).collect();
            let Some(basis) = reg.linear_basis().filter(|_| !mine.is_empty()) else {
                continue;
            };
            for (g, cols) in basis.groups.iter().enumerate() {
                let in_group: Vec<&Source<'_>> = mine
                    .iter()
                    .copied()
                    .filter(|s| cols.contains(&s.coef_offset))
                    .collect();
                let m = reg.n_outputs();
                if let Some(p) = fold(&in_group, basis.weights, m, basis.n_basis, n_p) {
                    served += p.quantities.len();
                    parts.push((r, g, p));
                }
            }
        }
        ScalarPath {
            parts,
            complete: served == sources.len(),
            block_regressor,
        }
    }

    /// Whether the folded tables serve every scalar quantity.
    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// Index of block `b`'s regressor among the model's regressors.
    #[inline]
    pub fn block_regressor(&self, b: usize) -> usize {
        self.block_regressor[b]
    }

    /// Length of the scratch buffer [`Self::predict_into`] needs.
    pub fn scratch_len(&self) -> usize {
        self.parts
            .iter()
            .map(|(_, _, p)| p.n_basis)
            .max()
            .unwrap_or(0)
    }

    /// The scalar quantities at the scaled features `x` and the pressure stencil `st` into
    /// `values` (indexed by output). No allocation.
    pub fn predict_into(
        &self,
        regressors: &Regressors,
        x: &[f64],
        st: &Stencil<f64>,
        values: &mut [f64],
        scratch: &mut [f64],
    ) {
        for (r, g, part) in &self.parts {
            let phi = &mut scratch[..part.n_basis];
            regressors.at(*r).basis_into(*g, x, phi);
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
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn accumulate_nodes(t: &[f64], block: usize, phi: &[f64]) -> [[f64; NS]; NS] {
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

// public for the tests in tests/rom/
#[doc(hidden)]
#[inline(always)]
pub fn accumulate_nodes_body(t: &[f64], block: usize, phi: &[f64]) -> [[f64; NS]; NS] {
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
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn accumulate<const Q: usize>(t: &[f64], phi: &[f64]) -> [f64; NS] {
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
