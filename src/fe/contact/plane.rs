//! Contact of a face with a rigid plane (the clamp block, the force plate).

use serde::{Deserialize, Serialize};

use super::face::{face_points, FacePoint};
use super::law::barrier;
use super::ContactError;

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

/// Contact of one 9-node face (reference coordinates `x0`, current `x`) with a plane: adds the
/// residual into `r` (27), the tangent into `k` (27 × 27 row-major) if given, and returns
/// (energy, normal reaction force on the body, smallest gap at a quadrature point). The
/// barrier of quadrature point `q` acts on `g − shift[q]` (the augmented-Lagrangian gap shift,
/// [`update_shift`](super::update_shift); zeros for the plain penalty).
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
