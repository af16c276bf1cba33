//! Frictionless contact of element faces with rigid planes (the clamp block, the force plate).
//!
//! Penalty with a C² barrier: with the signed gap `g = n·(x − x₀)` of a face quadrature point
//! (`n` the plane's unit normal pointing towards the body), the contact energy per reference area
//! is
//!
//! ```text
//!   ψ(g) = 0                                  g ≥ δ
//!   ψ(g) = ε (δ − g)³ / (6δ)                  0 ≤ g < δ
//!   ψ(g) = ε (δ²/6 − δ g/2 + g²/2)            g < 0
//! ```
//!
//! so the contact pressure `t = −ψ'(g)` rises smoothly from zero at `g = δ` and grows as `ε·(−g)`
//! in penetration, and the tangent `ψ''` is continuous: Newton sees no jump when contact opens
//! or closes. Residual and tangent of a face (3×3 Gauss points, reference area `dA₀`):
//!
//! ```text
//!   r_a = ∫ ψ'(g) N_a n dA₀          K_ab = ∫ ψ''(g) N_a N_b n⊗n dA₀
//! ```
//!
//! The plane's reaction on the body is `F = ∫ −ψ'(g) dA₀` along `n`.

// Index loops mirror the tensor notation of the equations (a, b: nodes; c, e: components).
#![allow(clippy::needless_range_loop)]

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::contact_cp;
use super::element::{lagrange2, GAUSS3};

/// Errors of contact settings.
#[derive(Debug, Error, PartialEq)]
pub enum ContactError {
    /// A setting out of range.
    #[error("contact setting {field} = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// Setting.
        field: &'static str,
        /// Value.
        value: f64,
        /// Allowed range.
        expected: String,
    },
    /// A contact pair couples two nodes that the sparse pattern does not.
    #[error("contact pair couples nodes {0} and {1}, which the sparse pattern does not hold")]
    MissingCoupling(usize, usize),
}

/// A rigid plane obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigidPlane {
    /// A point of the plane.
    pub point: [f64; 3],
    /// Unit normal pointing from the obstacle towards the body.
    pub normal: [f64; 3],
    /// Penalty stiffness ε (MPa/mm: contact pressure per mm of penetration).
    pub stiffness: f64,
    /// Smoothing width δ (mm): contact pressure starts at a gap δ.
    pub smoothing: f64,
}

impl RigidPlane {
    /// A validated plane.
    ///
    /// # Errors
    /// [`ContactError::OutOfRange`] for a zero normal, a non-positive stiffness or a negative
    /// smoothing width.
    pub fn new(
        point: [f64; 3],
        normal: [f64; 3],
        stiffness: f64,
        smoothing: f64,
    ) -> Result<Self, ContactError> {
        let len = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
        if !len.is_finite() || len < 1e-12 {
            return Err(ContactError::OutOfRange {
                field: "normal",
                value: len,
                expected: "a non-zero normal vector".into(),
            });
        }
        if !(stiffness.is_finite() && stiffness > 0.0) {
            return Err(ContactError::OutOfRange {
                field: "stiffness",
                value: stiffness,
                expected: "a finite positive penalty (MPa/mm)".into(),
            });
        }
        if !(smoothing.is_finite() && smoothing >= 0.0) {
            return Err(ContactError::OutOfRange {
                field: "smoothing",
                value: smoothing,
                expected: "a finite width ≥ 0 mm".into(),
            });
        }
        Ok(Self {
            point,
            normal: normal.map(|c| c / len),
            stiffness,
            smoothing,
        })
    }

    /// Signed gap of a point.
    pub fn gap(&self, x: [f64; 3]) -> f64 {
        (0..3)
            .map(|i| self.normal[i] * (x[i] - self.point[i]))
            .sum()
    }

    /// ψ(g), ψ'(g), ψ''(g) of the barrier.
    pub fn barrier(&self, g: f64) -> (f64, f64, f64) {
        barrier(self.stiffness, self.smoothing, g)
    }
}

/// ψ(g), ψ'(g), ψ''(g) of the C² penalty barrier with stiffness `e` and smoothing width `d`
/// (module docs).
pub fn barrier(e: f64, d: f64, g: f64) -> (f64, f64, f64) {
    if g >= d {
        (0.0, 0.0, 0.0)
    } else if g >= 0.0 {
        let s = d - g;
        (e * s * s * s / (6.0 * d), -e * s * s / (2.0 * d), e * s / d)
    } else {
        (
            e * (d * d / 6.0 - d * g / 2.0 + g * g / 2.0),
            e * (g - d / 2.0),
            e,
        )
    }
}

/// A Gauss point of a 9-node face: shape functions, their derivatives in the face's
/// parameters `s`, `t`, and the reference area element (with the quadrature weight).
struct FacePoint {
    xi: [f64; 2],
    na: [f64; 9],
    nas: [f64; 9],
    nat: [f64; 9],
    da: f64,
}

/// The 3×3 Gauss points of a 9-node face with reference coordinates `x0`.
fn face_points(x0: &[[f64; 3]; 9]) -> impl Iterator<Item = FacePoint> + '_ {
    (0..9).map(move |q| {
        let (js, jt) = (q % 3, q / 3);
        let (ls, ds) = lagrange2(GAUSS3.0[js]);
        let (lt, dt) = lagrange2(GAUSS3.0[jt]);
        let mut p = FacePoint {
            xi: [GAUSS3.0[js], GAUSS3.0[jt]],
            na: [0.0; 9],
            nas: [0.0; 9],
            nat: [0.0; 9],
            da: 0.0,
        };
        let (mut xs, mut xt) = ([0.0; 3], [0.0; 3]);
        for j in 0..3 {
            for i in 0..3 {
                let a = i + 3 * j;
                p.na[a] = ls[i] * lt[j];
                p.nas[a] = ds[i] * lt[j];
                p.nat[a] = ls[i] * dt[j];
                for c in 0..3 {
                    xs[c] += p.nas[a] * x0[a][c];
                    xt[c] += p.nat[a] * x0[a][c];
                }
            }
        }
        let cr = [
            xs[1] * xt[2] - xs[2] * xt[1],
            xs[2] * xt[0] - xs[0] * xt[2],
            xs[0] * xt[1] - xs[1] * xt[0],
        ];
        p.da = GAUSS3.1[js] * GAUSS3.1[jt] * (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt();
        p
    })
}

/// Contact of one 9-node face (reference coordinates `x0`, current `x`) with a plane: adds the
/// residual into `r` (27), the tangent into `k` (27 × 27 row-major) if given, and returns
/// (energy, normal reaction force on the body, smallest gap at a quadrature point). The
/// barrier of quadrature point `q` acts on `g − shift[q]` (the augmented-Lagrangian gap shift,
/// [`update_shift`]; zeros for the plain penalty).
pub fn plane_face(
    plane: &RigidPlane,
    x0: &[[f64; 3]; 9],
    x: &[[f64; 3]; 9],
    shift: &[f64; 9],
    r: &mut [f64; 27],
    k: Option<&mut [f64; 729]>,
) -> (f64, f64, f64) {
    plane_face_with(|g| plane.barrier(g), plane, x0, x, shift, r, k)
}

/// [`plane_face`] with another contact law `law(g) = (ψ, ψ', ψ'')` in place of the plane's
/// penalty (e.g. the log barrier of [`crate::fe::assembly::terms::barrier`]).
pub fn plane_face_with(
    law: impl Fn(f64) -> (f64, f64, f64),
    plane: &RigidPlane,
    x0: &[[f64; 3]; 9],
    x: &[[f64; 3]; 9],
    shift: &[f64; 9],
    r: &mut [f64; 27],
    mut k: Option<&mut [f64; 729]>,
) -> (f64, f64, f64) {
    let n = plane.normal;
    let mut energy = 0.0;
    let mut force = 0.0;
    let mut min_gap = f64::INFINITY;
    for (q, FacePoint { na, da, .. }) in face_points(x0).enumerate() {
        let mut xq = [0.0; 3];
        for a in 0..9 {
            for c in 0..3 {
                xq[c] += na[a] * x[a][c];
            }
        }
        let g = plane.gap(xq);
        min_gap = min_gap.min(g);
        let (psi, dpsi, ddpsi) = law(g - shift[q]);
        if dpsi == 0.0 && ddpsi == 0.0 {
            continue;
        }
        energy += psi * da;
        force -= dpsi * da;
        for a in 0..9 {
            for c in 0..3 {
                r[3 * a + c] += dpsi * na[a] * n[c] * da;
            }
        }
        if let Some(k) = k.as_deref_mut() {
            for a in 0..9 {
                for b in 0..9 {
                    let w = ddpsi * na[a] * na[b] * da;
                    for c in 0..3 {
                        for d in 0..3 {
                            k[(3 * a + c) * 27 + 3 * b + d] += w * n[c] * n[d];
                        }
                    }
                }
            }
        }
    }
    (energy, force, min_gap)
}

/// Penalty settings of deformable–deformable (bellow-to-bellow) contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairSettings {
    /// Penalty stiffness ε (MPa/mm).
    pub stiffness: f64,
    /// Smoothing width δ (mm).
    pub smoothing: f64,
    /// Gap to the closest point of the facing face ([`super::contact_cp`]: frictionless under
    /// any sliding) instead of between points of equal reference position.
    pub closest_point: bool,
}

/// Two facing 9-node faces across a gap whose nodes are matched by their reference position
/// in the gap plane: `back[a]` faces `front[a]`, both in the back face's tensor order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FacePair {
    /// Nodes of the face on the near side of the gap.
    pub back: [usize; 9],
    /// Nodes of the facing face, in the same order.
    pub front: [usize; 9],
    /// ±1: makes the gap positive for the reference configuration.
    pub orientation: f64,
}

/// Number of unknowns of a face pair (2 faces × 9 nodes × 3).
pub const PAIR_DOFS: usize = 54;

/// Second-order forward-mode number in the 9 variables `z = (d, t₁, t₂)` of the gap function.
#[derive(Clone, Copy)]
struct Hd {
    v: f64,
    g: [f64; 9],
    h: [[f64; 9]; 9],
}

impl Hd {
    fn var(v: f64, i: usize) -> Self {
        let mut g = [0.0; 9];
        g[i] = 1.0;
        Self {
            v,
            g,
            h: [[0.0; 9]; 9],
        }
    }
    fn add(&self, o: &Self) -> Self {
        let mut r = *self;
        r.v += o.v;
        for i in 0..9 {
            r.g[i] += o.g[i];
            for j in 0..9 {
                r.h[i][j] += o.h[i][j];
            }
        }
        r
    }
    fn sub(&self, o: &Self) -> Self {
        self.add(&o.scale(-1.0))
    }
    fn scale(&self, s: f64) -> Self {
        let mut r = *self;
        r.v *= s;
        for i in 0..9 {
            r.g[i] *= s;
            for j in 0..9 {
                r.h[i][j] *= s;
            }
        }
        r
    }
    fn mul(&self, o: &Self) -> Self {
        let mut r = Self {
            v: self.v * o.v,
            g: [0.0; 9],
            h: [[0.0; 9]; 9],
        };
        for i in 0..9 {
            r.g[i] = self.v * o.g[i] + o.v * self.g[i];
            for j in 0..9 {
                r.h[i][j] = self.v * o.h[i][j]
                    + o.v * self.h[i][j]
                    + self.g[i] * o.g[j]
                    + o.g[i] * self.g[j];
            }
        }
        r
    }
    /// `f(self)` from f, f', f'' at `self.v`.
    fn chain(&self, f: f64, df: f64, ddf: f64) -> Self {
        let mut r = Self {
            v: f,
            g: [0.0; 9],
            h: [[0.0; 9]; 9],
        };
        for i in 0..9 {
            r.g[i] = df * self.g[i];
            for j in 0..9 {
                r.h[i][j] = df * self.h[i][j] + ddf * self.g[i] * self.g[j];
            }
        }
        r
    }
}

/// Signed gap `G(z) = o · d·ν/|ν|`, `ν = t₁ × t₂`, with its gradient and Hessian in `z`.
fn gap_function(z: &[f64; 9], orientation: f64) -> Hd {
    let v: [Hd; 9] = std::array::from_fn(|i| Hd::var(z[i], i));
    let (d, t1, t2) = (&v[0..3], &v[3..6], &v[6..9]);
    let nu: [Hd; 3] = std::array::from_fn(|c| {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        t1[a].mul(&t2[b]).sub(&t1[b].mul(&t2[a]))
    });
    let nn = nu[0]
        .mul(&nu[0])
        .add(&nu[1].mul(&nu[1]))
        .add(&nu[2].mul(&nu[2]));
    let len = nn.v.sqrt();
    // 1/|ν| = (ν·ν)^(-1/2)
    let inv = nn.chain(
        1.0 / len,
        -0.5 / (len * len * len),
        0.75 / (len * len * len * len * len),
    );
    let dn = d[0]
        .mul(&nu[0])
        .add(&d[1].mul(&nu[1]))
        .add(&d[2].mul(&nu[2]));
    dn.mul(&inv).scale(orientation)
}

/// The variables `z = (d, t₁, t₂)` of the gap function at a face point with shape values `na`
/// and parameter derivatives `nas`, `nat`: `d = x_f − x_b`, `t = ∂m/∂s, ∂m/∂t` of the
/// mid-surface `m = (x_b + x_f)/2`.
fn gap_variables(
    na: &[f64; 9],
    nas: &[f64; 9],
    nat: &[f64; 9],
    x_back: &[[f64; 3]; 9],
    x_front: &[[f64; 3]; 9],
) -> [f64; 9] {
    let mut z = [0.0; 9];
    for a in 0..9 {
        for c in 0..3 {
            z[c] += na[a] * (x_front[a][c] - x_back[a][c]);
            z[3 + c] += 0.5 * nas[a] * (x_front[a][c] + x_back[a][c]);
            z[6 + c] += 0.5 * nat[a] * (x_front[a][c] + x_back[a][c]);
        }
    }
    z
}

/// Plain value of the gap function.
fn gap_value(z: &[f64; 9], orientation: f64) -> f64 {
    let nu = [
        z[4] * z[8] - z[5] * z[7],
        z[5] * z[6] - z[3] * z[8],
        z[3] * z[7] - z[4] * z[6],
    ];
    let len = (nu[0] * nu[0] + nu[1] * nu[1] + nu[2] * nu[2]).sqrt();
    orientation * (z[0] * nu[0] + z[1] * nu[1] + z[2] * nu[2]) / len
}

/// Contact of two facing faces (frictionless penalty with the C² barrier of the module docs).
///
/// At each 3×3 Gauss point of the back face's parametrisation the gap is measured between
/// the points of equal reference position on the two faces, along the normal of their
/// mid-surface:
///
/// ```text
///   d = x_f − x_b,   m = (x_b + x_f)/2,   ν = ∂m/∂s × ∂m/∂t,   g = o · d·ν/|ν|
///   Π_c = ∫ ψ(g) dA₀,   r = ∫ ψ'(g) ∂g/∂y dA₀,   K = ∫ (ψ''(g) ∂g⊗∂g + ψ'(g) ∂²g) dA₀
/// ```
///
/// with `y` the 54 nodal positions (back face first). Matching points by reference position
/// assumes small relative sliding of the facing walls, which holds for the bellows: they
/// bulge towards each other and bend together (the closest-point gap of
/// [`PairSettings::closest_point`] moves the tip by 0.01 % at 3 bar). `x0_back` are the back face's reference
/// coordinates, `x_back`, `x_front` the current ones. Adds into `r` (54) and `k` (54 × 54
/// row-major) and returns (energy, magnitude of the force the two faces exchange, smallest gap
/// at a quadrature point). The barrier of quadrature point `q` acts on `g − shift[q]` (see
/// [`plane_face`]).
#[allow(clippy::too_many_arguments)]
pub fn pair_face(
    settings: &PairSettings,
    orientation: f64,
    x0_back: &[[f64; 3]; 9],
    x_back: &[[f64; 3]; 9],
    x_front: &[[f64; 3]; 9],
    shift: &[f64; 9],
    r: &mut [f64; PAIR_DOFS],
    k: Option<&mut [f64; PAIR_DOFS * PAIR_DOFS]>,
) -> (f64, f64, f64) {
    let law = |g| barrier(settings.stiffness, settings.smoothing, g);
    pair_face_with(
        law,
        settings,
        orientation,
        x0_back,
        x_back,
        x_front,
        shift,
        r,
        k,
    )
}

/// [`pair_face`] with another contact law `law(g) = (ψ, ψ', ψ'')` in place of the pairs'
/// penalty (e.g. the log barrier of [`crate::fe::assembly::terms::barrier`]).
#[allow(clippy::too_many_arguments)]
pub fn pair_face_with(
    law: impl Fn(f64) -> (f64, f64, f64),
    settings: &PairSettings,
    orientation: f64,
    x0_back: &[[f64; 3]; 9],
    x_back: &[[f64; 3]; 9],
    x_front: &[[f64; 3]; 9],
    shift: &[f64; 9],
    r: &mut [f64; PAIR_DOFS],
    mut k: Option<&mut [f64; PAIR_DOFS * PAIR_DOFS]>,
) -> (f64, f64, f64) {
    if settings.closest_point {
        return pair_face_closest(&law, orientation, x0_back, x_back, x_front, shift, r, k);
    }
    let mut energy = 0.0;
    let mut front = [0.0; 3];
    let mut min_gap = f64::INFINITY;
    for (
        q,
        FacePoint {
            na, nas, nat, da, ..
        },
    ) in face_points(x0_back).enumerate()
    {
        let z = gap_variables(&na, &nas, &nat, x_back, x_front);
        let g0 = gap_value(&z, orientation);
        min_gap = min_gap.min(g0);
        let (psi, dpsi, ddpsi) = law(g0 - shift[q]);
        if dpsi == 0.0 && ddpsi == 0.0 {
            continue;
        }
        energy += psi * da;
        let g = gap_function(&z, orientation);
        // A = ∂z/∂y: per node a and side, coefficients of the (d, t₁, t₂) blocks
        let mut coef = [[0.0; 3]; 18];
        for a in 0..9 {
            coef[a] = [-na[a], 0.5 * nas[a], 0.5 * nat[a]];
            coef[9 + a] = [na[a], 0.5 * nas[a], 0.5 * nat[a]];
        }
        let mut dg = [0.0; PAIR_DOFS];
        for (n, cf) in coef.iter().enumerate() {
            for c in 0..3 {
                dg[3 * n + c] = cf[0] * g.g[c] + cf[1] * g.g[3 + c] + cf[2] * g.g[6 + c];
            }
        }
        for (ri, gi) in r.iter_mut().zip(&dg) {
            *ri += dpsi * gi * da;
        }
        for a in 0..9 {
            for c in 0..3 {
                front[c] += dpsi * dg[27 + 3 * a + c] * da;
            }
        }
        if let Some(k) = k.as_deref_mut() {
            for (n, cn) in coef.iter().enumerate() {
                for c in 0..3 {
                    let row = 3 * n + c;
                    for (m, cm) in coef.iter().enumerate() {
                        for e in 0..3 {
                            let col = 3 * m + e;
                            let mut h = 0.0;
                            for bi in 0..3 {
                                for bj in 0..3 {
                                    h += cn[bi] * cm[bj] * g.h[3 * bi + c][3 * bj + e];
                                }
                            }
                            k[row * PAIR_DOFS + col] += (ddpsi * dg[row] * dg[col] + dpsi * h) * da;
                        }
                    }
                }
            }
        }
    }
    let force = (front[0] * front[0] + front[1] * front[1] + front[2] * front[2]).sqrt();
    (energy, force, min_gap)
}

/// [`pair_face`] with the closest-point gap ([`super::contact_cp`]). A quadrature point whose
/// projection does not converge is open.
#[allow(clippy::too_many_arguments)]
fn pair_face_closest(
    law: &impl Fn(f64) -> (f64, f64, f64),
    orientation: f64,
    x0_back: &[[f64; 3]; 9],
    x_back: &[[f64; 3]; 9],
    x_front: &[[f64; 3]; 9],
    shift: &[f64; 9],
    r: &mut [f64; PAIR_DOFS],
    mut k: Option<&mut [f64; PAIR_DOFS * PAIR_DOFS]>,
) -> (f64, f64, f64) {
    let mut energy = 0.0;
    let mut front = [0.0; 3];
    let mut min_gap = f64::INFINITY;
    let mut hess = [0.0; PAIR_DOFS * PAIR_DOFS];
    for (q, FacePoint { xi, na, da, .. }) in face_points(x0_back).enumerate() {
        let Some((g, dg)) = contact_cp::gap_gradient(&na, xi, x_back, x_front, orientation) else {
            continue;
        };
        min_gap = min_gap.min(g);
        let (psi, dpsi, ddpsi) = law(g - shift[q]);
        if dpsi == 0.0 && ddpsi == 0.0 {
            continue;
        }
        energy += psi * da;
        for (ri, gi) in r.iter_mut().zip(&dg) {
            *ri += dpsi * gi * da;
        }
        for a in 0..9 {
            for c in 0..3 {
                front[c] += dpsi * dg[27 + 3 * a + c] * da;
            }
        }
        if let Some(k) = k.as_deref_mut() {
            if contact_cp::gap_hessian(&na, xi, x_back, x_front, orientation, &mut hess).is_none() {
                continue;
            }
            for row in 0..PAIR_DOFS {
                for col in 0..PAIR_DOFS {
                    k[row * PAIR_DOFS + col] +=
                        (ddpsi * dg[row] * dg[col] + dpsi * hess[row * PAIR_DOFS + col]) * da;
                }
            }
        }
    }
    let force = (front[0] * front[0] + front[1] * front[1] + front[2] * front[2]).sqrt();
    (energy, force, min_gap)
}

/// Gaps at the 3×3 quadrature points of a face against a plane (order of [`plane_face`]).
pub fn plane_face_gaps(plane: &RigidPlane, x0: &[[f64; 3]; 9], x: &[[f64; 3]; 9]) -> [f64; 9] {
    let mut gaps = [0.0; 9];
    for (q, FacePoint { na, .. }) in face_points(x0).enumerate() {
        let mut xq = [0.0; 3];
        for a in 0..9 {
            for c in 0..3 {
                xq[c] += na[a] * x[a][c];
            }
        }
        gaps[q] = plane.gap(xq);
    }
    gaps
}

/// Gaps at the 3×3 quadrature points of a face pair (order of [`pair_face`]); a closest-point
/// projection that fails gives an open point (`+∞`).
pub fn pair_face_gaps(
    settings: &PairSettings,
    orientation: f64,
    x0_back: &[[f64; 3]; 9],
    x_back: &[[f64; 3]; 9],
    x_front: &[[f64; 3]; 9],
) -> [f64; 9] {
    let mut gaps = [0.0; 9];
    for (
        q,
        FacePoint {
            xi, na, nas, nat, ..
        },
    ) in face_points(x0_back).enumerate()
    {
        gaps[q] = if settings.closest_point {
            contact_cp::gap_gradient(&na, xi, x_back, x_front, orientation)
                .map_or(f64::INFINITY, |(g, _)| g)
        } else {
            gap_value(
                &gap_variables(&na, &nas, &nat, x_back, x_front),
                orientation,
            )
        };
    }
    gaps
}

/// One Uzawa update of the augmented-Lagrangian gap shift of a contact point at a converged
/// state with gap `g` and shift `c`; returns the new shift and the change of the point's
/// multiplier (its contact pressure at `g = 0`) divided by ε, in mm.
///
/// The barrier acts on `g − c`, so the point carries the pressure `λ = P(g − c)`,
/// `P = −ψ'` (decreasing, zero from δ on). The shift stands for the multiplier `P(−c)`: the
/// pressure the point would carry when just touching. The update sets it to the pressure the
/// point carries now, `c ← −P⁻¹(λ) = c − g` for a point in contact, so that the same pressure
/// is reached at `g = 0`; an open point (`λ = 0`) gets `c = −δ`, the shift whose pressure
/// starts exactly at `g = 0`. At the fixed point every point either touches (`g = 0`,
/// `λ ≥ 0`) or is open without pressure, for any ε and δ: the penalty's offset from the true
/// contact (`δ/2 − λ/ε` for the plain penalty) is gone.
pub fn update_shift(stiffness: f64, smoothing: f64, g: f64, c: f64) -> (f64, f64) {
    let pressure = |x: f64| -barrier(stiffness, smoothing, x).1;
    let before = pressure(-c);
    let now = if g.is_finite() { pressure(g - c) } else { 0.0 };
    let c_new = if now > 0.0 { c - g } else { -smoothing };
    (c_new, (now - before).abs() / stiffness)
}

/// Gap at the centre of a face pair (current coordinates, back face's tensor order).
pub fn pair_centre_gap(orientation: f64, x_back: &[[f64; 3]; 9], x_front: &[[f64; 3]; 9]) -> f64 {
    let (ls, ds) = lagrange2(0.0);
    let mut z = [0.0; 9];
    for j in 0..3 {
        for i in 0..3 {
            let a = i + 3 * j;
            for c in 0..3 {
                z[c] += ls[i] * ls[j] * (x_front[a][c] - x_back[a][c]);
                z[3 + c] += 0.5 * ds[i] * ls[j] * (x_front[a][c] + x_back[a][c]);
                z[6 + c] += 0.5 * ls[i] * ds[j] * (x_front[a][c] + x_back[a][c]);
            }
        }
    }
    gap_value(&z, orientation)
}

/// The orientation (±1) that makes the gap of a pair positive in its reference state.
pub fn pair_orientation(x0_back: &[[f64; 3]; 9], x0_front: &[[f64; 3]; 9]) -> f64 {
    if pair_centre_gap(1.0, x0_back, x0_front) >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face(z: f64, tilt: f64) -> [[f64; 3]; 9] {
        std::array::from_fn(|a| {
            let (x, y) = ((a % 3) as f64, (a / 3) as f64);
            [x, y, z + tilt * x + 0.01 * (a as f64).sin()]
        })
    }

    #[test]
    fn uzawa_update_moves_the_pressure_to_zero_gap() {
        let (e, d) = (20.0, 0.05);
        let p = |x: f64| -barrier(e, d, x).1;
        // in penetration and in the smoothing zone: the same pressure is reached at g = 0
        for (g, c) in [(-0.03, 0.0), (0.02, 0.0), (-0.01, 0.04), (0.01, -0.02)] {
            let (c_new, change) = update_shift(e, d, g, c);
            assert!(
                (p(0.0 - c_new) - p(g - c)).abs() < 1e-12,
                "g = {g}, c = {c}"
            );
            assert!((change - (p(g - c) - p(-c)).abs() / e).abs() < 1e-15);
        }
        // open: the pressure starts exactly at g = 0
        let (c_new, _) = update_shift(e, d, 0.2, 0.0);
        assert_eq!(c_new, -d);
        assert_eq!(p(1e-9 - c_new), 0.0);
        assert!(p(-1e-3 - c_new) > 0.0);
        // a failed projection is open
        assert_eq!(update_shift(e, d, f64::INFINITY, 0.01).0, -d);
        // at the fixed point nothing changes
        let (c1, _) = update_shift(e, d, -0.02, 0.0);
        let (c2, change) = update_shift(e, d, 0.0, c1);
        assert_eq!((c1, change), (c2, 0.0));
    }

    #[test]
    fn barrier_is_c2() {
        let p = RigidPlane::new([0.0; 3], [0.0, 0.0, 1.0], 50.0, 0.1).unwrap();
        for g0 in [0.0, 0.1] {
            let (a, da, dda) = p.barrier(g0 - 1e-9);
            let (b, db, ddb) = p.barrier(g0 + 1e-9);
            assert!((a - b).abs() < 1e-6 && (da - db).abs() < 1e-6 && (dda - ddb).abs() < 1e-6);
        }
        let h = 1e-6;
        for g in [-0.3, -0.01, 0.02, 0.07] {
            let (_, d, dd) = p.barrier(g);
            let fd = (p.barrier(g + h).0 - p.barrier(g - h).0) / (2.0 * h);
            let fdd = (p.barrier(g + h).1 - p.barrier(g - h).1) / (2.0 * h);
            assert!((fd - d).abs() < 1e-6 * d.abs().max(1.0), "{g}");
            assert!((fdd - dd).abs() < 1e-6 * dd.abs().max(1.0), "{g}");
        }
    }

    #[test]
    fn face_residual_and_tangent_match_finite_differences() {
        let plane = RigidPlane::new([0.0, 0.0, 0.05], [0.0, 0.2, 1.0], 80.0, 0.05).unwrap();
        let x0 = face(0.0, 0.0);
        let x = face(0.02, -0.04);
        let mut r = [0.0; 27];
        let mut k = [0.0; 729];
        plane_face(&plane, &x0, &x, &[0.0; 9], &mut r, Some(&mut k));
        let h = 1e-7;
        for b in 0..9 {
            for d in 0..3 {
                let (mut xp, mut xm) = (x, x);
                xp[b][d] += h;
                xm[b][d] -= h;
                let (mut rp, mut rm) = ([0.0; 27], [0.0; 27]);
                let ep = plane_face(&plane, &x0, &xp, &[0.0; 9], &mut rp, None).0;
                let em = plane_face(&plane, &x0, &xm, &[0.0; 9], &mut rm, None).0;
                assert!(
                    ((ep - em) / (2.0 * h) - r[3 * b + d]).abs() < 1e-5,
                    "residual {b} {d}"
                );
                for row in 0..27 {
                    let fd = (rp[row] - rm[row]) / (2.0 * h);
                    assert!(
                        (fd - k[row * 27 + 3 * b + d]).abs() < 1e-4,
                        "tangent {row} {b} {d}"
                    );
                }
            }
        }
    }

    #[test]
    fn uniform_penetration_gives_pressure_times_area() {
        let plane = RigidPlane::new([0.0; 3], [0.0, 0.0, 1.0], 100.0, 0.0).unwrap();
        let x0 = std::array::from_fn(|a| [(a % 3) as f64, (a / 3) as f64, 0.0]);
        let x = x0.map(|p: [f64; 3]| [p[0], p[1], -0.01]);
        let mut r = [0.0; 27];
        let (_, f, g) = plane_face(&plane, &x0, &x, &[0.0; 9], &mut r, None);
        // 2 × 2 mm face, 0.01 mm penetration, 100 MPa/mm → 1 MPa × 4 mm² = 4 N
        assert!((f - 4.0).abs() < 1e-12, "{f}");
        assert!((g + 0.01).abs() < 1e-15);
        let rz: f64 = (0..9).map(|a| r[3 * a + 2]).sum();
        assert!((rz + 4.0).abs() < 1e-12);
    }

    #[test]
    fn bad_settings_are_named() {
        let e = RigidPlane::new([0.0; 3], [0.0; 3], 1.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("normal"));
        let e = RigidPlane::new([0.0; 3], [0.0, 0.0, 1.0], -1.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("stiffness = -1"));
    }

    #[test]
    fn pair_residual_and_tangent_match_finite_differences() {
        let set = PairSettings {
            stiffness: 60.0,
            smoothing: 0.2,
            closest_point: false,
        };
        let x0b = face(0.0, 0.0);
        let x0f = face(1.0, 0.0);
        let o = pair_orientation(&x0b, &x0f);
        assert_eq!(o, 1.0);
        // bulged, rotated walls: some points in penetration, some within δ, some open
        let xb: [[f64; 3]; 9] = std::array::from_fn(|a| {
            let p = x0b[a];
            [
                p[0] + 0.02 * p[1],
                p[1] - 0.03 * p[2],
                p[2] + 0.9 + 0.05 * (a as f64).cos(),
            ]
        });
        let xf: [[f64; 3]; 9] = std::array::from_fn(|a| {
            let p = x0f[a];
            [
                p[0] - 0.01,
                p[1] + 0.02 * p[0],
                p[2] - 0.05 * p[0] + 0.03 * (a as f64).sin(),
            ]
        });
        let mut r = [0.0; PAIR_DOFS];
        let mut k = [0.0; PAIR_DOFS * PAIR_DOFS];
        let (_, f, g) = pair_face(&set, o, &x0b, &xb, &xf, &[0.0; 9], &mut r, Some(&mut k));
        assert!(
            f > 0.0 && g < 0.0,
            "the test state must be in contact: f {f}, g {g}"
        );
        let eval = |xb: &[[f64; 3]; 9], xf: &[[f64; 3]; 9]| {
            let mut r = [0.0; PAIR_DOFS];
            let e = pair_face(&set, o, &x0b, xb, xf, &[0.0; 9], &mut r, None).0;
            (e, r)
        };
        let h = 1e-6;
        let (mut max_r, mut max_k) = (0.0f64, 0.0f64);
        for col in 0..PAIR_DOFS {
            let (node, c) = (col / 3, col % 3);
            let (mut bp, mut bm, mut fp, mut fm) = (xb, xb, xf, xf);
            if node < 9 {
                bp[node][c] += h;
                bm[node][c] -= h;
            } else {
                fp[node - 9][c] += h;
                fm[node - 9][c] -= h;
            }
            let (ep, rp) = eval(&bp, &fp);
            let (em, rm) = eval(&bm, &fm);
            max_r = max_r.max(((ep - em) / (2.0 * h) - r[col]).abs());
            for row in 0..PAIR_DOFS {
                let fd = (rp[row] - rm[row]) / (2.0 * h);
                max_k = max_k.max((fd - k[row * PAIR_DOFS + col]).abs());
            }
        }
        let scale_r = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let scale_k = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            max_r < 1e-6 * scale_r,
            "residual error {max_r} (scale {scale_r})"
        );
        assert!(
            max_k < 1e-5 * scale_k,
            "tangent error {max_k} (scale {scale_k})"
        );
    }

    #[test]
    fn parallel_walls_pressed_together_carry_pressure_times_area() {
        let set = PairSettings {
            stiffness: 100.0,
            smoothing: 0.0,
            closest_point: false,
        };
        let x0b = std::array::from_fn(|a| [(a % 3) as f64, (a / 3) as f64, 0.0]);
        let x0f = x0b.map(|p: [f64; 3]| [p[0], p[1], 1.0]);
        // the front wall moved 1.01 towards the back one and slid sideways by 0.3: 0.01 mm
        // penetration, 1 MPa over 4 mm², no tangential force
        let xf = x0f.map(|p| [p[0] + 0.3, p[1], p[2] - 1.01]);
        let mut r = [0.0; PAIR_DOFS];
        let o = pair_orientation(&x0b, &x0f);
        let (_, f, g) = pair_face(&set, o, &x0b, &x0b, &xf, &[0.0; 9], &mut r, None);
        assert!((f - 4.0).abs() < 1e-10, "{f}");
        assert!((g + 0.01).abs() < 1e-12, "{g}");
        let sum = |side: usize, c: usize| (0..9).map(|a| r[27 * side + 3 * a + c]).sum::<f64>();
        assert!((sum(0, 2) - 4.0).abs() < 1e-10 && (sum(1, 2) + 4.0).abs() < 1e-10);
        for side in 0..2 {
            assert!(sum(side, 0).abs() < 1e-12 && sum(side, 1).abs() < 1e-12);
        }
    }
}
