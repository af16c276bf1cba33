//! Validation at the door: inadmissible parameters, specifications, literature sets, serde,
//! inverted elements.

use nalgebra::{Matrix3, Vector3};
use surrogate::case::OgdenSet;
use surrogate::fe::material::{
    literature_sets, Material, MaterialError, MaterialLaw, MooneyRivlin5, NeoHookean, Ogden2,
};

/// The `field` of an [`MaterialError::Inadmissible`], panicking on anything else.
fn inadmissible_field<T: std::fmt::Debug>(result: Result<T, MaterialError>) -> String {
    match result {
        Err(e @ MaterialError::Inadmissible { .. }) => {
            let MaterialError::Inadmissible { field, value, .. } = &e else {
                unreachable!()
            };
            let message = e.to_string();
            assert!(
                message.contains(field.as_str()),
                "message {message:?} lacks {field}"
            );
            assert!(
                message.contains(&value.to_string()),
                "message {message:?} lacks {value}"
            );
            assert!(
                message.contains("expected"),
                "message {message:?} lacks the expectation"
            );
            field.clone()
        }
        other => panic!("expected an Inadmissible error, got {other:?}"),
    }
}

#[test]
fn inadmissible_parameters_are_errors_naming_the_field() {
    let nh = || MaterialLaw::from(NeoHookean::new(1.0).unwrap());
    let cases: Vec<(String, &str)> = vec![
        (
            inadmissible_field(Ogden2::new(f64::NAN, 3.11, -13.17, -0.6)),
            "mu1",
        ),
        (
            inadmissible_field(Ogden2::new(1.13, 3.11, f64::INFINITY, -0.6)),
            "mu2",
        ),
        (
            inadmissible_field(Ogden2::new(1.13, 0.0, -13.17, -0.6)),
            "alpha1",
        ),
        (
            inadmissible_field(Ogden2::new(1.13, 3.11, -13.17, f64::NAN)),
            "alpha2",
        ),
        (
            inadmissible_field(Ogden2::new(-1.13, 3.11, -13.17, -0.6)),
            "mu1*alpha1",
        ),
        (
            inadmissible_field(Ogden2::new(1.13, 3.11, 13.17, -0.6)),
            "mu2*alpha2",
        ),
        (
            inadmissible_field(Ogden2::new(1.13, 3.11, -13.17, 0.0)),
            "alpha2",
        ),
        (
            inadmissible_field(Ogden2::new(1e300, 1e300, 1.0, 1.0)),
            "mu1*alpha1",
        ),
        (
            inadmissible_field(MooneyRivlin5::new(f64::NAN, 1.0, 0.0, 0.0, 0.0)),
            "c10",
        ),
        (
            inadmissible_field(MooneyRivlin5::new(1.0, 1.0, 0.0, 0.0, f64::INFINITY)),
            "c02",
        ),
        (
            inadmissible_field(MooneyRivlin5::new(0.233, -2.562, 0.1, 0.0, 0.0)),
            "mu0 = 2*(c10 + c01)",
        ),
        (
            inadmissible_field(MooneyRivlin5::new(1.0, -1.0, 0.0, 0.0, 0.0)),
            "mu0 = 2*(c10 + c01)",
        ),
        (inadmissible_field(NeoHookean::new(0.0)), "mu"),
        (inadmissible_field(NeoHookean::new(-1.0)), "mu"),
        (inadmissible_field(NeoHookean::new(f64::NAN)), "mu"),
        (inadmissible_field(Material::new(nh(), 0.0)), "bulk_ratio"),
        (
            inadmissible_field(Material::new(nh(), f64::INFINITY)),
            "bulk_ratio",
        ),
        (inadmissible_field(Material::new(nh(), -5.0)), "bulk_ratio"),
        (
            inadmissible_field(Material::with_kappa(nh(), f64::NAN)),
            "kappa",
        ),
        (inadmissible_field(Material::with_kappa(nh(), 0.0)), "kappa"),
    ];
    for (got, want) in cases {
        assert_eq!(got, want);
    }
}

#[test]
fn literature_sets_match_the_stated_initial_shear_moduli() {
    let sets = literature_sets().unwrap();
    let mu0: Vec<(&str, f64)> = sets
        .iter()
        .map(|(n, law)| (n.as_str(), law.initial_shear_modulus()))
        .collect();
    let want = [
        ("ogden_002", 5.708),
        ("ogden_005", 3.476),
        ("mooney_rivlin_5", 4.658),
    ];
    assert_eq!(mu0.len(), want.len());
    for ((name, got), (want_name, want_mu0)) in mu0.into_iter().zip(want) {
        assert_eq!(name, want_name);
        assert!(
            (got - want_mu0).abs() < 1e-3,
            "{name}: mu0 = {got}, expected {want_mu0}"
        );
    }
}

#[test]
fn from_spec_accepts_literature_names_and_parameter_lists() {
    for (name, law) in literature_sets().unwrap() {
        for spec in [name.clone(), name.to_uppercase(), format!("  {name} ")] {
            let m = Material::from_spec(&spec, 1000.0).unwrap();
            assert_eq!(m.law, law, "{spec}");
            assert!((m.kappa - 1000.0 * law.initial_shear_modulus()).abs() < 1e-9 * m.kappa);
        }
    }
    let m = Material::from_spec("ogden_002", 1000.0).unwrap();
    assert_eq!(
        m.ogden_set(),
        Some(OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]))
    );
    let custom = Material::from_spec("1.13,3.11,-13.17,-0.6", 1000.0).unwrap();
    assert_eq!(custom, m);
    assert!((custom.mu0() - 5.708).abs() < 1e-3);
    let spaced = Material::from_spec(" 1.13, 3.11 , -13.17,-0.6 ", 1000.0).unwrap();
    assert_eq!(spaced, m);
    let nh = Material::from_spec("neo_hookean:2.5", 10.0).unwrap();
    assert_eq!(
        nh.law,
        MaterialLaw::NeoHookean(NeoHookean::new(2.5).unwrap())
    );
    assert_eq!(nh.mu0(), 2.5);
    assert_eq!(nh.kappa, 25.0);
    assert_eq!(nh.ogden_set(), None);
    let mr = Material::from_spec("Mooney_Rivlin_5", 1000.0).unwrap();
    assert!((mr.mu0() - 4.658).abs() < 1e-9);
}

#[test]
fn from_spec_rejects_unknown_malformed_and_inadmissible_specs() {
    match Material::from_spec("ogden_999", 1000.0) {
        Err(e @ MaterialError::UnknownName { .. }) => {
            let message = e.to_string();
            assert!(
                message.contains("ogden_999") && message.contains("ogden_002"),
                "{message}"
            );
        }
        other => panic!("ogden_999: {other:?}"),
    }
    assert!(matches!(
        Material::from_spec("", 1000.0),
        Err(MaterialError::UnknownName { .. })
    ));
    for (spec, mention) in [
        ("1,2,3", "expected 4"),
        ("1,2,3,4,5", "expected 4"),
        ("a,b,c,d", "mu1"),
        ("1,2,x,4", "mu2"),
        ("neo_hookean:abc", "mu"),
        ("neo_hookean:", "mu"),
    ] {
        match Material::from_spec(spec, 1000.0) {
            Err(e @ MaterialError::Parse { .. }) => {
                let message = e.to_string();
                assert!(message.contains(mention), "{spec}: {message}");
            }
            other => panic!("{spec}: expected a Parse error, got {other:?}"),
        }
    }
    assert_eq!(
        inadmissible_field(Material::from_spec("neo_hookean:-1", 1000.0)),
        "mu"
    );
    assert_eq!(
        inadmissible_field(Material::from_spec("1,-2,3,4", 1000.0)),
        "mu1*alpha1"
    );
    assert_eq!(
        inadmissible_field(Material::from_spec("ogden_002", f64::NAN)),
        "bulk_ratio"
    );
}

/// serde_json (without its `float_roundtrip` feature) may change the last bit of a float.
#[test]
fn serde_round_trips_and_validates() {
    for (spec, ratio) in [
        ("ogden_005", 1000.0),
        ("mooney_rivlin_5", 50.0),
        ("neo_hookean:3", 7.0),
    ] {
        let m = Material::from_spec(spec, ratio).unwrap();
        let back: Material = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
        assert_eq!(back.law, m.law, "{spec}");
        assert!((back.kappa - m.kappa).abs() <= 1e-14 * m.kappa, "{spec}");
    }
    let bad_law = r#"{"law":{"Ogden":{"mu":[-1.13,-13.17],"alpha":[3.11,-0.6]}},"kappa":1.0}"#;
    let err = serde_json::from_str::<Material>(bad_law)
        .unwrap_err()
        .to_string();
    assert!(err.contains("mu1*alpha1"), "{err}");
    let bad_kappa = r#"{"law":{"NeoHookean":{"mu":1.0}},"kappa":-1.0}"#;
    let err = serde_json::from_str::<Material>(bad_kappa)
        .unwrap_err()
        .to_string();
    assert!(err.contains("kappa"), "{err}");
}

#[test]
fn inverted_elements_give_infinite_energy_and_nan_stress() {
    let inverted = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -0.5));
    for spec in ["ogden_002", "mooney_rivlin_5", "neo_hookean:1"] {
        let m = Material::from_spec(spec, 1000.0).unwrap();
        for f in [inverted, Matrix3::zeros(), Matrix3::from_element(f64::NAN)] {
            assert_eq!(m.iso_energy(&f), f64::INFINITY, "{spec}");
            let (p, a) = m.stress_tangent(&f);
            assert!(
                p.iter().all(|x| x.is_nan()) && a.iter().all(|x| x.is_nan()),
                "{spec}"
            );
            assert!(m.stress(&f).iter().all(|x| x.is_nan()), "{spec}");
        }
    }
}

#[test]
fn initial_shear_modulus_is_the_small_strain_shear_stiffness() {
    // simple shear F = I + γ e_x⊗e_y: P_xy = μ0 γ + O(γ³)
    let gamma = 1e-4;
    let f = Matrix3::new(1.0, gamma, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    for (name, law) in literature_sets().unwrap() {
        let m = Material::new(law, 1000.0).unwrap();
        let shear = m.stress(&f)[(0, 1)] / gamma;
        assert!(
            (shear - m.mu0()).abs() < 1e-6 * m.mu0(),
            "{name}: {shear} vs {}",
            m.mu0()
        );
    }
}
