//! Cubic Hermite interpolation in pressure: the weights of the nodes around a pressure.

/// Cubic Hermite interpolation weights on a pressure grid: `y(P) = Σ_{i<len} w[i] y[start + i]`,
/// `dy/dP = Σ dw[i] y[start + i]`. Slopes at the nodes are 3-point finite differences
/// (one-sided at the ends), so the weights are linear in the nodal values. `P` is clamped to
/// the grid (zero derivative outside).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stencil<F> {
    /// First node of the stencil.
    pub start: usize,
    /// Number of nodes used (2..=4).
    pub len: usize,
    /// Weights.
    pub w: [F; 4],
    /// Derivatives of the weights with respect to `P`.
    pub dw: [F; 4],
}

/// Slope weights at node `j`: `m_j = Σ c[i] y[j0 + i]`.
fn slope_weights(grid: &[f64], j: usize) -> (usize, [f64; 3], usize) {
    let n = grid.len();
    if n == 2 {
        let h = grid[1] - grid[0];
        return (0, [-1.0 / h, 1.0 / h, 0.0], 2);
    }
    if j == 0 {
        let (h1, h2) = (grid[1] - grid[0], grid[2] - grid[1]);
        let c0 = -(2.0 * h1 + h2) / (h1 * (h1 + h2));
        let c1 = (h1 + h2) / (h1 * h2);
        let c2 = -h1 / (h2 * (h1 + h2));
        return (0, [c0, c1, c2], 3);
    }
    if j == n - 1 {
        let (h1, h2) = (grid[n - 2] - grid[n - 3], grid[n - 1] - grid[n - 2]);
        let c0 = h2 / (h1 * (h1 + h2));
        let c1 = -(h1 + h2) / (h1 * h2);
        let c2 = (2.0 * h2 + h1) / (h2 * (h1 + h2));
        return (n - 3, [c0, c1, c2], 3);
    }
    let (hl, hr) = (grid[j] - grid[j - 1], grid[j + 1] - grid[j]);
    let c0 = -hr / (hl * (hl + hr));
    let c1 = (hr - hl) / (hl * hr);
    let c2 = hl / (hr * (hl + hr));
    (j - 1, [c0, c1, c2], 3)
}

/// Hermite stencil at pressure `p` on the sorted grid (at least 2 nodes), computed in `f64`.
pub fn stencil(grid: &[f64], p: f64) -> Stencil<f64> {
    let n = grid.len();
    let (p, inside) = if p <= grid[0] {
        (grid[0], false)
    } else if p >= grid[n - 1] {
        (grid[n - 1], false)
    } else {
        (p, true)
    };
    let mut i = 0;
    while i + 2 < n && p >= grid[i + 1] {
        i += 1;
    }
    let h = grid[i + 1] - grid[i];
    let s = (p - grid[i]) / h;
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    let d00 = (6.0 * s2 - 6.0 * s) / h;
    let d10 = (3.0 * s2 - 4.0 * s + 1.0) / h;
    let d01 = (-6.0 * s2 + 6.0 * s) / h;
    let d11 = (3.0 * s2 - 2.0 * s) / h;
    let start = i.saturating_sub(1).min(n.saturating_sub(4));
    let len = (n - start).min(4);
    let mut st = Stencil {
        start,
        len,
        w: [0.0; 4],
        dw: [0.0; 4],
    };
    st.w[i - start] += h00;
    st.w[i + 1 - start] += h01;
    st.dw[i - start] += d00;
    st.dw[i + 1 - start] += d01;
    for (node, hv, dv) in [(i, h10 * h, d10 * h), (i + 1, h11 * h, d11 * h)] {
        let (j0, c, len_c) = slope_weights(grid, node);
        let mut k = 0;
        while k < len_c {
            st.w[j0 + k - start] += hv * c[k];
            st.dw[j0 + k - start] += dv * c[k];
            k += 1;
        }
    }
    if !inside {
        st.dw = [0.0; 4];
    }
    st
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;

    #[test]
    fn stencil_reproduces_cubics_inside_and_its_derivative() {
        let grid = [0.0, 0.25, 0.5, 0.8, 1.0, 1.5, 2.0];
        let f = |p: f64| 1.0 + 2.0 * p - 0.5 * p * p;
        let df = |p: f64| 2.0 - p;
        for k in 0..=40 {
            let p = 2.0 * k as f64 / 40.0;
            let st = stencil(&grid, p);
            let (mut y, mut dy) = (0.0, 0.0);
            for s in 0..st.len {
                y += st.w[s] * f(grid[st.start + s]);
                dy += st.dw[s] * f(grid[st.start + s]);
            }
            // 3-point slopes are exact for quadratics, so the Hermite cubic reproduces them
            assert!((y - f(p)).abs() < 1e-12, "p={p}: {y} vs {}", f(p));
            if p > 0.0 && p < 2.0 {
                assert!((dy - df(p)).abs() < 1e-10, "p={p}: {dy} vs {}", df(p));
            }
        }
    }
}
