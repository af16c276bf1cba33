//! The clamp's compliance at its neutral value: the rigid clamp's limit.
//!
//! With a compliance `c > 0` the clamped face is held by springs of stiffness `1/c` per unit
//! area ([`crate::fe::assembly::terms::foundation`]), and at equilibrium the face's nodes
//! carry `R_s(u) + (1/c) M u_s = 0`, `R_s` the body's residual there (the reactions of the
//! rigid clamp), `M_ab = ∫ N_a N_b dA` the face's mass matrix. As `c → 0`,
//!
//! ```text
//!   u_s = −c M⁻¹ R_s + O(c²),       du_s/dc = −M⁻¹ R_s   (at c = 0),
//! ```
//!
//! and the free unknowns follow from `K_ff du_f = −K_fs du_s`, the product `K_fs du_s` being
//! the residual's directional difference along `du_s`. `M` is solved by conjugate gradients
//! (it is symmetric positive definite and well conditioned).

use std::collections::HashMap;

use crate::fe::assembly::terms::foundation::Foundation;
use crate::fe::simulate::ActuatorModel;

/// Largest conjugate-gradient iterations for the face's mass matrix.
const CG_ITERATIONS: usize = 2000;

/// The face's mass matrix did not solve: its size and the iterations spent.
#[derive(Debug)]
pub(super) struct NotSolved {
    /// Nodes of the face.
    pub(super) nodes: usize,
    /// Conjugate-gradient iterations spent.
    pub(super) iterations: usize,
}

/// The clamped face's mass matrix on its nodes.
pub(super) struct ClampFace {
    /// Global node of each local index.
    nodes: Vec<usize>,
    /// Rows of `M` (local index, value).
    rows: Vec<Vec<(usize, f64)>>,
    /// Whether node `i` is on the symmetry plane (its `x` stays held).
    on_symmetry: Vec<bool>,
}

impl ClampFace {
    /// The clamped face of `model`.
    pub(super) fn new(model: &ActuatorModel) -> Self {
        let faces = model.mesh.clamped_faces();
        let mut index: HashMap<usize, usize> = HashMap::new();
        let mut nodes = Vec::new();
        let mut entries: Vec<HashMap<usize, f64>> = Vec::new();
        for f in &faces {
            let x = f.nodes.map(|n| model.fe.mesh.nodes[n]);
            let m = Foundation::face_mass(&x);
            let local = f.nodes.map(|n| {
                *index.entry(n).or_insert_with(|| {
                    nodes.push(n);
                    entries.push(HashMap::new());
                    nodes.len() - 1
                })
            });
            for a in 0..9 {
                for b in 0..9 {
                    *entries[local[a]].entry(local[b]).or_insert(0.0) += m[a][b];
                }
            }
        }
        let rows = entries
            .into_iter()
            .map(|r| {
                let mut v: Vec<_> = r.into_iter().collect();
                v.sort_unstable_by_key(|&(j, _)| j);
                v
            })
            .collect();
        let symmetric: std::collections::HashSet<usize> =
            model.mesh.symmetry.iter().copied().collect();
        let on_symmetry = nodes.iter().map(|n| symmetric.contains(n)).collect();
        Self {
            nodes,
            rows,
            on_symmetry,
        }
    }

    /// `du_s/dc` on every dof of the face in the directions `comps` (the full vector's
    /// entries, zero elsewhere): `−M⁻¹ R_s` per direction, from the reactions in `r_full`.
    /// Only dofs the rigid model holds move (`x` stays held on the symmetry plane).
    ///
    /// # Errors
    /// [`NotSolved`] if the conjugate gradients do not converge.
    pub(super) fn face_motion(
        &self,
        model: &ActuatorModel,
        r_full: &[f64],
        comps: [bool; 3],
        out: &mut [f64],
    ) -> Result<(), NotSolved> {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (c, _) in comps.iter().enumerate().filter(|(_, on)| **on) {
            let active: Vec<bool> = self
                .nodes
                .iter()
                .zip(&self.on_symmetry)
                .map(|(&n, &sym)| model.fe.dofs.eq(3 * n + c).is_none() && !(c == 0 && sym))
                .collect();
            let b: Vec<f64> = self
                .nodes
                .iter()
                .zip(&active)
                .map(|(&n, &a)| if a { r_full[3 * n + c] } else { 0.0 })
                .collect();
            let w = self.solve(&active, &b)?;
            for (i, &n) in self.nodes.iter().enumerate() {
                if active[i] {
                    out[3 * n + c] = -w[i];
                }
            }
        }
        Ok(())
    }

    /// `M_aa w = b` on the active nodes (Jacobi-preconditioned conjugate gradients).
    fn solve(&self, active: &[bool], b: &[f64]) -> Result<Vec<f64>, NotSolved> {
        let n = self.nodes.len();
        let apply = |x: &[f64], y: &mut [f64]| {
            for i in 0..n {
                y[i] = if active[i] {
                    self.rows[i]
                        .iter()
                        .filter(|(j, _)| active[*j])
                        .map(|(j, m)| m * x[*j])
                        .sum()
                } else {
                    0.0
                };
            }
        };
        let diag: Vec<f64> = (0..n)
            .map(|i| {
                self.rows[i]
                    .iter()
                    .find(|(j, _)| *j == i)
                    .map_or(0.0, |(_, m)| *m)
            })
            .collect();
        let precondition = |r: &[f64], z: &mut [f64]| {
            for i in 0..n {
                z[i] = if active[i] && diag[i] > 0.0 {
                    r[i] / diag[i]
                } else {
                    0.0
                };
            }
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut x = vec![0.0; n];
        let mut r = b.to_vec();
        let norm_b = dot(b, b).sqrt();
        if norm_b == 0.0 {
            return Ok(x);
        }
        let mut z = vec![0.0; n];
        precondition(&r, &mut z);
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        let mut q = vec![0.0; n];
        for _ in 0..CG_ITERATIONS {
            apply(&p, &mut q);
            let alpha = rz / dot(&p, &q);
            for i in 0..n {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
            }
            if dot(&r, &r).sqrt() <= 1e-13 * norm_b {
                return Ok(x);
            }
            precondition(&r, &mut z);
            let rz_new = dot(&r, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        Err(NotSolved {
            nodes: n,
            iterations: CG_ITERATIONS,
        })
    }
}
