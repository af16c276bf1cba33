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

use serde::{Deserialize, Serialize};
use thiserror::Error;

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
        let (e, d) = (self.stiffness, self.smoothing);
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
}

/// Contact of one 9-node face (reference coordinates `x0`, current `x`) with a plane: adds the
/// residual into `r` (27), the tangent into `k` (27 × 27 row-major) if given, and returns
/// (energy, normal reaction force on the body, smallest gap at a quadrature point).
pub fn plane_face(
    plane: &RigidPlane,
    x0: &[[f64; 3]; 9],
    x: &[[f64; 3]; 9],
    r: &mut [f64; 27],
    mut k: Option<&mut [f64; 729]>,
) -> (f64, f64, f64) {
    let n = plane.normal;
    let mut energy = 0.0;
    let mut force = 0.0;
    let mut min_gap = f64::INFINITY;
    for (jt, &t) in GAUSS3.0.iter().enumerate() {
        for (js, &s) in GAUSS3.0.iter().enumerate() {
            let (ls, ds) = lagrange2(s);
            let (lt, dt) = lagrange2(t);
            let mut na = [0.0; 9];
            let mut xs = [0.0; 3];
            let mut xt = [0.0; 3];
            let mut xq = [0.0; 3];
            for j in 0..3 {
                for i in 0..3 {
                    let a = i + 3 * j;
                    na[a] = ls[i] * lt[j];
                    for c in 0..3 {
                        xs[c] += ds[i] * lt[j] * x0[a][c];
                        xt[c] += ls[i] * dt[j] * x0[a][c];
                        xq[c] += na[a] * x[a][c];
                    }
                }
            }
            let cr = [
                xs[1] * xt[2] - xs[2] * xt[1],
                xs[2] * xt[0] - xs[0] * xt[2],
                xs[0] * xt[1] - xs[1] * xt[0],
            ];
            let da = GAUSS3.1[js]
                * GAUSS3.1[jt]
                * (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt();
            let g = plane.gap(xq);
            min_gap = min_gap.min(g);
            let (psi, dpsi, ddpsi) = plane.barrier(g);
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
    }
    (energy, force, min_gap)
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
        plane_face(&plane, &x0, &x, &mut r, Some(&mut k));
        let h = 1e-7;
        for b in 0..9 {
            for d in 0..3 {
                let (mut xp, mut xm) = (x, x);
                xp[b][d] += h;
                xm[b][d] -= h;
                let (mut rp, mut rm) = ([0.0; 27], [0.0; 27]);
                let ep = plane_face(&plane, &x0, &xp, &mut rp, None).0;
                let em = plane_face(&plane, &x0, &xm, &mut rm, None).0;
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
        let (_, f, g) = plane_face(&plane, &x0, &x, &mut r, None);
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
}
