//! Contact of two facing faces across a gap between bellows: the gap between points of equal
//! reference position along the mid-surface normal, or to the closest point.

use serde::{Deserialize, Serialize};

use super::face::{face_points, FacePoint};
use super::law::barrier;
use crate::fe::contact_cp;
use crate::fe::element::lagrange2;

/// Penalty settings of deformable–deformable (bellow-to-bellow) contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairSettings {
    /// Penalty stiffness ε (MPa/mm).
    pub stiffness: f64,
    /// Smoothing width δ (mm).
    pub smoothing: f64,
    /// Gap to the closest point of the facing face ([`crate::fe::contact_cp`]: frictionless under
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
/// [`plane_face`](super::plane_face)).
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

/// [`pair_face`] with the closest-point gap ([`crate::fe::contact_cp`]). A quadrature point whose
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
