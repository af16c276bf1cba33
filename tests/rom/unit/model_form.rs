//! The unit tests of `src/rom/model_form.rs`.

use surrogate::case::OgdenSet;
use surrogate::rom::model_form::*;
use surrogate::rom::{Q_ANGLE, Q_FORCE};

fn source() -> CalibrationSource {
    CalibrationSource {
        report: "r.json".into(),
        report_checksum: "crc32:0".into(),
        model: "m".into(),
        objective: "tip=1".into(),
        material: OgdenSet::from_array([1.0, 2.0, -1.0, -1.0]),
        configurations: 12,
    }
}

fn residual(p: f64, value: f64) -> Residual {
    Residual {
        pressure_bar: p,
        output: Q_ANGLE,
        value,
    }
}

#[test]
fn levels_are_floored_by_the_global_rms() {
    // 6 residuals at 1 bar of size 1, 6 at 3 bar of size 3: rms √5
    let mut r: Vec<Residual> = (0..6).map(|k| residual(1.0, [1.0, -1.0][k % 2])).collect();
    r.extend((0..6).map(|_| residual(3.0, 3.0)));
    let m = ModelFormError::from_residuals(source(), &r).unwrap();
    let o = &m.outputs[0];
    assert_eq!(o.name, "angle_deg");
    assert!((o.rms - 5f64.sqrt()).abs() < 1e-12);
    assert!((o.mean - 1.5).abs() < 1e-12);
    assert_eq!(o.level_count, vec![6, 6]);
    assert_eq!(o.at_levels, vec![o.rms, 3.0]);
    assert_eq!(m.error(Q_ANGLE, 1.0), Some(o.rms));
    assert_eq!(m.error(Q_ANGLE, 2.0), Some(0.5 * (o.rms + 3.0)));
    assert_eq!(m.error(Q_ANGLE, 3.5), Some(3.0));
    assert_eq!(m.error(Q_FORCE, 2.0), None);
    assert_eq!(m.at(2.0).angle_deg(), m.error(Q_ANGLE, 2.0));
    m.check().unwrap();
}

#[test]
fn a_level_with_few_residuals_reports_the_global_rms() {
    let mut r: Vec<Residual> = (0..6).map(|_| residual(1.0, 1.0)).collect();
    r.extend((0..2).map(|_| residual(3.0, 10.0)));
    let m = ModelFormError::from_residuals(source(), &r).unwrap();
    let o = &m.outputs[0];
    assert_eq!(o.level_count, vec![6, 2]);
    assert_eq!(o.at_levels, vec![o.rms, o.rms]);
}

#[test]
fn too_few_or_bad_residuals_are_refused() {
    let e = ModelFormError::from_residuals(source(), &[residual(1.0, 1.0)]).unwrap_err();
    assert!(e.to_string().contains("at least 3 residuals"), "{e}");
    let e = ModelFormError::from_residuals(source(), &[residual(1.0, f64::NAN)]).unwrap_err();
    assert!(e.to_string().contains("finite residual"), "{e}");
}

#[test]
fn check_names_the_inconsistent_field() {
    let r: Vec<Residual> = (0..6).map(|_| residual(2.0, 1.0)).collect();
    let mut m = ModelFormError::from_residuals(source(), &r).unwrap();
    m.outputs[0].at_levels[0] = 0.5;
    let e = m.check().unwrap_err();
    assert!(e.contains("at least the output's rms 1"), "{e}");
    m.outputs[0].name = "angle".into();
    assert!(m.check().unwrap_err().contains("\"angle\""));
}
