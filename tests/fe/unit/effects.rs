//! The unit tests of `src/fe/effects/mod.rs`.

use surrogate::fe::effects::*;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Fibre, Material};

#[test]
fn the_library_lists_every_effect_once_with_its_neutral_value_inside_the_range() {
    let mut names: Vec<_> = BUILTIN_EFFECTS.iter().map(|e| e.name()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), BUILTIN_EFFECTS.len());
    for (k, &e) in BUILTIN_EFFECTS.iter().enumerate() {
        // the handle's rank is its place in the list
        assert_eq!(e.rank(), Some(k), "{e} out of order");
        assert_eq!(Effect::from_name(e.name()), Ok(e));
        assert_eq!(e.check(), Ok(()));
        assert_eq!(Effect::all().nth(k), Some(e));
        let i = e.info();
        assert!(i.range.0 <= i.neutral && i.neutral <= i.range.1, "{e}");
        assert!(i.range.0 < i.range.1);
    }
    // the library is ordered as listed
    assert!(BUILTIN_EFFECTS.windows(2).all(|w| w[0] < w[1]));
}

#[test]
fn neutral_effects_leave_the_design_and_the_pressure_unchanged() {
    let nominal = DesignParams::new(9, 1.6);
    let e = Effects::neutral()
        .with(Effect::WallBias, 0.0)
        .unwrap()
        .with(Effect::Density, 1.0)
        .unwrap();
    assert!(e.is_neutral());
    assert_eq!(e.printed_design(&nominal), nominal);
    for p in [0.0, 0.1, 1.7, 3.5] {
        assert_eq!(e.effective_pressure_bar(p).to_bits(), p.to_bits());
    }
    assert_eq!(e.clamp_springs(), [None, None, None]);
    // a neutral set writes nothing
    assert_eq!(serde_json::to_string(&Effects::neutral()).unwrap(), "{}");
}

#[test]
fn biases_reach_the_printed_design() {
    let nominal = DesignParams::new(11, 2.0);
    let e = Effects::parse(["wall_bias=0.1", "wall_bias_skin=-0.3", "gap_bias=0.2"]).unwrap();
    let p = e.printed_design(&nominal);
    assert_eq!(p.wall_thickness, 2.0);
    assert!((p.bellow_wall_thickness.unwrap() - 2.1).abs() < 1e-12);
    assert!((p.skin_thickness.unwrap() - 1.8).abs() < 1e-12);
    assert!((p.gap - 1.2).abs() < 1e-12);
    assert!(p.validate().is_ok());
    let e = Effects::parse(["pressure_loss=0.1", "pressure_offset=0.05"]).unwrap();
    assert!((e.effective_pressure_bar(2.0) - 1.75).abs() < 1e-12);
    assert_eq!(e.effective_pressure_bar(0.0), 0.0);
    let e = Effects::parse(["clamp_compliance=0.2"]).unwrap();
    assert_eq!(e.clamp_springs(), [None, None, Some(5.0)]);
}

#[test]
fn anisotropy_adds_a_fibre_along_the_length_and_refuses_to_replace_one() {
    let m = Material::from_spec("ogden_002", surrogate::fe::material::DEFAULT_BULK_RATIO).unwrap();
    assert_eq!(Effects::neutral().printed_material(&m).unwrap(), m);
    let e = Effects::parse(["anisotropy=0.5"]).unwrap();
    let printed = e.printed_material(&m).unwrap();
    let fibre = printed.fibre.as_ref().unwrap();
    assert!((fibre.modulus() - 0.5 * m.mu0()).abs() < 1e-12);
    assert_eq!(fibre.params().direction, Fibre::ALONG_LENGTH);
    let err = e.printed_material(&printed).unwrap_err().to_string();
    assert!(err.contains("fibre") && err.contains("anisotropy"), "{err}");
}

/// Fuzz-style: every malformed assignment is an error naming the effect and its range.
#[test]
fn bad_assignments_are_errors_naming_the_effect_and_its_range() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["wal_bias=0.1"],
            "unknown effect \"wal_bias\": expected one of wall_bias",
        ),
        (&["wall_bias"], "expected NAME=VALUE"),
        (&["wall_bias=abc"], "expected NAME=VALUE"),
        (&["=0.1"], "unknown effect \"\""),
        (
            &["wall_bias=NaN"],
            "effect wall_bias = NaN mm: expected a value in [-0.4, 0.4] mm",
        ),
        (&["wall_bias=inf"], "effect wall_bias = inf mm"),
        (&["wall_bias=0.5"], "expected a value in [-0.4, 0.4] mm"),
        (
            &["density=0"],
            "effect density = 0 1: expected a value in [0.5, 1.5]",
        ),
        (&["clamp_compliance=-0.1"], "clamp_compliance = -0.1 mm/MPa"),
        (
            &["pressure_loss=0.1", "pressure_loss=0.2"],
            "given twice (0.1 and 0.2)",
        ),
    ];
    for (items, want) in cases {
        let e = Effects::parse(items.iter().copied())
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{items:?}: {e}");
    }
    // random strings never panic
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let alphabet: Vec<char> = "wall_bias=0.1-e+NaN,;= xyz".chars().collect();
    for _ in 0..2000 {
        let len = (state % 24) as usize;
        let s: String = (0..len)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                alphabet[(state % alphabet.len() as u64) as usize]
            })
            .collect();
        let _ = Effects::parse([s.as_str()]);
    }
}

#[test]
fn effects_round_trip_through_json_and_refuse_bad_files() {
    let e = Effects::parse(["wall_bias=-0.1", "plate_offset=1"]).unwrap();
    let s = serde_json::to_string(&e).unwrap();
    assert_eq!(s, r#"{"plate_offset":1.0,"wall_bias":-0.1}"#);
    assert_eq!(serde_json::from_str::<Effects>(&s).unwrap(), e);
    let bad = serde_json::from_str::<Effects>(r#"{"wall_bias":3}"#).unwrap_err();
    assert!(bad.to_string().contains("[-0.4, 0.4]"), "{bad}");
}
