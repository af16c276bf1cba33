//! A prepared ramp (`Surrogate::ramp`: design and material fixed, pressure free) gives exactly
//! the library path's values at every pressure, for either regressor.

use surrogate::case::{OgdenSet, Query};
use surrogate::rom::regression::RegressorKind;

use crate::rom_common;

#[test]
fn ramp_matches_the_library_path_bit_for_bit() {
    for only in [Some(RegressorKind::GP), Some(RegressorKind::POLY), None] {
        let m = rom_common::small_model(only.clone());
        let mut direct = m.new_prediction();
        let mut via = m.new_prediction();
        for (n, t, mat) in [
            (11, 2.0, [1.13, 3.11, -13.17, -0.6]),
            (9, 1.7, [0.8, 4.0, -3.0, -1.2]),
            (13, 2.4, [2.0, 2.5, -6.0, -0.3]),
        ] {
            let q = Query::new(n, t, 0.0, OgdenSet::from_array(mat));
            let ramp = m.ramp(&q).unwrap();
            // inside, on the nodes and outside the grid (clamped by both paths)
            for i in 0..=90 {
                let p = -0.2 + 0.041 * i as f64;
                m.predict_into(&Query { p_bar: p, ..q }, &mut direct)
                    .unwrap();
                ramp.predict_into(p, &mut via).unwrap();
                assert_eq!(direct.values, via.values, "{only:?} {q:?} p = {p}");
                let s = ramp.predict_scalars(p).unwrap();
                assert_eq!(
                    s,
                    [
                        direct.tip_uz_mm(),
                        direct.tip_uy_mm(),
                        direct.angle_deg(),
                        direct.force_n()
                    ]
                );
            }
            for &p in &m.pressures {
                m.predict_into(&Query { p_bar: p, ..q }, &mut direct)
                    .unwrap();
                ramp.predict_into(p, &mut via).unwrap();
                assert_eq!(direct.values, via.values);
            }
        }
    }
}

#[test]
fn ramp_rejects_what_the_library_path_rejects() {
    let m = rom_common::small_model(None);
    let bad_n = Query::new(
        10,
        2.0,
        0.0,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    let e = m.ramp(&bad_n).unwrap_err().to_string();
    assert!(e.contains("n") && e.contains("10"), "{e}");
    let bad_mat = Query::new(
        11,
        2.0,
        0.0,
        OgdenSet::from_array([1.13, -3.11, -13.17, -0.6]),
    );
    assert!(m.ramp(&bad_mat).is_err());
    let ramp = m
        .ramp(&Query::new(
            11,
            2.0,
            0.0,
            OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
        ))
        .unwrap();
    let mut pred = m.new_prediction();
    let e = ramp
        .predict_into(f64::NAN, &mut pred)
        .unwrap_err()
        .to_string();
    assert!(e.contains("p_bar"), "{e}");
}
