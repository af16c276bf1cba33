//! An elastic foundation on a set of faces: a compliant support instead of a rigid one.
//!
//! Each face point is tied to its reference position by springs per unit reference area,
//! one stiffness per global direction (MPa/mm = N/mm³):
//!
//! ```text
//!   Π_f = ½ Σ_i k_i ∫_A u_i² dA,     r_ai = k_i Σ_b M_ab u_bi,     K_ai,bj = δ_ij k_i M_ab,
//!   M_ab = ∫_A N_a N_b dA    (the face's reference "mass" matrix, 3×3 Gauss, exact)
//! ```
//!
//! The term is linear in `u`: the tangent is the constant matrix above. It models a clamp
//! that yields (the printed material squeezed between the clamp's jaws, the jaws themselves):
//! a traction `t_i = −k_i u_i` on the clamped face. A direction with `k_i = ∞` stays a
//! Dirichlet constraint instead (the caller keeps it constrained and passes `k_i = 0` here).

// Index loops mirror the local (node, component) layout.
#![allow(clippy::needless_range_loop)]

use super::term::{ElementContext, ElementTerm, LocalSystem};
use crate::fe::assembly::model::FeModel;
use crate::fe::element::{lagrange2, ElementError, GAUSS3};
use crate::fe::mesh::{face_local_nodes, Face};

/// Springs per unit area on faces, stored per element.
pub struct Foundation {
    /// Per element: the local node ids of each of its foundation faces.
    faces: Vec<Vec<[usize; 9]>>,
    /// Stiffness per unit area in x, y, z (MPa/mm).
    stiffness: [f64; 3],
}

impl Foundation {
    /// A foundation of stiffness `stiffness` (per direction, MPa/mm) on `faces` of a mesh of
    /// `n_elements` elements.
    pub fn new(n_elements: usize, faces: &[Face], stiffness: [f64; 3]) -> Self {
        let mut per = vec![Vec::new(); n_elements];
        for f in faces {
            per[f.element].push(face_local_nodes(f.axis, f.positive));
        }
        Self {
            faces: per,
            stiffness,
        }
    }

    /// `M_ab = ∫ N_a N_b dA` of a face with reference nodes `x` (biquadratic, 3×3 Gauss).
    pub fn face_mass(x: &[[f64; 3]; 9]) -> [[f64; 9]; 9] {
        let mut m = [[0.0; 9]; 9];
        for (jt, &t) in GAUSS3.0.iter().enumerate() {
            for (js, &s) in GAUSS3.0.iter().enumerate() {
                let w = GAUSS3.1[js] * GAUSS3.1[jt];
                let (ls, ds) = lagrange2(s);
                let (lt, dt) = lagrange2(t);
                let mut n = [0.0; 9];
                let (mut xs, mut xt) = ([0.0; 3], [0.0; 3]);
                for j in 0..3 {
                    for i in 0..3 {
                        let a = i + 3 * j;
                        n[a] = ls[i] * lt[j];
                        for c in 0..3 {
                            xs[c] += ds[i] * lt[j] * x[a][c];
                            xt[c] += ls[i] * dt[j] * x[a][c];
                        }
                    }
                }
                let cr = [
                    xs[1] * xt[2] - xs[2] * xt[1],
                    xs[2] * xt[0] - xs[0] * xt[2],
                    xs[0] * xt[1] - xs[1] * xt[0],
                ];
                let da = (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt() * w;
                for a in 0..9 {
                    for b in 0..9 {
                        m[a][b] += n[a] * n[b] * da;
                    }
                }
            }
        }
        m
    }
}

impl ElementTerm<FeModel> for Foundation {
    fn name(&self) -> &'static str {
        "foundation"
    }

    fn add(
        &self,
        _model: &FeModel,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError> {
        for lf in &self.faces[cx.element] {
            let x: [[f64; 3]; 9] = lf.map(|l| cx.nodes[cx.conn[l]]);
            let m = Self::face_mass(&x);
            let mut rf = [0.0; 27];
            let mut kf = [0.0; 729];
            for a in 0..9 {
                for b in 0..9 {
                    for i in 0..3 {
                        let kab = self.stiffness[i] * m[a][b];
                        rf[3 * a + i] += kab * cx.ue[lf[b]][i];
                        kf[(3 * a + i) * 27 + 3 * b + i] = kab;
                        if cx.with_energy {
                            local.energy += 0.5 * kab * cx.ue[lf[a]][i] * cx.ue[lf[b]][i];
                        }
                    }
                }
            }
            local.add_face(lf, &rf, cx.with_tangent.then_some(&kf));
        }
        Ok(())
    }
}
