//! The unit tests of `src/fe/contact_cp.rs`.

use surrogate::fe::contact_cp::*;

/// A curved front face over a flat back face, slid sideways.
fn faces() -> ([[f64; 3]; 9], [[f64; 3]; 9]) {
    let yb = std::array::from_fn(|a| {
        let (i, j) = ((a % 3) as f64, (a / 3) as f64);
        [i, j, 0.02 * i * j]
    });
    let yf = std::array::from_fn(|a| {
        let (i, j) = ((a % 3) as f64, (a / 3) as f64);
        [
            i + 0.3,
            j - 0.1,
            0.05 + 0.04 * (i - 1.0) * (i - 1.0) + 0.01 * j,
        ]
    });
    (yb, yf)
}

#[test]
fn projection_is_orthogonal_and_gap_gradient_matches_finite_differences() {
    let (yb, yf) = faces();
    let xi_b = [0.3, -0.5];
    let (ls, _) = surrogate::fe::element::lagrange2(xi_b[0]);
    let (lt, _) = surrogate::fe::element::lagrange2(xi_b[1]);
    let nb: [f64; 9] = std::array::from_fn(|a| ls[a % 3] * lt[a / 3]);
    let mut hess = [0.0; DOFS * DOFS];
    let (g, grad) = gap_hessian(&nb, xi_b, &yb, &yf, 1.0, &mut hess).unwrap();
    assert!(g > 0.0 && g < 0.2, "{g}");
    let h = 1e-6;
    let eval =
        |yb: &[[f64; 3]; 9], yf: &[[f64; 3]; 9]| gap_gradient(&nb, xi_b, yb, yf, 1.0).unwrap();
    for col in 0..DOFS {
        let (mut bp, mut fp, mut bm, mut fm) = (yb, yf, yb, yf);
        let (a, c) = ((col % 27) / 3, col % 3);
        if col < 27 {
            bp[a][c] += h;
            bm[a][c] -= h;
        } else {
            fp[a][c] += h;
            fm[a][c] -= h;
        }
        let (gp, dp) = eval(&bp, &fp);
        let (gm, dm) = eval(&bm, &fm);
        let fd = (gp - gm) / (2.0 * h);
        assert!(
            (fd - grad[col]).abs() < 1e-7,
            "dg/dy[{col}]: fd {fd}, exact {}",
            grad[col]
        );
        for row in 0..DOFS {
            let fd2 = (dp[row] - dm[row]) / (2.0 * h);
            let ex = hess[row * DOFS + col];
            assert!(
                (fd2 - ex).abs() < 1e-6 * (1.0 + ex.abs()),
                "H[{row}][{col}]: fd {fd2}, dual {ex}"
            );
        }
    }
    // symmetric (a second derivative)
    for i in 0..DOFS {
        for j in 0..i {
            let (a, b) = (hess[i * DOFS + j], hess[j * DOFS + i]);
            assert!(
                (a - b).abs() < 1e-9 * (1.0 + a.abs()),
                "H[{i}][{j}] {a} vs {b}"
            );
        }
    }
}

#[test]
fn flat_faces_give_the_distance_along_the_normal_whatever_the_slide() {
    let yb: [[f64; 3]; 9] = std::array::from_fn(|a| [(a % 3) as f64, (a / 3) as f64, 0.0]);
    for slide in [0.0, 0.2, 0.45] {
        let yf: [[f64; 3]; 9] =
            std::array::from_fn(|a| [(a % 3) as f64 + slide, (a / 3) as f64, 0.07]);
        let (g, grad) = gap_gradient(
            &[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0],
            &yb,
            &yf,
            1.0,
        )
        .unwrap();
        assert!((g - 0.07).abs() < 1e-14, "slide {slide}: gap {g}");
        // the force direction has no tangential part
        for a in 0..18 {
            assert!(grad[3 * a].abs() < 1e-14 && grad[3 * a + 1].abs() < 1e-14);
        }
    }
}
