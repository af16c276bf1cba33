//! Stress and tangent of isotropic isochoric energies written in terms of `C = FᵀF`.
//!
//! Two routes share the push-forward `A_iJkL = δ_ik S_JL + F_iM ℂ_MJNL F_kN`:
//!
//! * **Invariants** (Mooney–Rivlin, neo-Hookean): `W = Ŵ(Ī1, Ī2)` with
//!   `Ī1 = J^{-2/3} I1`, `Ī2 = J^{-4/3} I2`, `I1 = tr C`, `I2 = ½(I1² − tr C²)`. With
//!   `G1 = ∂Ī1/∂C = J^{-2/3}(I − I1/3 C⁻¹)`, `G2 = ∂Ī2/∂C = J^{-4/3}(I1 I − C − 2/3 I2 C⁻¹)`:
//!   `S = 2(W1 G1 + W2 G2)`,
//!   `ℂ = 4(W1 H1 + W2 H2 + W11 G1⊗G1 + W12 (G1⊗G2 + G2⊗G1) + W22 G2⊗G2)`, where
//!   `H1 = −J^{-2/3}/3 [I⊗C⁻¹ + C⁻¹⊗I − I1/3 C⁻¹⊗C⁻¹ − I1 C⁻¹⊙C⁻¹]`,
//!   `H2 = J^{-4/3} [I⊗I − 𝕀 − 2/3 (I1 I − C)⊗C⁻¹ − 2/3 C⁻¹⊗(I1 I − C) + 4/9 I2 C⁻¹⊗C⁻¹ + 2/3 I2 C⁻¹⊙C⁻¹]`,
//!   `(X⊙Y)_IJKL = ½(X_IK Y_JL + X_IL Y_JK)` and `𝕀 = I⊙I`.
//! * **Principal values** (Ogden): `W = w(c1, c2, c3)` symmetric in the eigenvalues `c_a` of `C`
//!   with eigenvectors `n_a`, `N_a = n_a⊗n_a`, `M_ab = n_a⊗n_b + n_b⊗n_a`:
//!   `S = Σ S_a N_a`, `S_a = 2 ∂w/∂c_a`,
//!   `ℂ = Σ_ab 2 ∂S_a/∂c_b N_a⊗N_b + Σ_{a<b} θ_ab M_ab⊗M_ab`,
//!   `θ_ab = (S_a − S_b)/(c_a − c_b)`, replaced by its limit
//!   `½(∂S_a/∂c_a − ∂S_a/∂c_b + ∂S_b/∂c_b − ∂S_b/∂c_a)` when `|c_a − c_b| ≤ 10⁻⁶ max(c_a, c_b)`.
//!
//! Everything is fixed-size: no heap allocation.

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

/// Relative gap between principal values of `C` below which `θ_ab` uses its limit.
const COALESCENCE_TOL: f64 = 1e-6;

/// Iteration cap of the symmetric eigen solver (3×3 converges in a handful).
/// Fourth-order tangent as a 9×9 matrix: `A[(3*i + J, 3*k + L)] = ∂P_iJ / ∂F_kL`.
pub type Tangent9 = nalgebra::SMatrix<f64, 9, 9>;

const EIGEN_MAX_ITER: usize = 200;

/// `J = det F` and `F^{-T}` if `J > 0` and finite.
// public for the tests in tests/fe/
#[doc(hidden)]
pub fn jacobian_and_inverse_transpose(f: &Matrix3<f64>) -> Option<(f64, Matrix3<f64>)> {
    let j = f.determinant();
    if !(j.is_finite() && j > 0.0) {
        return None;
    }
    f.try_inverse().map(|inv| (j, inv.transpose()))
}

/// `J = det F` if it is finite and positive.
fn positive_jacobian(f: &Matrix3<f64>) -> Option<f64> {
    let j = f.determinant();
    (j.is_finite() && j > 0.0).then_some(j)
}

/// Fills stress and tangent with `NaN` (inadmissible `F`).
pub(crate) fn fill_nan(p: &mut Matrix3<f64>, a: Option<&mut Tangent9>) {
    p.fill(f64::NAN);
    if let Some(a) = a {
        a.fill(f64::NAN);
    }
}

/// `A_iJkL = δ_ik S_JL + F_iM ℂ_MJNL F_kN` and `P = F S`.
pub(crate) fn push_forward_into(
    f: &Matrix3<f64>,
    s: &Matrix3<f64>,
    cc: &Tangent9,
    p: &mut Matrix3<f64>,
    a: &mut Tangent9,
) {
    *p = f * s;
    // B[(3i + J, 3N + L)] = F_iM ℂ[(3M + J, 3N + L)]
    let mut b = Tangent9::zeros();
    for i in 0..3 {
        for jj in 0..3 {
            for col in 0..9 {
                b[(3 * i + jj, col)] = (0..3).map(|m| f[(i, m)] * cc[(3 * m + jj, col)]).sum();
            }
        }
    }
    for row in 0..9 {
        for k in 0..3 {
            for l in 0..3 {
                let geo = if row / 3 == k { s[(row % 3, l)] } else { 0.0 };
                a[(row, 3 * k + l)] =
                    geo + (0..3).map(|n| b[(row, 3 * n + l)] * f[(k, n)]).sum::<f64>();
            }
        }
    }
}

/// `cc += coef · X⊗Y`, `(X⊗Y)_IJKL = X_IJ Y_KL`.
fn add_outer(cc: &mut Tangent9, coef: f64, x: &Matrix3<f64>, y: &Matrix3<f64>) {
    if coef == 0.0 {
        return;
    }
    for r in 0..9 {
        let xr = coef * x[(r / 3, r % 3)];
        for c in 0..9 {
            cc[(r, c)] += xr * y[(c / 3, c % 3)];
        }
    }
}

/// `cc += coef · X⊙Y`, `(X⊙Y)_IJKL = ½(X_IK Y_JL + X_IL Y_JK)`.
fn add_sym_product(cc: &mut Tangent9, coef: f64, x: &Matrix3<f64>, y: &Matrix3<f64>) {
    if coef == 0.0 {
        return;
    }
    let h = 0.5 * coef;
    for (i, jj, k, l) in indices4() {
        cc[(3 * i + jj, 3 * k + l)] += h * (x[(i, k)] * y[(jj, l)] + x[(i, l)] * y[(jj, k)]);
    }
}

/// All index quadruples `(I, J, K, L)` in `0..3`.
fn indices4() -> impl Iterator<Item = (usize, usize, usize, usize)> {
    (0..81).map(|n| (n / 27, (n / 9) % 3, (n / 3) % 3, n % 3))
}

/// Kinematics of the invariant route.
pub(crate) struct IsoInvariants {
    c: Matrix3<f64>,
    c_inv: Matrix3<f64>,
    i1: f64,
    i2: f64,
    /// `J^{-2/3}`.
    r: f64,
    /// `Ī1 = J^{-2/3} I1`.
    pub i1b: f64,
    /// `Ī2 = J^{-4/3} I2`.
    pub i2b: f64,
}

impl IsoInvariants {
    /// Invariants of `C̄`, or `None` unless `det F > 0`.
    pub(crate) fn new(f: &Matrix3<f64>) -> Option<Self> {
        let j = positive_jacobian(f)?;
        let c = f.tr_mul(f);
        let c_inv = c.try_inverse()?;
        let i1 = c.trace();
        let i2 = 0.5 * (i1 * i1 - c.norm_squared());
        let r = j.powf(-2.0 / 3.0);
        Some(Self {
            c,
            c_inv,
            i1,
            i2,
            r,
            i1b: r * i1,
            i2b: r * r * i2,
        })
    }

    /// `G1 = ∂Ī1/∂C`.
    fn g1(&self) -> Matrix3<f64> {
        (Matrix3::identity() - self.c_inv * (self.i1 / 3.0)) * self.r
    }

    /// `G2 = ∂Ī2/∂C`.
    fn g2(&self) -> Matrix3<f64> {
        (Matrix3::identity() * self.i1 - self.c - self.c_inv * (2.0 * self.i2 / 3.0))
            * (self.r * self.r)
    }
}

/// Derivatives of `Ŵ(Ī1, Ī2)`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct InvariantDerivatives {
    /// `∂Ŵ/∂Ī1`.
    pub w1: f64,
    /// `∂Ŵ/∂Ī2`.
    pub w2: f64,
    /// `∂²Ŵ/∂Ī1²`.
    pub w11: f64,
    /// `∂²Ŵ/∂Ī1∂Ī2`.
    pub w12: f64,
    /// `∂²Ŵ/∂Ī2²`.
    pub w22: f64,
}

/// `P = F S`, `S = 2(W1 G1 + W2 G2)`.
pub(crate) fn invariant_stress_into(
    f: &Matrix3<f64>,
    inv: &IsoInvariants,
    d: &InvariantDerivatives,
    p: &mut Matrix3<f64>,
) {
    let mut s = inv.g1() * (2.0 * d.w1);
    if d.w2 != 0.0 {
        s += inv.g2() * (2.0 * d.w2);
    }
    *p = f * s;
}

/// Stress and tangent of the invariant route (see the module docs).
pub(crate) fn invariant_stress_tangent_into(
    f: &Matrix3<f64>,
    inv: &IsoInvariants,
    d: &InvariantDerivatives,
    p: &mut Matrix3<f64>,
    a: &mut Tangent9,
) {
    let id = Matrix3::identity();
    let ci = &inv.c_inv;
    let g1 = inv.g1();
    let mut cc = Tangent9::zeros();
    // 4 W1 H1
    let h1 = -4.0 * d.w1 * inv.r / 3.0;
    add_outer(&mut cc, h1, &id, ci);
    add_outer(&mut cc, h1, ci, &id);
    add_outer(&mut cc, -h1 * inv.i1 / 3.0, ci, ci);
    add_sym_product(&mut cc, -h1 * inv.i1, ci, ci);
    add_outer(&mut cc, 4.0 * d.w11, &g1, &g1);
    let mut s = g1 * (2.0 * d.w1);
    let second_invariant = d.w2 != 0.0 || d.w12 != 0.0 || d.w22 != 0.0;
    if second_invariant {
        let g2 = inv.g2();
        s += g2 * (2.0 * d.w2);
        // 4 W2 H2
        let h2 = 4.0 * d.w2 * inv.r * inv.r;
        let t = id * inv.i1 - inv.c;
        add_outer(&mut cc, h2, &id, &id);
        add_sym_product(&mut cc, -h2, &id, &id);
        add_outer(&mut cc, -h2 * 2.0 / 3.0, &t, ci);
        add_outer(&mut cc, -h2 * 2.0 / 3.0, ci, &t);
        add_outer(&mut cc, h2 * 4.0 / 9.0 * inv.i2, ci, ci);
        add_sym_product(&mut cc, h2 * 2.0 / 3.0 * inv.i2, ci, ci);
        add_outer(&mut cc, 4.0 * d.w12, &g1, &g2);
        add_outer(&mut cc, 4.0 * d.w12, &g2, &g1);
        add_outer(&mut cc, 4.0 * d.w22, &g2, &g2);
    }
    push_forward_into(f, &s, &cc, p, a);
}

/// Principal values `c_a` and eigenvectors (columns) of `C = FᵀF`, or `None` unless
/// `det F > 0` and all `c_a > 0`.
pub(crate) fn principal_frame(f: &Matrix3<f64>) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    positive_jacobian(f)?;
    let eig = SymmetricEigen::try_new(f.tr_mul(f), f64::EPSILON, EIGEN_MAX_ITER)?;
    eig.eigenvalues
        .iter()
        .all(|&c| c > 0.0 && c.is_finite())
        .then_some((eig.eigenvalues, eig.eigenvectors))
}

/// Principal values of `C = FᵀF` (see [`principal_frame`]).
pub(crate) fn principal_values(f: &Matrix3<f64>) -> Option<Vector3<f64>> {
    principal_frame(f).map(|(c, _)| c)
}

/// `S = Σ S_a n_a⊗n_a`.
pub(crate) fn spectral_stress(n: &Matrix3<f64>, s: &Vector3<f64>) -> Matrix3<f64> {
    let mut out = Matrix3::zeros();
    for a in 0..3 {
        let na = n.column(a);
        out += na * na.transpose() * s[a];
    }
    out
}

/// Material tangent `ℂ` of the principal-value route (see the module docs).
///
/// `ds[(a, b)] = ∂S_a/∂c_b`.
pub(crate) fn spectral_material_tangent(
    c: &Vector3<f64>,
    n: &Matrix3<f64>,
    s: &Vector3<f64>,
    ds: &Matrix3<f64>,
) -> Tangent9 {
    let mut cc = Tangent9::zeros();
    let proj: [Matrix3<f64>; 3] = core::array::from_fn(|a| n.column(a) * n.column(a).transpose());
    for a in 0..3 {
        for b in 0..3 {
            add_outer(&mut cc, 2.0 * ds[(a, b)], &proj[a], &proj[b]);
        }
    }
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let gap = c[a] - c[b];
        let theta = if gap.abs() <= COALESCENCE_TOL * c[a].max(c[b]) {
            0.5 * (ds[(a, a)] - ds[(a, b)] + ds[(b, b)] - ds[(b, a)])
        } else {
            (s[a] - s[b]) / gap
        };
        let nab = n.column(a) * n.column(b).transpose();
        let m = nab + nab.transpose();
        add_outer(&mut cc, theta, &m, &m);
    }
    cc
}
