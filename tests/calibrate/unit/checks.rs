//! The unit tests of `src/calibrate/checks.rs`.

use surrogate::calibrate::checks::*;
use surrogate::calibrate::objective::{Recording, Recordings};

#[test]
fn the_shipped_inconsistent_rows_are_flagged_and_only_they() {
    let rec = Recordings::shipped().unwrap();
    let flags = check(&rec);
    assert_eq!(flags.len(), 3, "{flags:#?}");
    // N = 11, T = 1.6 at 2 and 3 bar: tips 90.2 and 84.8 mm from the support at 51.7° and
    // 68.7°, where arcs of 92 mm put them at 80.0 and 71.5 mm
    for (f, p) in flags[1..].iter().zip([2.0, 3.0]) {
        let c = &f.config;
        assert_eq!(
            (c.n_bellows, c.wall_thickness_mm, c.pressure_bar),
            (11, 1.6, p)
        );
        assert!(f.message.contains("farther than an arc"), "{}", f.message);
    }
    assert!(flags[2].message.contains("84.8 mm"), "{}", flags[2].message);
    // the floors: no shape in the other rows' band comes nearer than 5.7 and 8.8 mm
    assert!(
        flags[1].message.contains("than 5.7 mm"),
        "{}",
        flags[1].message
    );
    assert!(
        flags[2].message.contains("than 8.8 mm"),
        "{}",
        flags[2].message
    );
    let f = &flags[0];
    assert_eq!(
        (
            f.config.n_bellows,
            f.config.wall_thickness_mm,
            f.config.pressure_bar
        ),
        (11, 1.6, 1.0)
    );
    assert!(f.message.contains("95.7 mm"), "{}", f.message);
    assert!(f.source.ends_with("line 11"), "{}", f.source);
}

#[test]
fn the_arc_ratio_is_one_on_an_arc() {
    // an arc of 92 mm turned by 2α at the tip: chord 92 sin α / α at angle α
    let (l, a) = (92.0_f64, 40.0_f64.to_radians());
    let chord = l * a.sin() / a;
    let uy = -chord * a.sin();
    assert!((arc_ratio(uy, 40.0, l) - 1.0).abs() < 1e-12);
    assert!(arc_ratio(uy, 0.0, l).is_nan());
    // a tip moved 10 % farther out along the chord
    assert!((arc_ratio(1.1 * uy, 40.0, l) - 1.1).abs() < 1e-12);
}

#[test]
fn the_arc_floor_is_zero_on_the_band_and_the_distance_off_it() {
    let (l, a) = (92.0_f64, 40.0_f64.to_radians());
    let c = l * a.sin() / a;
    let tip = |q: f64| (l - q * c * a.cos(), -q * c * a.sin());
    let (uz, uy) = tip(1.0);
    assert!(arc_floor_mm(uz, uy, l, 0.97, 1.05) < 1e-9);
    // 10 % farther out along the chord: 5 % of the chord beyond the band's edge at its own
    // angle; a slightly smaller angle, whose arc's chord is longer, comes a little nearer
    let (uz, uy) = tip(1.10);
    let d = arc_floor_mm(uz, uy, l, 0.97, 1.05);
    assert!(
        d <= 0.05 * c + 1e-9 && d > 0.9 * 0.05 * c,
        "{d} against {}",
        0.05 * c
    );
    // the undeformed tip itself is on the band (α = 0)
    assert!(arc_floor_mm(0.0, 0.0, l, 0.97, 1.05) < 1e-9);
}

#[test]
fn a_decreasing_force_is_flagged() {
    let mut rec = Recordings::shipped().unwrap();
    rec.force[2].force_n = 1.0; // N = 9, T = 1.6, 3 bar below its 2 bar value
    let flags = check(&rec);
    assert!(flags
        .iter()
        .any(|f| f.recording == Recording::Force && f.message.contains("decreases")));
}
