//! The 3×3 Gauss points of a 9-node face.

use crate::fe::element::{lagrange2, GAUSS3};

/// A Gauss point of a 9-node face: shape functions, their derivatives in the face's
/// parameters `s`, `t`, and the reference area element (with the quadrature weight).
pub(super) struct FacePoint {
    pub(super) xi: [f64; 2],
    pub(super) na: [f64; 9],
    pub(super) nas: [f64; 9],
    pub(super) nat: [f64; 9],
    pub(super) da: f64,
}

/// The 3×3 Gauss points of a 9-node face with reference coordinates `x0`.
pub(super) fn face_points(x0: &[[f64; 3]; 9]) -> impl Iterator<Item = FacePoint> + '_ {
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
