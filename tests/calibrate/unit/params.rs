//! The unit tests of `src/calibrate/params.rs`.

use surrogate::calibrate::params::*;

fn domain() -> ParamSpace {
    ParamSpace::Training {
        lo: [3f64.ln(), 0.02, 1.5, -2.0],
        hi: [9f64.ln(), 0.95, 6.0, -0.004],
    }
}

#[test]
fn coordinates_round_trip() {
    let p = OgdenSet::literature("ogden_002").unwrap();
    let q = OgdenSet::from_coords(p.coords()).unwrap();
    for (a, b) in p.as_array().iter().zip(q.as_array()) {
        assert!((a - b).abs() < 1e-12 * a.abs());
    }
    let d = domain();
    assert!(d.contains(&p));
    let u = d.unit(&p);
    let r = d.ogden(&u).unwrap();
    for (a, b) in p.as_array().iter().zip(r.as_array()) {
        assert!((a - b).abs() < 1e-12 * a.abs());
    }
}

#[test]
fn jacobian_matches_finite_differences() {
    let d = domain();
    let u = [0.3, 0.6, 0.4, 0.7];
    let j = d.ogden_jacobian(&u);
    let h = 1e-6;
    for k in 0..4 {
        let mut up = u;
        let mut um = u;
        up[k] += h;
        um[k] -= h;
        let (a, b) = (
            d.ogden(&up).unwrap().as_array(),
            d.ogden(&um).unwrap().as_array(),
        );
        for i in 0..4 {
            let fd = (a[i] - b[i]) / (2.0 * h);
            assert!(
                (fd - j[i][k]).abs() < 1e-6 * (1.0 + fd.abs()),
                "d{}/du{k}: {fd} vs {}",
                NAMES[i],
                j[i][k]
            );
        }
    }
}

#[test]
fn inadmissible_sets_and_boxes_are_rejected() {
    assert!(OgdenSet::new(1.0, -2.0, -1.0, -1.0)
        .unwrap_err()
        .to_string()
        .contains("mu1*alpha1"));
    assert!(OgdenSet::new(f64::NAN, 2.0, -1.0, -1.0).is_err());
    let p = OgdenSet::literature("ogden_002").unwrap();
    assert!(ParamSpace::raw_box(&p, 0.1, &domain()).is_ok());
    // a ±50 % box around a set at the edge of the domain leaves it
    let edge = OgdenSet::from_coords(MaterialCoords {
        mu0_mpa: 8.9,
        share: 0.5,
        alpha1: 3.0,
        alpha2: -1.0,
    })
    .unwrap();
    assert!(ParamSpace::raw_box(&edge, 0.5, &domain()).is_err());
    assert!(ParamSpace::raw_box(&p, 0.0, &domain()).is_err());
    // the same boxes as outcomes: the box inside, the corner outside named, a bad fraction
    // still an error
    let inside = ParamSpace::raw_box_in(&p, 0.1, &domain()).unwrap();
    assert_eq!(
        inside,
        BoxFit::Inside(ParamSpace::raw_box(&p, 0.1, &domain()).unwrap())
    );
    match ParamSpace::raw_box_in(&edge, 0.5, &domain()).unwrap() {
        BoxFit::Outside { corner } => assert!(!domain().contains(&corner), "{corner:?}"),
        other => panic!("{other:?}"),
    }
    let e = ParamSpace::raw_box_in(&p, 0.0, &domain()).unwrap_err();
    assert!(e.to_string().starts_with("box fraction = 0"), "{e}");
}
