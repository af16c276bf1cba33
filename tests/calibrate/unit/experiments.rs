//! The unit tests of `src/calibrate/experiments.rs`.

use surrogate::calibrate::experiments::*;

#[test]
fn shipped_files_parse() {
    let b = shipped_bending().unwrap();
    assert_eq!(b.len(), 27);
    assert_eq!(b[0].n_bellows, 9);
    assert!((b[2].tip_uy_mm + 65.76).abs() < 1e-12);
    assert_eq!(shipped_force().unwrap().len(), 27);
}

#[test]
fn malformed_rows_name_line_and_column() {
    let text = "n_bellows,wall_thickness_mm,pressure_bar,tip_uz_mm,tip_uy_mm,angle_deg,angle_std_deg\n9,1.6,1,abc,-35.9,23.57,1.95\n";
    let e = parse_bending("x.csv", text).unwrap_err();
    assert_eq!(
        e.to_string(),
        "x.csv, line 2, column tip_uz_mm: 'abc' is not a finite number"
    );
    let e = parse_bending("x.csv", "n_bellows,pressure_bar\n9,1\n").unwrap_err();
    assert!(
        e.to_string()
            .contains("column wall_thickness_mm: missing column"),
        "{e}"
    );
}

#[test]
fn extra_columns_duplicates_and_bad_values_are_named() {
    let head = "n_bellows,wall_thickness_mm,pressure_bar,force_n,force_std_n";
    let e = parse_force(
        "f.csv",
        &format!("{head},force_lbf\n9,1.6,1,0.7,0.05,0.1\n"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("f.csv, line 1, column force_lbf: unexpected column"),
        "{e}"
    );
    let e = parse_force(
        "f.csv",
        &format!("{head}\n9,1.6,1,0.7,0.05\n9,1.6,2,1.7,0.05\n9.0,1.6,1,0.8,0.05\n"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(
            "line 4, column row: duplicate of line 2 (same configuration: N = 9, T = 1.6 \
             mm, P = 1 bar)"
        ),
        "{e}"
    );
    let e = parse_force("f.csv", &format!("{head}\n9,1.6,1,NaN,0.05\n"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 2, column force_n: 'NaN' is not a finite number"),
        "{e}"
    );
    let e = parse_force("f.csv", &format!("{head}\n9,1.6,1,0.7,0\n"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("column force_std_n"), "{e}");
    let e = parse_force("f.csv", &format!("{head}\n9.5,1.6,1,0.7,0.1\n"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("column n_bellows: '9.5' is not a non-negative integer"),
        "{e}"
    );
    let ok = parse_force("f.csv", &format!("{head}\n9.0,1.6,1,0.7,0.1\n")).unwrap();
    assert_eq!(ok[0].n_bellows, 9);
    let e = parse_force("f.csv", &format!("{head}\n"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("no records"), "{e}");
    let m =
        "n_bellows,wall_thickness_mm,pressure_bar,marker,uz_mm,uy_mm,std_mm\n9,1.6,1,10,0,0,1\n";
    let e = parse_markers("m.csv", m).unwrap_err().to_string();
    assert!(
        e.contains("column marker: 10 is not a marker number"),
        "{e}"
    );
}

#[test]
fn columns_in_other_units_are_converted_and_listed() {
    let text =
        "n_bellows,wall_thickness_mm,pressure_kpa,tip_uz_cm,tip_uy_cm,angle_rad,angle_std_deg\n\
                9,1.6,100,0.94,-3.59,0.41137,1.95\n";
    let p = bending_from("k.csv", text).unwrap();
    let r = &p.rows()[0];
    assert!((r.pressure_bar - 1.0).abs() < 1e-12);
    assert!((r.tip_uz_mm - 9.4).abs() < 1e-12 && (r.tip_uy_mm + 35.9).abs() < 1e-12);
    assert!((r.angle_deg - 23.57).abs() < 0.01);
    assert_eq!(
        p.converted(),
        [
            "pressure_kpa → pressure_bar × 0.01",
            "tip_uz_cm → tip_uz_mm × 10",
            "tip_uy_cm → tip_uy_mm × 10",
            "angle_rad → angle_deg × 57.29577951308232",
        ]
    );
    let f = "n_bellows,wall_thickness_mm,pressure_bar,force_mn,force_std_mn\n9,1.6,1,759,58\n";
    let r = &parse_force("f.csv", f).unwrap()[0];
    assert!((r.force_n - 0.759).abs() < 1e-12 && (r.force_std_n - 0.058).abs() < 1e-12);
    // a quantity given in two units is refused, naming both
    let e = parse_force(
        "f.csv",
        "n_bellows,wall_thickness_mm,pressure_bar,pressure_kpa,force_n,force_std_n\n9,1.6,1,100,0.7,0.1\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("column pressure_bar: column given twice, as pressure_bar and as pressure_kpa"),
        "{e}"
    );
}

#[test]
fn bending_error_is_euclidean() {
    assert!((bending_error(3.0, 4.0, 0.0, 0.0) - 5.0).abs() < 1e-15);
}
