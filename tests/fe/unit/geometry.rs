//! The unit tests of `src/fe/geometry.rs`.

use surrogate::fe::geometry::*;

#[test]
fn default_design_is_valid_and_classifies_points() {
    let d = DesignParams::new(11, 2.0).validate().unwrap();
    assert_eq!(d.region([1.0, 2.0, 10.0]), Region::Solid);
    assert_eq!(d.region([8.0, 2.0, 10.0]), Region::Duct);
    assert_eq!(d.region([8.0, 2.0, 91.0]), Region::Solid);
    let p = d.pitch();
    assert_eq!(d.region([8.0, 10.0, 0.5 * p]), Region::Cavity(0));
    assert_eq!(d.region([8.0, 10.0, p]), Region::Gap(0));
    assert_eq!(d.region([8.0, 10.0, 0.2]), Region::ClampGap);
    assert_eq!(d.region([1.0, 10.0, 0.5 * p]), Region::Solid);
    assert_eq!(d.region([8.0, 21.0, 0.5 * p]), Region::Solid);
}

#[test]
fn bad_designs_are_named_errors() {
    let e = DesignParams::new(16, 2.0).validate().unwrap_err();
    assert!(matches!(
        e,
        GeometryError::OutOfRange {
            field: "n_bellows",
            ..
        }
    ));
    let e = DesignParams::new(11, 3.0).validate().unwrap_err();
    assert!(matches!(
        e,
        GeometryError::OutOfRange {
            field: "wall_thickness",
            ..
        }
    ));
    let e = DesignParams::new(15, 2.8).validate().unwrap_err();
    assert!(matches!(e, GeometryError::NoCavity { .. }), "{e}");
    assert!(e.to_string().contains("cavity"));
    let mut p = DesignParams::new(11, 2.0);
    p.gap = f64::NAN;
    assert!(p.validate().is_err());
    let mut p = DesignParams::new(11, 2.0);
    p.gap_floor = Some(17.0);
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("gap_floor") && e.contains("17"), "{e}");
    let mut p = DesignParams::new(11, 2.0);
    p.cavity_fillet = Some(-0.5);
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("cavity_fillet") && e.contains("-0.5"), "{e}");
}

#[test]
fn a_gap_floor_fuses_the_facing_walls_below_it() {
    let mut p = DesignParams::new(11, 2.0);
    p.gap_floor = Some(3.0);
    let d = p.validate().unwrap();
    let z = d.pitch(); // the middle of gap 0
    assert_eq!(d.region([8.0, 4.0 + 2.9, z]), Region::Solid);
    assert_eq!(d.region([8.0, 4.0 + 3.1, z]), Region::Gap(0));
    // the clamp gap and the cavities are left as they are
    assert_eq!(d.region([8.0, 5.0, 0.2]), Region::ClampGap);
    assert_eq!(d.region([8.0, 5.0, 0.5 * z]), Region::Cavity(0));
    // no floor, or a floor of 0: the gap reaches down to the base
    let open = DesignParams::new(11, 2.0).validate().unwrap();
    assert_eq!(open.region([8.0, 4.1, z]), Region::Gap(0));
    assert_eq!(open.gap_floor(), 0.0);
}

#[test]
fn cavity_fillets_fill_the_floor_corners_and_a_short_cavity_floor() {
    let mut p = DesignParams::new(11, 2.0);
    p.cavity_fillet = Some(1.0);
    let d = p.validate().unwrap();
    let c = d.cavity(0);
    let y = c.lo[1];
    // the corners are solid, the middle of the floor and the corners above r are not
    assert_eq!(d.region([8.0, y + 0.5, c.lo[2] + 0.5]), Region::Solid);
    assert_eq!(d.region([8.0, y + 0.5, c.hi[2] - 0.5]), Region::Solid);
    assert_eq!(d.region([8.0, y + 1.5, c.lo[2] + 0.5]), Region::Cavity(0));
    assert_eq!(
        d.region([8.0, y + 0.5, 0.5 * (c.lo[2] + c.hi[2])]),
        Region::Cavity(0)
    );
    // N = 13, T = 2.4: a cavity 1.28 mm long, shorter than 2r: its whole floor raised
    let mut p = DesignParams::new(13, 2.4);
    p.cavity_fillet = Some(1.0);
    let d = p.validate().unwrap();
    let c = d.cavity(3);
    assert!(c.hi[2] - c.lo[2] < 2.0);
    let mid = 0.5 * (c.lo[2] + c.hi[2]);
    assert_eq!(d.region([8.0, c.lo[1] + 0.9, mid]), Region::Solid);
    assert_eq!(d.region([8.0, c.lo[1] + 1.1, mid]), Region::Cavity(3));
}

#[test]
fn parts_classify_the_solid_and_their_stiffness_is_checked() {
    let mut p = DesignParams::new(11, 2.0);
    p.side_wall_thickness = Some(1.0);
    p.part_stiffness = Some(PartStiffness {
        gap_walls: 2.0,
        top: 0.5,
        side_walls: 0.25,
        base: 3.0,
    });
    let d = p.validate().unwrap();
    let c = d.cavity(2);
    let mid_z = 0.5 * (c.lo[2] + c.hi[2]);
    assert_eq!(d.part([8.0, 2.0, 10.0]), Part::Base);
    assert_eq!(d.part([0.5, 10.0, mid_z]), Part::SideWalls);
    assert_eq!(d.part([15.5, 21.5, mid_z]), Part::SideWalls);
    assert_eq!(d.part([8.0, 21.5, mid_z]), Part::Top);
    assert_eq!(d.part([8.0, 10.0, c.lo[2] - 0.5]), Part::GapWalls);
    assert_eq!(d.stiffness_at([8.0, 21.5, mid_z]), 0.5);
    assert_eq!(d.stiffness_at([8.0, 10.0, c.hi[2] + 0.5]), 2.0);
    assert_eq!(d.stiffness_at([8.0, 1.0, 50.0]), 3.0);
    // unset: every part as the material, and the design's serialisation unchanged
    let plain = DesignParams::new(11, 2.0);
    assert!(!serde_json::to_string(&plain)
        .unwrap()
        .contains("part_stiffness"));
    assert_eq!(
        plain.validate().unwrap().stiffness_at([0.5, 10.0, mid_z]),
        1.0
    );
    // a factor outside its range names the part
    let mut p = DesignParams::new(11, 2.0);
    p.part_stiffness = Some(PartStiffness {
        top: 5.0,
        ..PartStiffness::default()
    });
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("part_stiffness.top") && e.contains('5'), "{e}");
}
