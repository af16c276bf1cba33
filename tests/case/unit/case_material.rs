//! The unit tests of `src/case/material.rs`.

use serde::{Deserialize, Serialize};
use surrogate::case::material::*;

const OGDEN_002: OgdenSet = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);

#[test]
fn coordinates_round_trip() {
    let q = OgdenSet::from_coords(OGDEN_002.coords()).unwrap();
    for (a, b) in OGDEN_002.as_array().iter().zip(q.as_array()) {
        assert!((a - b).abs() < 1e-12 * a.abs());
    }
    assert_eq!(OgdenSet::from_array(OGDEN_002.as_array()), OGDEN_002);
    assert_eq!(OGDEN_002.mu0_mpa(), OGDEN_002.coords().mu0_mpa);
}

#[test]
fn rounding_keeps_significant_digits() {
    let p = OgdenSet::new(0.038_249, 5.996_127, -5.194_93, -1.996_45).unwrap();
    let r = p.rounded(4);
    assert_eq!(r.as_array(), [0.03825, 5.996, -5.195, -1.996]);
}

#[test]
fn inadmissible_sets_are_rejected_naming_the_field() {
    let e = OgdenSet::new(1.0, -2.0, -1.0, -1.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("mu1*alpha1"), "{e}");
    let e = OgdenSet::new(f64::NAN, 2.0, -1.0, -1.0)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("mu1_mpa = NaN"), "{e}");
    assert!(OgdenSet::from_array([1.0, 2.0, 1.0, -1.0]).check().is_err());
    assert!(OGDEN_002.check().is_ok());
    let bad = MaterialCoords {
        share: 1.0,
        ..OGDEN_002.coords()
    };
    assert!(OgdenSet::from_coords(bad).is_err());
}

#[test]
fn the_serde_shape_is_the_four_named_fields() {
    let json = serde_json::to_string(&OGDEN_002).unwrap();
    assert_eq!(
        json,
        r#"{"mu1_mpa":1.13,"alpha1":3.11,"mu2_mpa":-13.17,"alpha2":-0.6}"#
    );
    assert_eq!(serde_json::from_str::<OgdenSet>(&json).unwrap(), OGDEN_002);
    assert_eq!(OGDEN_002.spec(), "1.13,3.11,-13.17,-0.6");
}

#[test]
fn the_array_shape_round_trips() {
    #[derive(Serialize, Deserialize)]
    struct File {
        #[serde(with = "array")]
        material: OgdenSet,
        #[serde(with = "arrays")]
        materials: Vec<OgdenSet>,
    }
    let json = serde_json::to_string(&File {
        material: OGDEN_002,
        materials: vec![OGDEN_002; 2],
    })
    .unwrap();
    assert_eq!(
        json,
        r#"{"material":[1.13,3.11,-13.17,-0.6],"materials":[[1.13,3.11,-13.17,-0.6],[1.13,3.11,-13.17,-0.6]]}"#
    );
    let back: File = serde_json::from_str(&json).unwrap();
    assert_eq!(back.material, OGDEN_002);
    assert_eq!(back.materials, vec![OGDEN_002; 2]);
}
