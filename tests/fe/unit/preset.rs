//! The unit tests of `src/fe/preset.rs`.

use surrogate::fe::geometry::{DesignParams, PartStiffness, MIN_CAVITY_LENGTH, T_RANGE};
use surrogate::fe::preset::*;

#[test]
fn as_modelled_builds_the_historical_designs_bit_for_bit() {
    let g = Geometry::as_modelled();
    for n in [7, 9, 11, 13, 15] {
        for t in [1.2, 1.6, 2.0, 2.4] {
            assert_eq!(g.params(n, t), DesignParams::new(n, t));
        }
    }
    assert_eq!(
        serde_json::to_string(&g.params(11, 2.0)).unwrap(),
        serde_json::to_string(&DesignParams::new(11, 2.0)).unwrap()
    );
}

#[test]
fn out_of_range_and_impossible_presets_are_named_errors() {
    let mut g = Geometry::as_modelled();
    g.gap_mm = 0.0;
    let e = g.design(11, 2.0).unwrap_err().to_string();
    assert!(e.contains("gap_mm = 0") && e.contains("0.2"), "{e}");
    g.gap_mm = 2.0;
    // N = 13, T = 2.4: pitch 7.08 − gap 2 − 2·2.4 leaves 0.28 mm of cavity
    let e = g.design(13, 2.4).unwrap_err().to_string();
    assert!(e.contains("N = 13") && e.contains("cavity"), "{e}");
    assert!(g.design(9, 1.6).is_ok());
    let mut g = Geometry::as_modelled();
    g.side_wall_mm = Some(f64::NAN);
    assert!(g
        .design(11, 2.0)
        .unwrap_err()
        .to_string()
        .contains("side_wall_mm"));
    assert!(Geometry::from_name("nominal").is_err());
    let mut g = Geometry::as_modelled();
    g.gap_floor_mm = Some(9.5);
    let e = g.design(11, 2.0).unwrap_err().to_string();
    assert!(
        e.contains("gap_floor_mm = 9.5") && e.contains("9 mm"),
        "{e}"
    );
    g.gap_floor_mm = Some(3.0);
    g.cavity_fillet_mm = Some(3.5);
    let e = g.design(11, 2.0).unwrap_err().to_string();
    assert!(e.contains("cavity_fillet_mm = 3.5"), "{e}");
    g.cavity_fillet_mm = Some(1.0);
    let d = g.design(11, 2.0).unwrap();
    assert_eq!((d.gap_floor(), d.cavity_fillet()), (3.0, 1.0));
    assert!(!g.is_as_modelled());
    // the parts' stiffness: checked as a ratio, carried into the design
    g.part_stiffness = Some(PartStiffness {
        gap_walls: 0.1,
        ..PartStiffness::default()
    });
    let e = g.design(11, 2.0).unwrap_err().to_string();
    assert!(
        e.contains("part_stiffness.gap_walls = 0.1 is outside") && e.contains("0.25 … 4"),
        "{e}"
    );
    g.part_stiffness = Some(PartStiffness {
        gap_walls: 2.0,
        ..PartStiffness::default()
    });
    let d = g.design(11, 2.0).unwrap();
    assert_eq!(d.params().part_stiffness.unwrap().gap_walls, 2.0);
    // a law of the cavity length: every wall of the design off by a + b / c
    let mut g = Geometry::as_modelled();
    g.side_wall_mm = Some(2.5);
    g.wall_law = Some(WallLaw {
        offset_mm: -0.3,
        inverse_cavity_mm2: 0.5,
    });
    let c = g.cavity_length(13, 2.4);
    assert!((c - (92.0 / 13.0 - 1.0 - 4.8)).abs() < 1e-12);
    let d = g.design(13, 2.4).unwrap();
    let off = -0.3 + 0.5 / c;
    assert!((d.bellow_wall() - (2.4 + off)).abs() < 1e-12);
    assert!((d.skin() - (2.4 + off)).abs() < 1e-12);
    assert!((d.side_wall() - (2.5 + off)).abs() < 1e-12);
    g.wall_law = Some(WallLaw {
        offset_mm: 0.0,
        inverse_cavity_mm2: 3.5,
    });
    let e = g.design(11, 2.0).unwrap_err().to_string();
    assert!(e.contains("wall_law.inverse_cavity_mm2 = 3.5 mm²"), "{e}");
    // a preset without them reads as before, and writes no key for them
    let text = serde_json::to_string(&Geometry::as_modelled()).unwrap();
    assert!(
        !text.contains("gap_floor")
            && !text.contains("cavity_fillet")
            && !text.contains("part_stiffness")
            && !text.contains("wall_law")
    );
}

#[test]
fn the_side_wall_is_decoupled_from_t() {
    let g = Geometry {
        side_wall_mm: Some(1.2),
        name: "test".into(),
        ..Geometry::as_modelled()
    };
    for t in [1.6, 2.4] {
        let d = g.design(11, t).unwrap();
        assert_eq!(d.side_wall(), 1.2);
        assert_eq!(d.bellow_wall(), t);
        assert_eq!(d.skin(), t);
        let c = d.cavity(0);
        assert_eq!(c.lo[0], 1.2);
        assert_eq!(c.hi[1], 22.0 - t);
    }
}

/// The buildability limit: as modelled it is the drawn rule; with a wall law that
/// thickens the walls of short cavities it is lower, valid, and 10⁻⁶ mm more is not.
#[test]
fn the_largest_buildable_wall_follows_the_wall_law() {
    let m = Geometry::as_modelled();
    for n in 7..=15 {
        let t = m
            .max_wall_thickness(n)
            .expect("every N has a T as modelled");
        let drawn = (92.0 / n as f64 - 1.0 - MIN_CAVITY_LENGTH) / 2.0 - 1e-9;
        assert_eq!(t, drawn.min(T_RANGE.1), "N = {n}");
    }
    let identified = Geometry {
        name: "law".into(),
        gap_mm: 0.2,
        side_wall_mm: Some(2.9),
        wall_law: Some(WallLaw {
            offset_mm: -0.28,
            inverse_cavity_mm2: 1.33,
        }),
        ..Geometry::as_modelled()
    };
    for n in 7..=15 {
        let t = identified.max_wall_thickness(n).expect("a T for every N");
        assert!(identified.design(n, t).is_ok(), "N = {n}, T = {t}");
        if t < T_RANGE.1 {
            assert!(identified.design(n, t + 1e-6).is_err(), "N = {n}, T = {t}");
            // the printed cavity closes before the drawn one: the limit is below the drawn rule
            let drawn = (92.0 / n as f64 - 0.2 - MIN_CAVITY_LENGTH) / 2.0;
            assert!(t < drawn - 0.1, "N = {n}: {t} against {drawn}");
        }
    }
    assert_eq!(identified.max_wall_thickness(7), Some(T_RANGE.1));
    let closed = Geometry {
        gap_mm: 2.0,
        wall_law: Some(WallLaw {
            offset_mm: -0.28,
            inverse_cavity_mm2: 3.0,
        }),
        ..identified
    };
    assert_eq!(closed.max_wall_thickness(15), None);
}

#[test]
fn the_identified_preset_is_the_committed_file_and_a_named_preset() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = Geometry::load(&root.join("data/geometry/identified.json")).unwrap();
    assert_eq!(Geometry::identified(), file);
    assert_eq!(Geometry::from_name("identified").unwrap(), file);
    assert!(!file.is_as_modelled());
    let err = Geometry::from_name("identfied").unwrap_err().to_string();
    assert!(
        err.contains("'identfied'") && err.contains("as_modelled, identified"),
        "{err}"
    );
}
