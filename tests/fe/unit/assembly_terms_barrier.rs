//! The unit tests of `src/fe/assembly/terms/barrier.rs`.

use surrogate::fe::assembly::terms::barrier::*;

#[test]
fn barrier_derivatives_match_finite_differences_and_vanish_at_activation() {
    let b = IpcBarrier::new(2e-3, 0.3).unwrap();
    for x in [0.01, 0.1, 0.37, 0.5, 0.9, 0.999] {
        let g = x * b.dhat;
        let h = 1e-7 * g;
        let (_, d, dd) = b.eval(g);
        let fd = (b.eval(g + h).0 - b.eval(g - h).0) / (2.0 * h);
        let fdd = (b.eval(g + h).1 - b.eval(g - h).1) / (2.0 * h);
        assert!(
            (fd - d).abs() <= 1e-6 * d.abs().max(1e-9),
            "x {x}: {fd} vs {d}"
        );
        assert!(
            (fdd - dd).abs() <= 1e-6 * dd.abs().max(1e-6),
            "x {x}: {fdd} vs {dd}"
        );
        // repulsive and convex in the active zone
        assert!(d < 0.0 && dd > 0.0, "x {x}");
    }
    // C² at the activation distance
    let (e, d, dd) = b.eval(b.dhat * (1.0 - 1e-9));
    assert!(e.abs() < 1e-20 && d.abs() < 1e-8 && dd.abs() < 1e-3);
    assert_eq!(b.eval(b.dhat), (0.0, 0.0, 0.0));
    // pressure p̂·1.19 at half the activation distance
    let p = -b.eval(0.5 * b.dhat).1;
    assert!((p / b.pressure - 0.5 * (1.0 - 2.0 * 0.5f64.ln())).abs() < 1e-12);
    assert!(b.eval(0.0).0.is_infinite() && b.eval(-1e-3).0.is_infinite());
}

#[test]
fn bad_barrier_settings_are_named() {
    let e = IpcBarrier::new(0.0, 0.1).unwrap_err();
    assert!(e.to_string().contains("activation distance"), "{e}");
    let e = IpcBarrier::new(1e-3, -1.0).unwrap_err();
    assert!(e.to_string().contains("pressure scale"), "{e}");
}
