//! The unit tests of `src/fe/solver/settings.rs`.

use surrogate::fe::solver::settings::*;

/// Factor reuse is the default and is not written: settings written before (without the
/// field) read as the default and serialise as they did, so cache keys carry over; only
/// `false` is written.
#[test]
fn factor_reuse_is_the_default_and_keeps_the_old_keys() {
    let d = SolverSettings::default();
    assert!(d.reuse_factor);
    let text = serde_json::to_string(&d).unwrap();
    assert!(!text.contains("reuse_factor"), "{text}");
    let back: SolverSettings = serde_json::from_str(&text).unwrap();
    assert_eq!(back, d);
    let off = SolverSettings {
        reuse_factor: false,
        ..d
    };
    let text = serde_json::to_string(&off).unwrap();
    assert!(text.contains("\"reuse_factor\":false"), "{text}");
    assert_eq!(serde_json::from_str::<SolverSettings>(&text).unwrap(), off);
}

#[test]
fn defaults_are_valid_and_each_bad_field_is_named() {
    SolverSettings::default().validate().expect("defaults");
    let bad = |f: fn(&mut SolverSettings), field: &str| {
        let mut s = SolverSettings::default();
        f(&mut s);
        let e = s.validate().expect_err(field);
        assert_eq!(e.field, field, "{e}");
        assert!(e.to_string().contains("expected"), "{e}");
    };
    bad(|s| s.rtol = 0.0, "rtol");
    bad(|s| s.rtol = 0.5, "rtol");
    bad(|s| s.rtol = f64::NAN, "rtol");
    bad(|s| s.max_iterations = 0, "max_iterations");
    bad(|s| s.initial_fraction = 1.5, "initial_fraction");
    bad(
        |s| s.initial_pressure_increment = -0.01,
        "initial_pressure_increment",
    );
    bad(|s| s.max_pressure_increment = 0.0, "max_pressure_increment");
    bad(|s| s.stabilization = -1.0, "stabilization");
    bad(|s| s.augmented_updates = 1000, "augmented_updates");
    let minimise = |m: MinimiseSettings| SolverSettings {
        kind: SolverKind::Minimise(m),
        ..SolverSettings::default()
    };
    minimise(MinimiseSettings::default())
        .validate()
        .expect("minimise defaults");
    for (m, field) in [
        (
            MinimiseSettings {
                dhat_mm: 0.0,
                ..MinimiseSettings::default()
            },
            "kind.dhat_mm",
        ),
        (
            MinimiseSettings {
                barrier_pressure: f64::NAN,
                ..MinimiseSettings::default()
            },
            "kind.barrier_pressure",
        ),
        (
            MinimiseSettings {
                target_iterations: 0,
                ..MinimiseSettings::default()
            },
            "kind.target_iterations",
        ),
    ] {
        assert_eq!(minimise(m).validate().unwrap_err().field, field);
    }
    // the default kind is not written, so that settings keep their keys
    let json = serde_json::to_string(&SolverSettings::default()).unwrap();
    assert!(!json.contains("kind"), "{json}");
    let e = SolverSettings {
        rtol: 1.0,
        ..SolverSettings::default()
    }
    .validate()
    .unwrap_err()
    .within("settings.solver.");
    assert_eq!(e.field, "settings.solver.rtol");
}
