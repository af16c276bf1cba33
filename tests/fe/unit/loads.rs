//! The unit tests of `src/fe/loads.rs`.

use surrogate::fe::loads::*;

fn flat_face() -> [[f64; 3]; 9] {
    std::array::from_fn(|a| [(a % 3) as f64 * 0.5, (a / 3) as f64 * 0.5, 0.0])
}

#[test]
fn unit_square_pressure_resultant() {
    let x = flat_face();
    let a = face_vector_area(&x);
    assert!((a[2] - 1.0).abs() < 1e-14 && a[0].abs() < 1e-14);
}

#[test]
fn pressure_tangent_matches_finite_differences() {
    let mut x = flat_face();
    // distort
    for (a, xa) in x.iter_mut().enumerate() {
        xa[2] += 0.1 * ((a * 7 % 5) as f64 - 2.0) * 0.1;
        xa[0] += 0.03 * (a as f64).sin();
    }
    let mut r0 = [0.0; 27];
    let mut k = [0.0; 729];
    pressure_face(0.7, &x, &mut r0, Some(&mut k));
    let h = 1e-6;
    for b in 0..9 {
        for kc in 0..3 {
            let mut xp = x;
            let mut xm = x;
            xp[b][kc] += h;
            xm[b][kc] -= h;
            let mut rp = [0.0; 27];
            let mut rm = [0.0; 27];
            pressure_face(0.7, &xp, &mut rp, None);
            pressure_face(0.7, &xm, &mut rm, None);
            for r in 0..27 {
                let fd = (rp[r] - rm[r]) / (2.0 * h);
                assert!((fd - k[r * 27 + 3 * b + kc]).abs() < 1e-7, "{r} {b} {kc}");
            }
        }
    }
}
