//! The model-form error on the command line: `surrogate model-form` stores it, `predict`
//! reports it labelled beside `--std` (one query and a batch), `export` writes it, and a model
//! without one says so.
use std::path::{Path, PathBuf};

use crate::common::{outcome, repo, shared_dir, REPORT};

const SHIPPED: &str = "models/as_modelled/actuator.json";

fn dir() -> PathBuf {
    shared_dir("model_form_cli")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn predict_reports_the_model_form_error_beside_the_std() {
    let (model, report) = (repo().join(SHIPPED), repo().join(REPORT));
    let (ok, out, err) = outcome(&[
        "predict",
        "--model",
        s(&model),
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "3.0",
        "--material",
        s(&report),
        "--std",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["std_is"], "surrogate vs FE");
    let mf = &v["model_form_error"];
    assert_eq!(mf["what"], "model-form error (calibration residuals)");
    let angle = mf["angle_deg"].as_f64().unwrap();
    // at 3 bar: the rms of the 9 recorded designs there (11.8°), above the global 8.9°
    assert!((angle - 11.812).abs() < 1e-3, "{angle}");
    assert!(angle > 20.0 * v["std"]["angle_deg"].as_f64().unwrap());
    assert!(
        err.contains("model-form error (calibration residuals) at 3 bar")
            && err.contains("angle ±11.812 deg")
            && err.contains("--std is the surrogate vs FE only"),
        "{err}"
    );
    // without --std, the model-form error is still there
    let (ok, out, _) = outcome(&[
        "predict",
        "--model",
        s(&model),
        "--n",
        "9",
        "--t",
        "1.6",
        "--pressure",
        "1.0",
        "--material",
        "ogden_002",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v.get("std").is_none() && v.get("std_is").is_none());
    assert!(v["model_form_error"]["force_n"].as_f64().unwrap() > 0.5);
}

#[test]
fn batch_predictions_carry_a_model_form_column_per_recorded_output() {
    let d = dir();
    let input = d.join("q.csv");
    std::fs::write(
        &input,
        "id,n_bellows,wall_thickness_mm,pressure_bar,material\na,11,2.0,1.5,ogden_002\nb,9,1.6,3.0,ogden_002\n",
    )
    .unwrap();
    let out = d.join("p.csv");
    let (ok, _, err) = outcome(&[
        "predict",
        "--model",
        s(&repo().join(SHIPPED)),
        "--csv",
        s(&input),
        "--out",
        s(&out),
        "--std",
    ]);
    assert!(ok, "{err}");
    let mut r = csv::Reader::from_path(&out).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{name}: {header:?}"))
    };
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    let angle_mf = col("angle_deg_model_form");
    let angle_std = col("angle_deg_std");
    for name in [
        "tip_uz_mm_model_form",
        "tip_uy_mm_model_form",
        "force_n_model_form",
    ] {
        col(name);
    }
    assert!(
        !header.iter().any(|h| h == "m1_uz_mm_model_form"),
        "markers were not recorded"
    );
    let at = |row: usize, c: usize| rows[row][c].parse::<f64>().unwrap();
    assert!(at(1, angle_mf) > at(0, angle_mf), "3 bar above 1.5 bar");
    assert!(at(0, angle_mf) > 20.0 * at(0, angle_std));
    // a query column of that name would be overwritten: refused
    std::fs::write(
        &input,
        "n_bellows,wall_thickness_mm,pressure_bar,material,angle_deg_model_form\n11,2,1,ogden_002,3\n",
    )
    .unwrap();
    let (ok, _, err) = outcome(&[
        "predict",
        "--model",
        s(&repo().join(SHIPPED)),
        "--csv",
        s(&input),
        "--out",
        s(&out),
    ]);
    assert!(
        !ok && err.contains("column `angle_deg_model_form` would be overwritten"),
        "{err}"
    );
}

#[test]
fn a_model_without_a_model_form_error_says_so() {
    let (ok, out, err) = outcome(&[
        "predict",
        "--model",
        s(&repo().join("models/as_modelled/actuator_coarse.json")),
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "2.0",
        "--material",
        "ogden_002",
    ]);
    assert!(ok, "{err}");
    assert!(!out.contains("model_form_error"));
    assert!(
        err.contains("carries no model-form error (calibration residuals)")
            && err.contains("surrogate model-form"),
        "{err}"
    );
}

#[test]
fn model_form_command_stores_it_and_refuses_a_report_of_another_model() {
    let d = dir();
    let out = d.join("coarse_with.json");
    let _ = std::fs::remove_file(&out);
    // the committed report was made through the standard-mesh model, not the coarse one
    let (ok, _, err) = outcome(&[
        "model-form",
        "--model",
        s(&repo().join("models/as_modelled/actuator_coarse.json")),
        "--calibration",
        s(&repo().join(REPORT)),
        "--out",
        s(&out),
    ]);
    assert!(!ok && !out.exists());
    assert!(
        err.contains("calibration.configurations[0].tip_uz_mm")
            && err.contains("calibrate through this model first"),
        "{err}"
    );
    // through the shipped model: the same model (checksum), now with its error
    let copy = d.join("shipped_again.json");
    let _ = std::fs::remove_file(&copy);
    let (shipped, report) = (repo().join(SHIPPED), repo().join(REPORT));
    let args = [
        "model-form",
        "--model",
        s(&shipped),
        "--calibration",
        s(&report),
        "--out",
        s(&copy),
    ];
    let (ok, table, err) = outcome(&args);
    assert!(ok, "{err}");
    assert!(
        table.contains("angle_deg") && table.contains("8.8511"),
        "{table}"
    );
    let shipped: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(repo().join(SHIPPED)).unwrap()).unwrap();
    let again: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&copy).unwrap()).unwrap();
    assert_eq!(again["checksum"], shipped["checksum"]);
    assert_eq!(again["format_version"], 3);
    assert_eq!(
        again["model_form"]["content"]["outputs"],
        shipped["model_form"]["content"]["outputs"]
    );
    let (ok, _, err) = outcome(&args);
    assert!(
        !ok && err.contains("exists") && err.contains("--force"),
        "{err}"
    );
}

#[test]
fn export_writes_the_model_form_error_into_the_ramp_and_its_header() {
    let d = dir();
    let (rs, h) = (d.join("ramp.rs"), d.join("ramp.h"));
    let (ok, _, err) = outcome(&[
        "export",
        "--model",
        s(&repo().join(SHIPPED)),
        "--ramp",
        "--n",
        "11",
        "--t",
        "2.0",
        "--material",
        "ogden_002",
        "--rust",
        s(&rs),
        "--header",
        s(&h),
    ]);
    assert!(ok, "{err}");
    let rs = std::fs::read_to_string(rs).unwrap();
    let h = std::fs::read_to_string(h).unwrap();
    assert!(rs.contains("pub static MODEL_FORM: Option<ModelFormTables<'static>> = Some("));
    assert!(
        rs.contains("angle_deg: 8.8511 at 1 bar, 8.8511 at 2 bar, 11.8119 at 3 bar"),
        "{rs}"
    );
    assert!(h.contains("#define SURROGATE_MODEL_FORM_N_LEVELS 3"), "{h}");
    assert!(
        h.contains("#define SURROGATE_MODEL_FORM_ANGLE {8.851"),
        "{h}"
    );
}
