//! The triquadratic hexahedron with a projected dilatation (Q2/P1-discontinuous).
//!
//! Kinematics: `F = I + ∇₀u`, `J = det F`, 27 Gauss points (3×3×3).
//!
//! Near-incompressibility is handled with the three-field Hu–Washizu / Simo–Taylor–Pister
//! formulation whose pressure and dilatation fields are linear and discontinuous per element
//! (`q = (1, X−X_c, Y−Y_c, Z−Z_c)/h`) and are condensed analytically:
//!
//! ```text
//!   θ = P₁[J]      (L²-projection on span q:  θ = qᵀ c,  M c = ∫ q J dV,  M = ∫ q qᵀ dV)
//!   Π_e(u) = ∫ W_iso(F) dV + ∫ U(θ) dV
//!   r_a = ∫ (P_iso + π J F⁻ᵀ) ∇₀N_a dV,          π = P₁[U'(θ)]   (projected pressure)
//!   K   = ∫ ∇₀N_a (A_iso + π J (F⁻ᵀ⊗F⁻ᵀ − F⁻ᵀ⊙F⁻ᵀ)) ∇₀N_b dV + Bᵀ M⁻¹ H M⁻¹ B
//!   B_l,(b,k) = ∫ q_l J F⁻ᵀ_kL ∂N_b/∂X_L dV,    H = ∫ U''(θ) q qᵀ dV
//! ```
//!
//! The element is free of volumetric locking (Q2/P1disc is inf-sup stable) and, being
//! quadratic, represents wall bending with one element through the thickness. The residual is
//! the exact gradient of `Π_e` and the tangent its exact Hessian (checked by finite differences).

// Index loops mirror the tensor index notation of the equations above (a, b: nodes;
// i, j, k, l: components); iterator chains would hide it.
#![allow(clippy::needless_range_loop)]

use std::sync::OnceLock;

use nalgebra::{Matrix3, Matrix4, Vector4};
use thiserror::Error;

use super::material::{Material, Tangent9};
use super::mesh::NODES_PER_ELEMENT;

/// Number of element degrees of freedom.
pub const DOFS: usize = 3 * NODES_PER_ELEMENT;
/// Quadrature points per element.
pub const QP: usize = 27;

/// Failures of an element evaluation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ElementError {
    /// det F ≤ 0 (or a non-positive projected dilatation) at a quadrature point.
    #[error("element {element}: inverted (J = {j:.3e} at quadrature point {qp})")]
    Inverted {
        /// Element id.
        element: usize,
        /// Quadrature point.
        qp: usize,
        /// The offending Jacobian.
        j: f64,
    },
    /// The reference element is degenerate.
    #[error("element {element}: degenerate reference geometry (det ∂X/∂ξ = {det:.3e})")]
    Degenerate {
        /// Element id.
        element: usize,
        /// Reference Jacobian.
        det: f64,
    },
}

/// 1D quadratic Lagrange basis on [−1, 1] (nodes −1, 0, 1) and its derivative.
#[inline]
pub fn lagrange2(x: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)],
        [x - 0.5, -2.0 * x, x + 0.5],
    )
}

/// Values and reference gradients of the 27 shape functions at ξ.
pub fn shape(xi: [f64; 3]) -> ([f64; 27], [[f64; 3]; 27]) {
    let (l0, d0) = lagrange2(xi[0]);
    let (l1, d1) = lagrange2(xi[1]);
    let (l2, d2) = lagrange2(xi[2]);
    let mut n = [0.0; 27];
    let mut dn = [[0.0; 3]; 27];
    for k in 0..3 {
        for j in 0..3 {
            for i in 0..3 {
                let a = i + 3 * j + 9 * k;
                n[a] = l0[i] * l1[j] * l2[k];
                dn[a] = [
                    d0[i] * l1[j] * l2[k],
                    l0[i] * d1[j] * l2[k],
                    l0[i] * l1[j] * d2[k],
                ];
            }
        }
    }
    (n, dn)
}

/// 3-point Gauss rule on [−1, 1].
pub const GAUSS3: ([f64; 3], [f64; 3]) = (
    [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4],
    [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0],
);

/// Shape-function table at the 27 Gauss points.
pub struct ShapeTable {
    /// Gauss points.
    pub xi: [[f64; 3]; QP],
    /// Weights.
    pub w: [f64; QP],
    /// N_a at each point.
    pub n: [[f64; 27]; QP],
    /// ∂N_a/∂ξ at each point.
    pub dn: [[[f64; 3]; 27]; QP],
}

/// The (lazily built) shape table.
pub fn table() -> &'static ShapeTable {
    static T: OnceLock<ShapeTable> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = ShapeTable {
            xi: [[0.0; 3]; QP],
            w: [0.0; QP],
            n: [[0.0; 27]; QP],
            dn: [[[0.0; 3]; 27]; QP],
        };
        for k in 0..3 {
            for j in 0..3 {
                for i in 0..3 {
                    let q = i + 3 * j + 9 * k;
                    t.xi[q] = [GAUSS3.0[i], GAUSS3.0[j], GAUSS3.0[k]];
                    t.w[q] = GAUSS3.1[i] * GAUSS3.1[j] * GAUSS3.1[k];
                    let (n, dn) = shape(t.xi[q]);
                    t.n[q] = n;
                    t.dn[q] = dn;
                }
            }
        }
        t
    })
}

/// Reference-configuration data of one element.
#[derive(Clone, Debug)]
pub struct ElementGeometry {
    /// ∂N_a/∂X at each quadrature point.
    pub dndx: Box<[[[f64; 3]; 27]; QP]>,
    /// Quadrature weight × det(∂X/∂ξ).
    pub wdet: [f64; QP],
    /// Projection basis q at each quadrature point.
    pub q: [[f64; 4]; QP],
    /// M⁻¹ of the projection basis.
    pub minv: Matrix4<f64>,
    /// ∫ N_a dV (for body loads).
    pub node_volume: [f64; 27],
}

impl ElementGeometry {
    /// Precomputes the reference data of an element from its node coordinates.
    ///
    /// # Errors
    /// [`ElementError::Degenerate`] if the reference mapping is not invertible.
    pub fn new(element: usize, x: &[[f64; 3]; 27]) -> Result<Self, ElementError> {
        let t = table();
        let mut dndx = Box::new([[[0.0; 3]; 27]; QP]);
        let mut wdet = [0.0; QP];
        let mut xq = [[0.0; 3]; QP];
        let mut node_volume = [0.0; 27];
        for q in 0..QP {
            let mut jac = Matrix3::zeros(); // ∂X_i/∂ξ_m
            for a in 0..27 {
                for i in 0..3 {
                    xq[q][i] += t.n[q][a] * x[a][i];
                    for m in 0..3 {
                        jac[(i, m)] += x[a][i] * t.dn[q][a][m];
                    }
                }
            }
            let det = jac.determinant();
            let inv = match jac.try_inverse() {
                Some(inv) if det > 0.0 => inv,
                _ => return Err(ElementError::Degenerate { element, det }),
            };
            wdet[q] = t.w[q] * det;
            for a in 0..27 {
                for jj in 0..3 {
                    dndx[q][a][jj] = (0..3).map(|m| t.dn[q][a][m] * inv[(m, jj)]).sum();
                }
                node_volume[a] += t.n[q][a] * wdet[q];
            }
        }
        let vol: f64 = wdet.iter().sum();
        let centre: [f64; 3] =
            std::array::from_fn(|i| (0..QP).map(|q| xq[q][i] * wdet[q]).sum::<f64>() / vol);
        let h = vol.cbrt();
        let mut qv = [[0.0; 4]; QP];
        let mut m = Matrix4::zeros();
        for q in 0..QP {
            qv[q] = [
                1.0,
                (xq[q][0] - centre[0]) / h,
                (xq[q][1] - centre[1]) / h,
                (xq[q][2] - centre[2]) / h,
            ];
            let v = Vector4::from(qv[q]);
            m += v * v.transpose() * wdet[q];
        }
        let minv = m.try_inverse().ok_or(ElementError::Degenerate {
            element,
            det: m.determinant(),
        })?;
        Ok(Self {
            dndx,
            wdet,
            q: qv,
            minv,
            node_volume,
        })
    }

    /// Reference volume.
    pub fn volume(&self) -> f64 {
        self.wdet.iter().sum()
    }
}

/// Per-thread work space of the element kernel (allocated once, reused).
pub struct ElementWork {
    /// Whether [`residual_tangent`] evaluates the strain energy (costs one more material
    /// evaluation per point; off in the Newton loop).
    pub with_energy: bool,
    /// Pressure coefficients used in the tangent's initial-stress term instead of the
    /// consistent ones (see [`linearised_pressure`]); `None` gives the exact Hessian.
    pub tangent_pressure: Option<[f64; 4]>,
    f: [Matrix3<f64>; QP],
    j: [f64; QP],
    /// Element residual (internal forces), length 81.
    pub r: Vec<f64>,
    /// Element tangent, row-major 81 × 81.
    pub k: Vec<f64>,
    b: Vec<[f64; DOFS]>,
    /// Per quadrature point: `g[(i, k, L)][a] = Σ_J ∂N_a/∂X_J Â[(3i+J), (3k+L)]`.
    g: Vec<[[f64; 27]; 27]>,
    /// Per quadrature point: `∂N_b/∂X_L` by `L`, contiguous in `b`.
    dt: Vec<[[f64; 27]; 3]>,
}

impl Default for ElementWork {
    fn default() -> Self {
        Self {
            with_energy: false,
            tangent_pressure: None,
            f: [Matrix3::zeros(); QP],
            j: [0.0; QP],
            r: vec![0.0; DOFS],
            k: vec![0.0; DOFS * DOFS],
            b: vec![[0.0; DOFS]; 4],
            g: vec![[[0.0; 27]; 27]; QP],
            dt: vec![[[0.0; 27]; 3]; QP],
        }
    }
}

/// Evaluates the internal-force residual (and optionally the tangent) of one element into
/// `work.r` / `work.k`; returns the element's strain energy if `work.with_energy` (else 0).
///
/// `u` are the element's nodal displacements in tensor order.
///
/// # Errors
/// [`ElementError::Inverted`] if det F ≤ 0 or the projected dilatation θ ≤ 0 anywhere.
pub fn residual_tangent(
    element: usize,
    geo: &ElementGeometry,
    u: &[[f64; 3]; 27],
    material: &Material,
    with_tangent: bool,
    work: &mut ElementWork,
) -> Result<f64, ElementError> {
    // Pass 1: deformation gradients, the projected dilatation and the projected pressure.
    let c = deformation_gradients(element, geo, u, work)?;
    let pressure = projected_pressure(element, geo, material, &c, with_tangent, work)?;

    // Pass 2: residual and tangent.
    work.clear(with_tangent);
    point_contributions(element, geo, material, &pressure, with_tangent, work)?;
    if with_tangent {
        upper_node_blocks(&geo.wdet, &work.g, &work.dt, &mut work.k);
        mirror_node_blocks(&mut work.k);
        add_volumetric_coupling(geo, pressure.h, &work.b, &mut work.k);
    }
    Ok(pressure.energy)
}

/// The projected pressure of pass 1 and what the tangent needs of it.
struct ProjectedPressure {
    /// Coefficients of `π = P₁[U'(θ)]` on the projection basis q.
    pi: Vector4<f64>,
    /// Coefficients of the pressure in the tangent's initial-stress term (`pi` unless
    /// [`ElementWork::tangent_pressure`] is set).
    pi_tangent: Vector4<f64>,
    /// `H = ∫ U''(θ) q qᵀ dV` (zero without the tangent).
    h: Matrix4<f64>,
    /// Strain energy of the element (zero unless [`ElementWork::with_energy`]).
    energy: f64,
}

impl ElementWork {
    /// Zeroes the residual and, with the tangent, the tangent and `B`.
    #[inline]
    fn clear(&mut self, with_tangent: bool) {
        self.r.iter_mut().for_each(|v| *v = 0.0);
        if with_tangent {
            self.k.iter_mut().for_each(|v| *v = 0.0);
            for row in self.b.iter_mut() {
                row.iter_mut().for_each(|v| *v = 0.0);
            }
        }
    }
}

/// `F` and `J = det F` at every point into `work`; returns the coefficients
/// `c = M⁻¹ ∫ q J dV` of the projected dilatation `θ = qᵀ c`.
#[inline]
fn deformation_gradients(
    element: usize,
    geo: &ElementGeometry,
    u: &[[f64; 3]; 27],
    work: &mut ElementWork,
) -> Result<Vector4<f64>, ElementError> {
    let mut bj = Vector4::zeros();
    for q in 0..QP {
        let f = deformation_gradient(&geo.dndx[q], u);
        let j = f.determinant();
        if j <= 0.0 || !j.is_finite() {
            return Err(ElementError::Inverted { element, qp: q, j });
        }
        work.f[q] = f;
        work.j[q] = j;
        bj += Vector4::from(geo.q[q]) * (j * geo.wdet[q]);
    }
    Ok(geo.minv * bj)
}

/// `F = I + Σ_a u_a ⊗ ∇₀N_a` at one point.
#[inline]
fn deformation_gradient(dndx: &[[f64; 3]; 27], u: &[[f64; 3]; 27]) -> Matrix3<f64> {
    let mut f: Matrix3<f64> = Matrix3::identity();
    for a in 0..27 {
        let d = &dndx[a];
        for i in 0..3 {
            for jj in 0..3 {
                f[(i, jj)] += u[a][i] * d[jj];
            }
        }
    }
    f
}

/// `π = M⁻¹ ∫ q U'(θ) dV` from the dilatation coefficients `c`, with `H` if the tangent is
/// wanted and the strain energy if `work.with_energy`.
#[inline]
fn projected_pressure(
    element: usize,
    geo: &ElementGeometry,
    material: &Material,
    c: &Vector4<f64>,
    with_tangent: bool,
    work: &ElementWork,
) -> Result<ProjectedPressure, ElementError> {
    let mut pv = Vector4::zeros();
    let mut h = Matrix4::zeros();
    let mut energy = 0.0;
    for q in 0..QP {
        let qv = Vector4::from(geo.q[q]);
        let theta = qv.dot(c);
        if theta <= 0.0 || !theta.is_finite() {
            return Err(ElementError::Inverted {
                element,
                qp: q,
                j: theta,
            });
        }
        pv += qv * (material.vol_pressure(theta) * geo.wdet[q]);
        if with_tangent {
            h += qv * qv.transpose() * (material.vol_stiffness(theta) * geo.wdet[q]);
        }
        if work.with_energy {
            energy += (material.vol_energy(theta) + material.iso_energy(&work.f[q])) * geo.wdet[q];
        }
    }
    let pi = geo.minv * pv;
    Ok(ProjectedPressure {
        pi,
        pi_tangent: work.tangent_pressure.map_or(pi, Vector4::from),
        h,
        energy,
    })
}

/// Pass 2 point by point: the stress `P_iso + π J F⁻ᵀ` into the residual; with the tangent,
/// each point's stiffness kernel (`g`, `dt`) and its share of `B`.
#[inline]
fn point_contributions(
    element: usize,
    geo: &ElementGeometry,
    material: &Material,
    pressure: &ProjectedPressure,
    with_tangent: bool,
    work: &mut ElementWork,
) -> Result<(), ElementError> {
    let mut p_iso = Matrix3::zeros();
    let mut a_iso = Tangent9::zeros();
    for q in 0..QP {
        let f = &work.f[q];
        let j = work.j[q];
        let finv_t = match f.try_inverse() {
            Some(m) => m.transpose(),
            None => return Err(ElementError::Inverted { element, qp: q, j }),
        };
        let cof = finv_t * j;
        let pi_q = Vector4::from(geo.q[q]).dot(&pressure.pi);
        if with_tangent {
            material.iso_stress_tangent_into(f, &mut p_iso, &mut a_iso);
        } else {
            material.iso_stress_into(f, &mut p_iso);
        }
        let stress = p_iso + cof * pi_q;
        let w = geo.wdet[q];
        let d = &geo.dndx[q];
        add_point_residual(w, &stress, d, &mut work.r);
        if !with_tangent {
            continue;
        }
        let s = Vector4::from(geo.q[q]).dot(&pressure.pi_tangent) * j;
        add_initial_stress(s, &finv_t, &mut a_iso);
        stiffness_kernel(d, &a_iso, &mut work.dt[q], &mut work.g[q]);
        add_dilatation_gradient(w, &cof, d, &geo.q[q], &mut work.b);
    }
    Ok(())
}

/// `r_(a,i) += w Σ_J P_iJ ∂N_a/∂X_J`.
#[inline]
fn add_point_residual(w: f64, stress: &Matrix3<f64>, d: &[[f64; 3]; 27], r: &mut [f64]) {
    for a in 0..27 {
        for i in 0..3 {
            r[3 * a + i] += w
                * (stress[(i, 0)] * d[a][0] + stress[(i, 1)] * d[a][1] + stress[(i, 2)] * d[a][2]);
        }
    }
}

/// `Â = A_iso + s (F⁻ᵀ_iJ F⁻ᵀ_kL − F⁻ᵀ_iL F⁻ᵀ_kJ)` in place, `s = π J`.
#[inline]
fn add_initial_stress(s: f64, finv_t: &Matrix3<f64>, a_hat: &mut Tangent9) {
    for i in 0..3 {
        for jj in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    a_hat[(3 * i + jj, 3 * k + l)] +=
                        s * (finv_t[(i, jj)] * finv_t[(k, l)] - finv_t[(i, l)] * finv_t[(k, jj)]);
                }
            }
        }
    }
}

/// One point's stiffness kernel, kept for [`upper_node_blocks`]: `dt[L][b] = ∂N_b/∂X_L` and
/// `g[(i, k, L)][a] = Σ_J ∂N_a/∂X_J Â[(3i+J), (3k+L)]`, both contiguous in the node.
#[inline]
fn stiffness_kernel(
    d: &[[f64; 3]; 27],
    a_hat: &Tangent9,
    dt: &mut [[f64; 27]; 3],
    g: &mut [[f64; 27]; 27],
) {
    for b in 0..27 {
        for l in 0..3 {
            dt[l][b] = d[b][l];
        }
    }
    for i in 0..3 {
        for k in 0..3 {
            for l in 0..3 {
                let c = 3 * k + l;
                let (a0, a1, a2) = (
                    a_hat[(3 * i, c)],
                    a_hat[(3 * i + 1, c)],
                    a_hat[(3 * i + 2, c)],
                );
                let g = &mut g[(3 * i + k) * 3 + l];
                for a in 0..27 {
                    g[a] = dt[0][a] * a0 + dt[1][a] * a1 + dt[2][a] * a2;
                }
            }
        }
    }
}

/// `B_l,(b,k) += w q_l Σ_L (J F⁻ᵀ)_kL ∂N_b/∂X_L`.
#[inline]
fn add_dilatation_gradient(
    w: f64,
    cof: &Matrix3<f64>,
    d: &[[f64; 3]; 27],
    qv: &[f64; 4],
    b_rows: &mut [[f64; DOFS]],
) {
    for b in 0..27 {
        for k in 0..3 {
            let v = w * (cof[(k, 0)] * d[b][0] + cof[(k, 1)] * d[b][1] + cof[(k, 2)] * d[b][2]);
            for l in 0..4 {
                b_rows[l][3 * b + k] += qv[l] * v;
            }
        }
    }
}

/// `K_(a,i),(b,k) = Σ_q w_q Σ_L g_q[(i,k,L)][a] ∂N_b/∂X_L` for the node blocks b ≥ a: one
/// row at a time over all points (the row stays in cache; the per-point terms are added in
/// point order, as a per-point accumulation would).
#[inline]
fn upper_node_blocks(
    wdet: &[f64; QP],
    g: &[[[f64; 27]; 27]],
    dt: &[[[f64; 27]; 3]],
    stiffness: &mut [f64],
) {
    for a in 0..27 {
        for i in 0..3 {
            for k in 0..3 {
                let gi = (3 * i + k) * 3;
                let mut acc = [0.0; 27];
                for q in 0..QP {
                    let w = wdet[q];
                    let g = &g[q];
                    let (g0, g1, g2) = (w * g[gi][a], w * g[gi + 1][a], w * g[gi + 2][a]);
                    let dt = &dt[q];
                    for b in a..27 {
                        acc[b] += g0 * dt[0][b] + g1 * dt[1][b] + g2 * dt[2][b];
                    }
                }
                let row = (3 * a + i) * DOFS;
                for b in a..27 {
                    stiffness[row + 3 * b + k] = acc[b];
                }
            }
        }
    }
}

/// The node blocks b < a from their mirror images (the tangent is symmetric).
#[inline]
fn mirror_node_blocks(stiffness: &mut [f64]) {
    for a in 0..27 {
        for b in (a + 1)..27 {
            for i in 0..3 {
                for k in 0..3 {
                    stiffness[(3 * b + k) * DOFS + 3 * a + i] =
                        stiffness[(3 * a + i) * DOFS + 3 * b + k];
                }
            }
        }
    }
}

/// The volumetric coupling `Bᵀ M⁻¹ H M⁻¹ B` added to the tangent.
#[inline]
fn add_volumetric_coupling(
    geo: &ElementGeometry,
    h: Matrix4<f64>,
    b_rows: &[[f64; DOFS]],
    stiffness: &mut [f64],
) {
    let c4 = geo.minv * h * geo.minv;
    let mut cb = [[0.0; DOFS]; 4];
    for l in 0..4 {
        for m in 0..4 {
            let cl = c4[(l, m)];
            if cl != 0.0 {
                for (dst, src) in cb[l].iter_mut().zip(b_rows[m].iter()) {
                    *dst += cl * src;
                }
            }
        }
    }
    for r in 0..DOFS {
        let row = r * DOFS;
        for l in 0..4 {
            let br = b_rows[l][r];
            if br == 0.0 {
                continue;
            }
            for (kv, cv) in stiffness[row..row + DOFS].iter_mut().zip(cb[l].iter()) {
                *kv += br * cv;
            }
        }
    }
}

/// The projected pressure linearised about `u` and evaluated at `u + du`:
///
/// ```text
///   θ_lin = θ(u) + M⁻¹ B(u) du,     π_lin = M⁻¹ ∫ q [U'(θ(u)) + U''(θ(u)) (θ_lin − θ(u))] dV
/// ```
///
/// This is the pressure that the mixed (u, θ, π) Newton iteration carries to its next iterate
/// (Simo–Taylor–Pister): the condensed residual is the same as that of the displacement-only
/// form, but the initial-stress term of the next tangent uses `π_lin` instead of the
/// consistent pressure `π(u + du)`. Along a linearised rotation `J` is violated at second
/// order and κ turns that into a spurious pressure in `π(u + du)` (of the order of μ0 for
/// rotations of a few degrees) that wrecks the bending stiffness of thin walls; `π_lin` does
/// not contain it.
///
/// # Errors
/// [`ElementError::Inverted`] if det F ≤ 0 at `u`.
pub fn linearised_pressure(
    element: usize,
    geo: &ElementGeometry,
    u: &[[f64; 3]; 27],
    du: &[[f64; 3]; 27],
    material: &Material,
) -> Result<[f64; 4], ElementError> {
    let mut bj = Vector4::zeros();
    let mut bdu = Vector4::zeros();
    for q in 0..QP {
        let mut f: Matrix3<f64> = Matrix3::identity();
        let mut g: Matrix3<f64> = Matrix3::zeros();
        for a in 0..27 {
            let d = &geo.dndx[q][a];
            for i in 0..3 {
                for jj in 0..3 {
                    f[(i, jj)] += u[a][i] * d[jj];
                    g[(i, jj)] += du[a][i] * d[jj];
                }
            }
        }
        let j = f.determinant();
        let finv = match f.try_inverse() {
            Some(m) if j > 0.0 && j.is_finite() => m,
            _ => return Err(ElementError::Inverted { element, qp: q, j }),
        };
        // dJ = J tr(F⁻¹ dF)
        let dj = j * (finv * g).trace();
        let qv = Vector4::from(geo.q[q]);
        bj += qv * (j * geo.wdet[q]);
        bdu += qv * (dj * geo.wdet[q]);
    }
    let c = geo.minv * bj;
    let dc = geo.minv * bdu;
    let mut pv = Vector4::zeros();
    for q in 0..QP {
        let qv = Vector4::from(geo.q[q]);
        let theta = qv.dot(&c);
        let dtheta = qv.dot(&dc);
        pv += qv
            * ((material.vol_pressure(theta) + material.vol_stiffness(theta) * dtheta)
                * geo.wdet[q]);
    }
    let pi = geo.minv * pv;
    Ok([pi[0], pi[1], pi[2], pi[3]])
}
