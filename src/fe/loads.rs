//! External loads: follower pressure on cavity and duct surfaces, gravity.
//!
//! Follower pressure `p` on a face with current position `x(s, t)` (biquadratic, outward
//! tangents so that `x,s × x,t` points out of the solid, into the cavity):
//!
//! ```text
//!   f_a = −p ∫ N_a (x,s × x,t) ds dt          (pressure pushes the wall away from the cavity)
//!   ∂r_a/∂x_b = p ∫ N_a (N_b,t [x,s]× − N_b,s [x,t]×) ds dt       (r = f_int − f_ext)
//! ```
//!
//! The 3×3 Gauss rule integrates this exactly on a biquadratic face. Summed over a closed
//! cavity (or one closed by symmetry planes and clamped faces) the load stiffness is symmetric:
//! the load is conservative, with potential `−p V`.
//!
//! Gravity is a dead load `f_a = ∫ N_a ρ g dV`.

use super::element::{lagrange2, GAUSS3};

/// Shape functions of a 9-node face at (s, t) and their derivatives.
#[inline]
fn face_shape(s: f64, t: f64) -> ([f64; 9], [f64; 9], [f64; 9]) {
    let (ls, ds) = lagrange2(s);
    let (lt, dt) = lagrange2(t);
    let mut n = [0.0; 9];
    let mut ns = [0.0; 9];
    let mut nt = [0.0; 9];
    for j in 0..3 {
        for i in 0..3 {
            n[i + 3 * j] = ls[i] * lt[j];
            ns[i + 3 * j] = ds[i] * lt[j];
            nt[i + 3 * j] = ls[i] * dt[j];
        }
    }
    (n, ns, nt)
}

#[inline]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Residual contribution (27 → the face's 9 nodes, 27 values) and its tangent (27 × 27,
/// row-major) of a pressure `p` on a face with current nodal positions `x`.
///
/// Adds into `r` and, if given, `k`.
pub fn pressure_face(p: f64, x: &[[f64; 3]; 9], r: &mut [f64; 27], k: Option<&mut [f64; 729]>) {
    let mut kk = k;
    for (jt, &t) in GAUSS3.0.iter().enumerate() {
        for (js, &s) in GAUSS3.0.iter().enumerate() {
            let w = GAUSS3.1[js] * GAUSS3.1[jt];
            let (n, ns, nt) = face_shape(s, t);
            let mut xs = [0.0; 3];
            let mut xt = [0.0; 3];
            for a in 0..9 {
                for i in 0..3 {
                    xs[i] += ns[a] * x[a][i];
                    xt[i] += nt[a] * x[a][i];
                }
            }
            let nrm = cross(xs, xt);
            for a in 0..9 {
                for i in 0..3 {
                    r[3 * a + i] += p * w * n[a] * nrm[i];
                }
            }
            if let Some(k) = kk.as_deref_mut() {
                // [v]× as a matrix: ([v]× d)_i = (v × d)_i
                let skew =
                    |v: [f64; 3]| [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
                let sxs = skew(xs);
                let sxt = skew(xt);
                for a in 0..9 {
                    let pa = p * w * n[a];
                    for b in 0..9 {
                        for i in 0..3 {
                            for kc in 0..3 {
                                k[(3 * a + i) * 27 + 3 * b + kc] +=
                                    pa * (nt[b] * sxs[i][kc] - ns[b] * sxt[i][kc]);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Area-weighted normal integral ∫ x,s × x,t ds dt of a face (its vector area).
pub fn face_vector_area(x: &[[f64; 3]; 9]) -> [f64; 3] {
    let mut r = [0.0; 27];
    pressure_face(1.0, x, &mut r, None);
    let mut out = [0.0; 3];
    for a in 0..9 {
        for i in 0..3 {
            out[i] += r[3 * a + i];
        }
    }
    out
}

/// Volume enclosed between a face and the origin, (1/3) ∫ x · n da: summed over a closed
/// surface (or one closed by planes through the origin) it is the enclosed volume.
pub fn face_volume(x: &[[f64; 3]; 9]) -> f64 {
    let mut v = 0.0;
    for (jt, &t) in GAUSS3.0.iter().enumerate() {
        for (js, &s) in GAUSS3.0.iter().enumerate() {
            let w = GAUSS3.1[js] * GAUSS3.1[jt];
            let (n, ns, nt) = face_shape(s, t);
            let mut xq = [0.0; 3];
            let mut xs = [0.0; 3];
            let mut xt = [0.0; 3];
            for a in 0..9 {
                for i in 0..3 {
                    xq[i] += n[a] * x[a][i];
                    xs[i] += ns[a] * x[a][i];
                    xt[i] += nt[a] * x[a][i];
                }
            }
            let nrm = cross(xs, xt);
            v += w * (xq[0] * nrm[0] + xq[1] * nrm[1] + xq[2] * nrm[2]) / 3.0;
        }
    }
    v
}
