//! Closest-point (frictionless) gap of two facing 9-node faces.
//!
//! For a quadrature point `x_b` of the back face (parameters `ξ_b`), the closest point of the
//! front face (the same parametrisation, nodes matched to the back face's) solves
//!
//! ```text
//!   (x_f(ξ) − x_b) · ∂x_f/∂ξ_α = 0,   α = s, t          (Newton from ξ = ξ_b)
//!   n = ∂x_f/∂s × ∂x_f/∂t,   g = o (x_f(ξ*) − x_b) · n/|n|
//! ```
//!
//! At the closest point `x_f − x_b` is parallel to `n` and the tangents are normal to `n`, so
//! the variations of `ξ*` and of `n` drop out of the first variation:
//!
//! ```text
//!   δg = o n̂ · (Σ_a N_a(ξ*) δy_f,a − Σ_a N_a(ξ_b) δy_b,a)
//! ```
//!
//! The force is along the front face's normal: frictionless, whatever the sliding. The second
//! variation (the tangent) is the derivative of that gradient, taken in forward mode with dual
//! numbers through the projection (exact to rounding: the converged Newton iteration carries
//! the implicit derivative of `ξ*`).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Number of unknowns of a face pair (2 faces × 9 nodes × 3).
// public for the tests in tests/fe/
#[doc(hidden)]
pub const DOFS: usize = 54;

/// Forward-mode dual number `v + d ε`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dual {
    v: f64,
    d: f64,
}

/// The arithmetic the projection needs, for `f64` and [`Dual`].
// public for the tests in tests/fe/
#[doc(hidden)]
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn c(v: f64) -> Self;
    fn val(self) -> f64;
    fn sqrt(self) -> Self;
}

impl Scalar for f64 {
    fn c(v: f64) -> Self {
        v
    }
    fn val(self) -> f64 {
        self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}
impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}
impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        let v = self.v / o.v;
        Dual {
            v,
            d: (self.d - v * o.d) / o.v,
        }
    }
}
impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            v: -self.v,
            d: -self.d,
        }
    }
}
impl Scalar for Dual {
    fn c(v: f64) -> Self {
        Dual { v, d: 0.0 }
    }
    fn val(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let v = self.v.sqrt();
        Dual {
            v,
            d: 0.5 * self.d / v,
        }
    }
}

/// Quadratic Lagrange values, first and second derivatives at `x`.
fn lagrange<T: Scalar>(x: T) -> ([T; 3], [T; 3], [f64; 3]) {
    let h = T::c(0.5);
    let one = T::c(1.0);
    (
        [h * x * (x - one), one - x * x, h * x * (x + one)],
        [x - h, T::c(-2.0) * x, x + h],
        [1.0, -2.0, 1.0],
    )
}

fn dot<T: Scalar>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<T: Scalar>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The closest point of a front face: the shape functions there, the unit normal and the gap.
pub(crate) struct Projection<T> {
    /// Front shape functions at `ξ*`.
    pub n_front: [T; 9],
    /// Unit normal `n̂` (oriented by `o`).
    pub normal: [T; 3],
    /// Signed gap.
    pub gap: T,
}

/// Projects `x_b` onto the front face (nodes `yf`) by Newton from `xi0`; `None` if the
/// iteration does not converge (then the point is treated as open).
pub(crate) fn project<T: Scalar>(
    xb: [T; 3],
    yf: &[[T; 3]; 9],
    xi0: [f64; 2],
    orientation: f64,
) -> Option<Projection<T>> {
    let mut xi = [T::c(xi0[0]), T::c(xi0[1])];
    let mut extra = 0;
    for _ in 0..40 {
        let (ls, ds, dds) = lagrange(xi[0]);
        let (lt, dt, ddt) = lagrange(xi[1]);
        let zero = [T::c(0.0); 3];
        let (mut x, mut xs, mut xt, mut xss, mut xtt, mut xst) =
            (zero, zero, zero, zero, zero, zero);
        for j in 0..3 {
            for i in 0..3 {
                let y = yf[i + 3 * j];
                for c in 0..3 {
                    x[c] = x[c] + ls[i] * lt[j] * y[c];
                    xs[c] = xs[c] + ds[i] * lt[j] * y[c];
                    xt[c] = xt[c] + ls[i] * dt[j] * y[c];
                    xss[c] = xss[c] + T::c(dds[i]) * lt[j] * y[c];
                    xtt[c] = xtt[c] + ls[i] * T::c(ddt[j]) * y[c];
                    xst[c] = xst[c] + ds[i] * dt[j] * y[c];
                }
            }
        }
        let r = [x[0] - xb[0], x[1] - xb[1], x[2] - xb[2]];
        let f = [dot(r, xs), dot(r, xt)];
        let j11 = dot(xs, xs) + dot(r, xss);
        let j12 = dot(xs, xt) + dot(r, xst);
        let j22 = dot(xt, xt) + dot(r, xtt);
        let det = j11 * j22 - j12 * j12;
        if det.val().abs() < 1e-300 {
            return None;
        }
        let d0 = (j22 * f[0] - j12 * f[1]) / det;
        let d1 = (j11 * f[1] - j12 * f[0]) / det;
        let step = d0.val().abs().max(d1.val().abs());
        if step < 1e-12 || extra > 0 {
            // converged in value: two more steps carry the derivative to convergence
            extra += 1;
            if extra > 2 {
                let n = cross(xs, xt);
                let len = dot(n, n).sqrt();
                let o = T::c(orientation);
                let normal = [o * n[0] / len, o * n[1] / len, o * n[2] / len];
                let mut n_front = [T::c(0.0); 9];
                for j in 0..3 {
                    for i in 0..3 {
                        n_front[i + 3 * j] = ls[i] * lt[j];
                    }
                }
                return Some(Projection {
                    n_front,
                    normal,
                    gap: dot(r, normal),
                });
            }
        }
        xi = [xi[0] - d0, xi[1] - d1];
        if xi[0].val().abs() > 3.0 || xi[1].val().abs() > 3.0 {
            return None;
        }
    }
    None
}

/// Gap and its gradient with respect to the 54 nodal positions (back face first) for a back
/// point with shape functions `nb` at parameters `xi_b`.
// public for the tests in tests/fe/
#[doc(hidden)]
pub fn gap_gradient<T: Scalar>(
    nb: &[f64; 9],
    xi_b: [f64; 2],
    yb: &[[T; 3]; 9],
    yf: &[[T; 3]; 9],
    orientation: f64,
) -> Option<(T, [T; DOFS])> {
    let mut xb = [T::c(0.0); 3];
    for a in 0..9 {
        for c in 0..3 {
            xb[c] = xb[c] + T::c(nb[a]) * yb[a][c];
        }
    }
    let p = project(xb, yf, xi_b, orientation)?;
    let mut grad = [T::c(0.0); DOFS];
    for a in 0..9 {
        for c in 0..3 {
            grad[3 * a + c] = -(T::c(nb[a]) * p.normal[c]);
            grad[27 + 3 * a + c] = p.n_front[a] * p.normal[c];
        }
    }
    Some((p.gap, grad))
}

/// Gap, gradient and Hessian (row-major 54 × 54) at one back point; `None` if the projection
/// fails.
// public for the tests in tests/fe/
#[doc(hidden)]
pub fn gap_hessian(
    nb: &[f64; 9],
    xi_b: [f64; 2],
    yb: &[[f64; 3]; 9],
    yf: &[[f64; 3]; 9],
    orientation: f64,
    hess: &mut [f64; DOFS * DOFS],
) -> Option<(f64, [f64; DOFS])> {
    let (g, grad) = gap_gradient(nb, xi_b, yb, yf, orientation)?;
    let lift = |y: &[[f64; 3]; 9]| y.map(|p| p.map(Dual::c));
    for col in 0..DOFS {
        let (mut db, mut df) = (lift(yb), lift(yf));
        let (a, c) = ((col % 27) / 3, col % 3);
        if col < 27 {
            db[a][c].d = 1.0;
        } else {
            df[a][c].d = 1.0;
        }
        let (_, dgrad) = gap_gradient(nb, xi_b, &db, &df, orientation)?;
        for row in 0..DOFS {
            hess[row * DOFS + col] = dgrad[row].d;
        }
    }
    Some((g, grad))
}
