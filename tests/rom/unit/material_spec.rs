//! The unit tests of `src/rom/material_spec.rs`.

use surrogate::rom::material_spec::*;

#[test]
fn only_json_paths_are_reports() {
    for spec in ["dir/report.json", " R.JSON ", "a.Json"] {
        assert!(is_report(spec), "{spec}");
    }
    for spec in ["ogden_002", "1,2,-3,-0.5", "neo_hookean:2", ".json", "json"] {
        assert!(!is_report(spec), "{spec}");
    }
}

#[test]
fn a_report_without_a_set_is_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("material_spec_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("report.json");
    std::fs::write(&path, r#"{"calibration": {"best": {"mu1_mpa": 1.0}}}"#).unwrap();
    let e = expand(path.to_str().unwrap()).unwrap_err().to_string();
    assert!(e.contains("calibration.best.alpha1 is missing"), "{e}");
    std::fs::write(&path, "not json").unwrap();
    let e = expand(path.to_str().unwrap()).unwrap_err().to_string();
    assert!(e.contains("calibration report"), "{e}");
    let e = expand(dir.join("absent.json").to_str().unwrap()).unwrap_err();
    assert!(e.to_string().contains("absent.json"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
