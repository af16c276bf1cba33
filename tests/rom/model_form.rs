//! The model-form error: learned from the calibration's residuals, stored in the model file
//! (checked on load), at least the calibration's rms residual at every recorded design, and
//! the same in the library and in an exported model.
use std::path::{Path, PathBuf};

use surrogate::case::{OgdenSet, Query};
use surrogate::predict::{ModelFormTables, ANGLE, FORCE, TIP_UY, TIP_UZ};
use surrogate::rom::model_form::{CalibrationSource, ModelFormError, Residual};
use surrogate::rom::model_form_report::from_calibration_report;
use surrogate::rom::{RomError, Surrogate};

use crate::rom_common;

const REPORT: &str = "fe_reference/calibration/surrogate/report.json";
const SHIPPED: &str = "models/as_modelled/actuator.json";

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
}

/// `(N, T, P, [(output, calibrated − recorded)])` of every fitted configuration of the
/// committed calibration report, read here from its JSON without the library.
type Row = (u32, f64, f64, Vec<(usize, f64)>);

fn report_rows() -> (Vec<Row>, [f64; 4]) {
    let text = std::fs::read_to_string(root(REPORT)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cal = &v["calibration"];
    let best = &cal["best"];
    let material = ["mu1_mpa", "alpha1", "mu2_mpa", "alpha2"].map(|k| best[k].as_f64().unwrap());
    let columns = [
        (TIP_UZ, "uz_cal_mm", "uz_exp_mm"),
        (TIP_UY, "uy_cal_mm", "uy_exp_mm"),
        (ANGLE, "angle_cal_deg", "angle_exp_deg"),
        (FORCE, "force_cal_n", "force_exp_n"),
    ];
    let rows = cal["configurations"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["fitted"].as_bool().unwrap())
        .map(|c| {
            let r = columns
                .iter()
                .filter_map(|&(o, p, e)| Some((o, c[p].as_f64()? - c[e].as_f64()?)))
                .collect();
            (
                c["n_bellows"].as_u64().unwrap() as u32,
                c["wall_thickness_mm"].as_f64().unwrap(),
                c["pressure_bar"].as_f64().unwrap(),
                r,
            )
        })
        .collect();
    (rows, material)
}

/// The target of issue 37: at every recorded design and pressure, the shipped model's
/// model-form error of tip Uz, tip Uy, angle and force is at least the calibration's rms
/// residual of that output (over all configurations, and over those at the same pressure).
#[test]
fn shipped_model_form_error_is_at_least_the_calibration_rms_at_every_recorded_design() {
    let model = Surrogate::load(&root(SHIPPED)).unwrap();
    let (rows, material) = report_rows();
    assert_eq!(rows.len(), 27);
    let residuals = |o: usize, p: Option<f64>| -> Vec<f64> {
        rows.iter()
            .filter(|r| p.is_none_or(|p| r.2 == p))
            .flat_map(|r| r.3.iter().filter(|x| x.0 == o).map(|x| x.1))
            .collect()
    };
    for &(n, t, p, ref r) in &rows {
        let q = Query::new(n, t, p, OgdenSet::from_array(material));
        let e = model
            .model_form_error(&q)
            .expect("the shipped model carries its model-form error");
        for &(o, _) in r {
            let got = e.values[o].unwrap_or_else(|| panic!("output {o} has no model-form error"));
            let global = rms(&residuals(o, None));
            let level = rms(&residuals(o, Some(p)));
            assert!(
                got >= global * (1.0 - 1e-12) && got >= level * (1.0 - 1e-12),
                "N {n} T {t} P {p} output {o}: model-form error {got} < rms {global} or level rms {level}"
            );
        }
    }
    // the issue's numbers: the angle misses by 8.9° rms, the surrogate's std is about 0.2°
    let q = Query::new(11, 2.0, 2.0, OgdenSet::from_array(material));
    let mut pred = model.new_prediction();
    model.predict_with_std_into(&q, &mut pred).unwrap();
    let angle = model.model_form_error(&q).unwrap().angle_deg().unwrap();
    assert!((angle - 8.851).abs() < 1e-3, "{angle}");
    assert!(angle > 20.0 * pred.std_angle_deg());
}

/// The shipped model's model-form error is the one the committed report gives through it
/// today (same report bytes, same numbers when learned again).
#[test]
fn shipped_model_form_error_is_learned_from_the_committed_report() {
    let model = Surrogate::load(&root(SHIPPED)).unwrap();
    let stored = model.model_form().unwrap().clone();
    let bytes = std::fs::read(root(REPORT)).unwrap();
    assert_eq!(
        stored.calibration.report_checksum,
        format!("crc32:{:08x}", crc32fast::hash(&bytes))
    );
    let again = from_calibration_report(&model, &root(REPORT)).unwrap();
    assert_eq!(again.outputs, stored.outputs);
    assert_eq!(again.pressures, stored.pressures);
    assert_eq!(again.pressures, vec![1.0, 2.0, 3.0]);
    assert_eq!(again.calibration.configurations, 27);
}

/// A report whose predictions are not the model's is refused, naming the field and value.
#[test]
fn a_report_made_through_another_model_is_refused() {
    let coarse = Surrogate::load(&root("models/as_modelled/actuator_coarse.json")).unwrap();
    let e = from_calibration_report(&coarse, &root(REPORT)).unwrap_err();
    let RomError::CalibrationReport {
        field, expected, ..
    } = &e
    else {
        panic!("expected a calibration-report error, got {e}");
    };
    assert!(field.starts_with("calibration.configurations[0]."), "{e}");
    assert!(
        expected.contains("calibrate through this model first"),
        "{e}"
    );
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("model_form_report");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("report.json");
    std::fs::write(&bad, r#"{"calibration": {"best": {}}}"#).unwrap();
    let e = from_calibration_report(&coarse, &bad)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("calibration report") && e.contains("missing field"),
        "{e}"
    );
}

fn synthetic_error() -> ModelFormError {
    let source = CalibrationSource {
        report: "r.json".into(),
        report_checksum: "crc32:00000000".into(),
        model: "m".into(),
        objective: "tip=1".into(),
        material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
        configurations: 18,
    };
    let residuals: Vec<Residual> = (0..18)
        .flat_map(|k| {
            let p = [1.0, 2.0, 3.0][k % 3];
            [
                Residual {
                    pressure_bar: p,
                    output: ANGLE,
                    value: p * if k % 2 == 0 { 1.0 } else { -2.0 },
                },
                Residual {
                    pressure_bar: p,
                    output: TIP_UZ,
                    value: 3.0,
                },
            ]
        })
        .collect();
    ModelFormError::from_residuals(source, &residuals).unwrap()
}

/// Save → load keeps the model-form error and the model's checksum; its own checksum, its
/// consistency and the version are checked on load; a version 2 file still loads.
#[test]
fn model_form_error_round_trips_and_is_checked_on_load() {
    let mut m = rom_common::small_model(None);
    let bare = m.to_json().unwrap();
    let sum = m.checksum().unwrap();
    m.model_form = Some(synthetic_error());
    assert_eq!(
        m.checksum().unwrap(),
        sum,
        "the model's identity is unchanged"
    );
    let text = m.to_json().unwrap();
    assert!(text.contains("\"format_version\":3") && text.contains("\"model_form\":{"));
    let back = Surrogate::from_json(&text, "m.json").unwrap();
    assert_eq!(back, m);
    assert_eq!(back.model_form(), m.model_form());

    let tampered = text.replacen("\"objective\":\"tip=1\"", "\"objective\":\"tip=2\"", 1);
    let e = Surrogate::from_json(&tampered, "m.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("model_form checksum mismatch"), "{e}");

    let v2 = bare.replacen("\"format_version\":3", "\"format_version\":2", 1);
    let old = Surrogate::from_json(&v2, "old.json").unwrap();
    assert!(old.model_form().is_none());
    assert!(old
        .model_form_error(&Query::new(
            11,
            2.0,
            1.0,
            OgdenSet::from_array([1.13, 3.11, -13.17, -0.6])
        ))
        .is_none());
    let v2_with = text.replacen("\"format_version\":3", "\"format_version\":2", 1);
    let e = Surrogate::from_json(&v2_with, "old.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("model_form in a format version 2 file"), "{e}");

    // an error below its output's rms, with a checksum that matches: refused as inconsistent
    let mut low = synthetic_error();
    low.outputs[0].at_levels[0] = 0.0;
    m.model_form = Some(low);
    let e = Surrogate::from_json(&m.to_json().unwrap(), "m.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("inconsistent model-form error") && e.contains("at least"),
        "{e}"
    );
}

/// The exported tables give the library's error at every pressure, and the exported source
/// carries them.
#[test]
fn exported_model_form_tables_agree_with_the_library() {
    let mut m = rom_common::small_model(None);
    m.model_form = Some(synthetic_error());
    let err = m.model_form().unwrap();
    let (pressures, outputs, values) = err.tables();
    let t = ModelFormTables {
        pressures: &pressures,
        outputs: &outputs,
        values: &values,
    };
    for i in 0..=40 {
        let p = -0.2 + 0.1 * i as f64;
        for o in 0..22 {
            assert_eq!(t.error(o, p), err.error(o, p), "output {o}, P {p}");
        }
    }
    assert!(t.error(FORCE, 2.0).is_none() && t.error(ANGLE, 2.0).is_some());
    use surrogate::rom::export::{c_header, rust_source, Precision};
    let sum = m.checksum().unwrap();
    let src = rust_source(&m, Precision::F32, &sum).unwrap();
    assert!(src.contains("pub static MODEL_FORM: Option<ModelFormTables<'static>> = Some("));
    assert!(src.contains("model-form error (calibration residuals)"));
    let h = c_header(&m, Precision::F32, &sum);
    assert!(
        h.contains("#define SURROGATE_MODEL_FORM_N_LEVELS 3\n"),
        "{h}"
    );
    assert!(
        h.contains("#define SURROGATE_MODEL_FORM_P_BAR {1.0, 2.0, 3.0}\n"),
        "{h}"
    );
    assert!(h.contains("#define SURROGATE_MODEL_FORM_ANGLE {"), "{h}");
    m.model_form = None;
    let h = c_header(&m, Precision::F32, &sum);
    assert!(
        h.contains("#define SURROGATE_MODEL_FORM_N_LEVELS 0\n"),
        "{h}"
    );
    let src = rust_source(&m, Precision::F32, &sum).unwrap();
    assert!(src.contains("pub static MODEL_FORM: Option<ModelFormTables<'static>> = None;"));
}
