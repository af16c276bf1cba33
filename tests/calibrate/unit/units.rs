//! The unit tests of `src/calibrate/units.rs`.

use surrogate::calibrate::experiments::{
    parse_bending, parse_force, shipped_bending, shipped_force, BendingRecord, ExperimentError,
    ForceRecord,
};
use surrogate::calibrate::units::*;

fn bending_rows(v: &[BendingRecord]) -> Vec<Row> {
    v.iter()
        .enumerate()
        .map(|(i, r)| Row {
            line: i + 2,
            pressure_bar: r.pressure_bar,
            wall_thickness_mm: r.wall_thickness_mm,
            recorded: Recorded::Bending {
                tip_uz_mm: r.tip_uz_mm,
                tip_uy_mm: r.tip_uy_mm,
                angle_deg: r.angle_deg,
                angle_std_deg: r.angle_std_deg,
            },
        })
        .collect()
}

fn force_rows(v: &[ForceRecord]) -> Vec<Row> {
    v.iter()
        .enumerate()
        .map(|(i, r)| Row {
            line: i + 2,
            pressure_bar: r.pressure_bar,
            wall_thickness_mm: r.wall_thickness_mm,
            recorded: Recorded::Force {
                force_n: r.force_n,
                force_std_n: r.force_std_n,
            },
        })
        .collect()
}

fn check_bending(v: &[BendingRecord], w: &Written) -> Vec<Suspicion> {
    check(&bending_rows(v), w)
}

fn check_force(v: &[ForceRecord], w: &Written) -> Vec<Suspicion> {
    check(&force_rows(v), w)
}

#[test]
fn the_shipped_experiments_pass() {
    let w = Written::default();
    assert_eq!(check_bending(&shipped_bending().unwrap(), &w), vec![]);
    assert_eq!(check_force(&shipped_force().unwrap(), &w), vec![]);
}

#[test]
fn each_unit_is_named_with_every_row() {
    let w = Written::default();
    let b = shipped_bending().unwrap();
    let scaled = |f: &dyn Fn(&mut BendingRecord)| {
        let mut v = b.clone();
        v.iter_mut().for_each(f);
        check_bending(&v, &w)
    };
    for (what, s, likely) in [
        ("kPa", scaled(&|r| r.pressure_bar *= 100.0), "kPa"),
        ("MPa", scaled(&|r| r.pressure_bar /= 10.0), "MPa"),
        (
            "cm",
            scaled(&|r| {
                r.tip_uz_mm /= 10.0;
                r.tip_uy_mm /= 10.0
            }),
            "cm",
        ),
        (
            "rad",
            scaled(&|r| r.angle_deg = r.angle_deg.to_radians()),
            "rad",
        ),
        ("sign", scaled(&|r| r.tip_uy_mm = -r.tip_uy_mm), SIGN),
    ] {
        assert_eq!(s.len(), 1, "{what}: {s:?}");
        assert_eq!(s[0].likely, likely, "{what}");
        assert_eq!(s[0].rows.len(), 27, "{what}: every row listed");
    }
    let f = shipped_force().unwrap();
    let mut mn = f.clone();
    mn.iter_mut().for_each(|r| {
        r.force_n *= 1000.0;
        r.force_std_n *= 1000.0
    });
    let s = check_force(&mn, &w);
    assert_eq!(s.len(), 2, "{s:?}");
    assert!(s.iter().all(|x| x.likely == "mN"));
    assert!(s
        .iter()
        .any(|x| x.to_string().contains("name the column force_mn")));
    assert!(s.iter().any(|x| x.to_string().contains("force_std_mn")));
    let mut mpa = f;
    mpa.iter_mut().for_each(|r| r.pressure_bar /= 10.0);
    let s = check_force(&mpa, &w);
    assert_eq!(s.len(), 1, "{s:?}");
    assert_eq!(s[0].likely, "MPa");
    assert!(s[0].to_string().contains("pressure_mpa"), "{}", s[0]);
}

#[test]
fn another_separator_and_a_renamed_column_are_named() {
    let e = parse_force(
        "s.csv",
        "n_bellows;wall_thickness_mm;pressure_bar;force_n;force_std_n\n9;1,6;1;0,7;0,1\n",
    )
    .unwrap_err();
    assert!(matches!(e, ExperimentError::Separator { .. }), "{e}");
    let e = e.to_string();
    assert!(
        e.contains("s.csv, line 1") && e.contains("looks ;-separated"),
        "{e}"
    );
    assert!(!e.contains("missing column"), "{e}");
    let e = parse_force(
        "r.csv",
        "n_bellows,wall_thickness_mm,pressure_bar,blocked_force_n,force_std_n\n9,1.6,1,0.7,0.1\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(
            "column force_n: missing column (the header has blocked_force_n, which this \
             format does not have: renamed?)"
        ),
        "{e}"
    );
}

#[test]
fn implausible_values_are_an_error_listing_every_row() {
    let head =
        "n_bellows,wall_thickness_mm,pressure_bar,tip_uz_mm,tip_uy_mm,angle_deg,angle_std_deg";
    let e = parse_bending(
        "b.csv",
        &format!("{head}\n9,1.6,100,9.4,-35.9,23.57,1.95\n9,1.6,200,28.15,-57.30,42.10,3.37\n"),
    )
    .unwrap_err();
    let ExperimentError::Implausible { problems, .. } = &e else {
        panic!("{e}")
    };
    assert_eq!(problems.len(), 1);
    assert_eq!(problems[0].rows, [(2, "100".into()), (3, "200".into())]);
    let e = e.to_string();
    assert!(
        e.contains("column pressure_bar looks like kPa") && e.contains("pressure_kpa"),
        "{e}"
    );
    // named in its own column, the value is converted and passes
    let ok = format!(
        "{}\n9,1.6,100,9.4,-35.9,23.57,1.95\n",
        head.replace("pressure_bar", "pressure_kpa")
    );
    assert_eq!(parse_bending("b.csv", &ok).unwrap()[0].pressure_bar, 1.0);
}
