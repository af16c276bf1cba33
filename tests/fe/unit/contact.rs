//! The unit tests of `src/fe/contact/mod.rs`.
//!
//! Tests of contact: the barrier and its update, faces against a plane and face pairs, each
//! residual and tangent against finite differences.

use surrogate::fe::contact::*;

fn face(z: f64, tilt: f64) -> [[f64; 3]; 9] {
    std::array::from_fn(|a| {
        let (x, y) = ((a % 3) as f64, (a / 3) as f64);
        [x, y, z + tilt * x + 0.01 * (a as f64).sin()]
    })
}

#[test]
fn uzawa_update_moves_the_pressure_to_zero_gap() {
    let (e, d) = (20.0, 0.05);
    let p = |x: f64| -barrier(e, d, x).1;
    // in penetration and in the smoothing zone: the same pressure is reached at g = 0
    for (g, c) in [(-0.03, 0.0), (0.02, 0.0), (-0.01, 0.04), (0.01, -0.02)] {
        let (c_new, change) = update_shift(e, d, g, c);
        assert!(
            (p(0.0 - c_new) - p(g - c)).abs() < 1e-12,
            "g = {g}, c = {c}"
        );
        assert!((change - (p(g - c) - p(-c)).abs() / e).abs() < 1e-15);
    }
    // open: the pressure starts exactly at g = 0
    let (c_new, _) = update_shift(e, d, 0.2, 0.0);
    assert_eq!(c_new, -d);
    assert_eq!(p(1e-9 - c_new), 0.0);
    assert!(p(-1e-3 - c_new) > 0.0);
    // a failed projection is open
    assert_eq!(update_shift(e, d, f64::INFINITY, 0.01).0, -d);
    // at the fixed point nothing changes
    let (c1, _) = update_shift(e, d, -0.02, 0.0);
    let (c2, change) = update_shift(e, d, 0.0, c1);
    assert_eq!((c1, change), (c2, 0.0));
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
    plane_face(&plane, &x0, &x, &[0.0; 9], &mut r, Some(&mut k));
    let h = 1e-7;
    for b in 0..9 {
        for d in 0..3 {
            let (mut xp, mut xm) = (x, x);
            xp[b][d] += h;
            xm[b][d] -= h;
            let (mut rp, mut rm) = ([0.0; 27], [0.0; 27]);
            let ep = plane_face(&plane, &x0, &xp, &[0.0; 9], &mut rp, None).0;
            let em = plane_face(&plane, &x0, &xm, &[0.0; 9], &mut rm, None).0;
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
    let (_, f, g) = plane_face(&plane, &x0, &x, &[0.0; 9], &mut r, None);
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

#[test]
fn pair_residual_and_tangent_match_finite_differences() {
    let set = PairSettings {
        stiffness: 60.0,
        smoothing: 0.2,
        closest_point: false,
    };
    let x0b = face(0.0, 0.0);
    let x0f = face(1.0, 0.0);
    let o = pair_orientation(&x0b, &x0f);
    assert_eq!(o, 1.0);
    // bulged, rotated walls: some points in penetration, some within δ, some open
    let xb: [[f64; 3]; 9] = std::array::from_fn(|a| {
        let p = x0b[a];
        [
            p[0] + 0.02 * p[1],
            p[1] - 0.03 * p[2],
            p[2] + 0.9 + 0.05 * (a as f64).cos(),
        ]
    });
    let xf: [[f64; 3]; 9] = std::array::from_fn(|a| {
        let p = x0f[a];
        [
            p[0] - 0.01,
            p[1] + 0.02 * p[0],
            p[2] - 0.05 * p[0] + 0.03 * (a as f64).sin(),
        ]
    });
    let mut r = [0.0; PAIR_DOFS];
    let mut k = [0.0; PAIR_DOFS * PAIR_DOFS];
    let (_, f, g) = pair_face(&set, o, &x0b, &xb, &xf, &[0.0; 9], &mut r, Some(&mut k));
    assert!(
        f > 0.0 && g < 0.0,
        "the test state must be in contact: f {f}, g {g}"
    );
    let eval = |xb: &[[f64; 3]; 9], xf: &[[f64; 3]; 9]| {
        let mut r = [0.0; PAIR_DOFS];
        let e = pair_face(&set, o, &x0b, xb, xf, &[0.0; 9], &mut r, None).0;
        (e, r)
    };
    let h = 1e-6;
    let (mut max_r, mut max_k) = (0.0f64, 0.0f64);
    for col in 0..PAIR_DOFS {
        let (node, c) = (col / 3, col % 3);
        let (mut bp, mut bm, mut fp, mut fm) = (xb, xb, xf, xf);
        if node < 9 {
            bp[node][c] += h;
            bm[node][c] -= h;
        } else {
            fp[node - 9][c] += h;
            fm[node - 9][c] -= h;
        }
        let (ep, rp) = eval(&bp, &fp);
        let (em, rm) = eval(&bm, &fm);
        max_r = max_r.max(((ep - em) / (2.0 * h) - r[col]).abs());
        for row in 0..PAIR_DOFS {
            let fd = (rp[row] - rm[row]) / (2.0 * h);
            max_k = max_k.max((fd - k[row * PAIR_DOFS + col]).abs());
        }
    }
    let scale_r = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale_k = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        max_r < 1e-6 * scale_r,
        "residual error {max_r} (scale {scale_r})"
    );
    assert!(
        max_k < 1e-5 * scale_k,
        "tangent error {max_k} (scale {scale_k})"
    );
}

#[test]
fn parallel_walls_pressed_together_carry_pressure_times_area() {
    let set = PairSettings {
        stiffness: 100.0,
        smoothing: 0.0,
        closest_point: false,
    };
    let x0b = std::array::from_fn(|a| [(a % 3) as f64, (a / 3) as f64, 0.0]);
    let x0f = x0b.map(|p: [f64; 3]| [p[0], p[1], 1.0]);
    // the front wall moved 1.01 towards the back one and slid sideways by 0.3: 0.01 mm
    // penetration, 1 MPa over 4 mm², no tangential force
    let xf = x0f.map(|p| [p[0] + 0.3, p[1], p[2] - 1.01]);
    let mut r = [0.0; PAIR_DOFS];
    let o = pair_orientation(&x0b, &x0f);
    let (_, f, g) = pair_face(&set, o, &x0b, &x0b, &xf, &[0.0; 9], &mut r, None);
    assert!((f - 4.0).abs() < 1e-10, "{f}");
    assert!((g + 0.01).abs() < 1e-12, "{g}");
    let sum = |side: usize, c: usize| (0..9).map(|a| r[27 * side + 3 * a + c]).sum::<f64>();
    assert!((sum(0, 2) - 4.0).abs() < 1e-10 && (sum(1, 2) + 4.0).abs() < 1e-10);
    for side in 0..2 {
        assert!(sum(side, 0).abs() < 1e-12 && sum(side, 1).abs() < 1e-12);
    }
}
