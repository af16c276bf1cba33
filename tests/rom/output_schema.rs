//! One output schema: a step of `simulate` and a prediction of `predict` write the same keys
//! for the same quantities (markers as `[{"uz_mm", "uy_mm"}]`), and pressures as given.
use crate::rom_common;

use surrogate::case::{OgdenSet, Query};
use surrogate::fe::simulate::StepResult;
use surrogate::rom::batch::PredictionRecord;

fn step() -> StepResult {
    StepResult {
        pressure_bar: 3.0,
        tip_uz_mm: 10.0,
        tip_uy_mm: -40.0,
        angle_deg: 30.0,
        markers: (1..=9).map(|k| [k as f64, -(k as f64)]).collect(),
        newton_iterations: 5,
        warm_start: false,
        substeps: 1,
        cutbacks: 0,
        residual: 1e-10,
        converged: true,
        min_gap_mm: 0.5,
        min_gap_at: "gap 1".into(),
        force_n: Some(1.5),
        contact_force_n: 0.0,
        clamp_force_n: 0.0,
        min_contact_gap_mm: 0.5,
    }
}

fn keys(v: &serde_json::Value) -> Vec<String> {
    let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
    k.sort();
    k
}

#[test]
fn simulate_and_predict_share_the_schema() {
    let s = serde_json::to_value(step()).unwrap();
    let m = rom_common::small_model(None);
    let q = Query::new(
        11,
        2.0,
        3.0,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    let p = m.predict(&q).unwrap();
    let r = serde_json::to_value(PredictionRecord::new(&q, &p.values, None, &[])).unwrap();
    for key in [
        "pressure_bar",
        "tip_uz_mm",
        "tip_uy_mm",
        "angle_deg",
        "force_n",
        "markers",
    ] {
        assert!(s.get(key).is_some() && r.get(key).is_some(), "{key}");
    }
    assert_eq!(s["markers"].as_array().unwrap().len(), 9);
    assert_eq!(r["markers"].as_array().unwrap().len(), 9);
    assert_eq!(keys(&s["markers"][0]), ["uy_mm", "uz_mm"]);
    assert_eq!(keys(&r["markers"][0]), keys(&s["markers"][0]));
    assert_eq!(s["markers"][8]["uz_mm"], 9.0);
    assert_eq!(r["markers"][8]["uy_mm"], p.values[17]);
    // pressures as given
    assert_eq!(r["pressure_bar"].to_string(), "3.0");
    assert_eq!(s["pressure_bar"].to_string(), "3.0");
}

/// Results written before the schema was unified (`[[Uz, Uy], …]`, e.g. cached baseline
/// ramps) are still read, and a step survives a round trip.
#[test]
fn older_marker_pairs_are_still_read() {
    let mut v = serde_json::to_value(step()).unwrap();
    v["markers"] = serde_json::json!((1..=9).map(|k| [k as f64, -(k as f64)]).collect::<Vec<_>>());
    let old: StepResult = serde_json::from_value(v).unwrap();
    assert_eq!(old, step());
    let back: StepResult = serde_json::from_value(serde_json::to_value(step()).unwrap()).unwrap();
    assert_eq!(back, step());
}
