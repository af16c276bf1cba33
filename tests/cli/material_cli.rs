//! The calibrated material can be used: a calibration report (`DIR/report.json`) is a material
//! wherever one is taken, the summary prints the set at full precision, a set typed back to
//! its printed digits is accepted at a bound, and the shipped domain is the plan's.
use std::path::Path;
use std::process::Output;

use surrogate::case::{OgdenSet, Query};
use surrogate::rom::Surrogate;

use crate::common::{repo, run, scratch, text, REPORT};

/// The calibrated set of a report.
fn best(path: &Path) -> [f64; 4] {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let b = &v["calibration"]["best"];
    ["mu1_mpa", "alpha1", "mu2_mpa", "alpha2"].map(|k| b[k].as_f64().unwrap())
}

fn predict(material: &str, t: &str) -> Output {
    run(&[
        "predict",
        "--model",
        "models/as_modelled/actuator.json",
        "--n",
        "11",
        "--t",
        t,
        "--pressure",
        "2.0",
        "--material",
        material,
    ])
}

#[test]
fn a_calibration_report_is_a_material_for_predict_export_and_queries() {
    let set = best(&repo().join(REPORT));
    let o = predict(REPORT, "2.0");
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    let m = Surrogate::load(&repo().join("models/as_modelled/actuator.json")).unwrap();
    let lib = m
        .predict(&Query::new(11, 2.0, 2.0, OgdenSet::from_array(set)))
        .unwrap();
    assert_eq!(json["tip_uz_mm"].as_f64().unwrap(), lib.tip_uz_mm());
    // the same as the four numbers at full precision
    let numbers = set.map(|v| v.to_string()).join(",");
    assert_eq!(text(&predict(&numbers, "2.0")).0, out);
    // export of a ramp at the calibrated set
    let dir = scratch("material_cli_export");
    let rs = dir.join("ramp.rs");
    let o = run(&[
        "export",
        "--model",
        "models/as_modelled/actuator.json",
        "--ramp",
        "--n",
        "11",
        "--t",
        "2.0",
        "--material",
        REPORT,
        "--rust",
        rs.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o).1);
    let header = std::fs::read_to_string(dir.join("ramp.h")).unwrap();
    assert!(
        header.contains(&format!("mu1 = {} MPa", set[0])),
        "{header}"
    );
    assert!(
        header.contains("#define SURROGATE_RAMP_IN_DOMAIN 1"),
        "{header}"
    );
    // a query CSV's material column
    let csv = dir.join("q.csv");
    std::fs::write(
        &csv,
        format!("n_bellows,wall_thickness_mm,pressure_bar,material\n11,2.0,2.0,{REPORT}\n"),
    )
    .unwrap();
    let o = run(&[
        "predict",
        "--model",
        "models/as_modelled/actuator.json",
        "--csv",
        csv.to_str().unwrap(),
        "--out",
        "-",
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(out.contains(&lib.tip_uz_mm().to_string()), "{out}");
    // a report that does not exist or holds no set: an error naming it, before any FE
    let o = run(&["simulate", "--material", "no/such/report.json"]);
    let err = text(&o).1;
    assert!(
        !o.status.success() && err.contains("no/such/report.json"),
        "{err}"
    );
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{}").unwrap();
    let o = run(&["validate", "--material", bad.to_str().unwrap()]);
    let err = text(&o).1;
    assert!(
        !o.status.success() && err.contains("calibration.best.mu1_mpa is missing"),
        "{err}"
    );
}

/// `calibrate` prints the set at full precision: the numbers of its summary, typed back,
/// are the report's set exactly, and `--material DIR/report.json` gives the same prediction.
#[test]
fn the_summary_prints_the_set_as_the_report_stores_it() {
    let dir = scratch("material_cli_calibrate");
    let o = run(&[
        "calibrate",
        "--model",
        "models/as_modelled/actuator.json",
        "--starts",
        "3",
        "--profile-points",
        "4",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o).1);
    let md = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    let row = md
        .lines()
        .find(|l| l.starts_with("| calibrated |"))
        .unwrap();
    let cells: Vec<f64> = row
        .split('|')
        .filter_map(|c| c.trim().parse().ok())
        .collect();
    let set = best(&dir.join("report.json"));
    assert_eq!(cells[..4], set, "{row}");
    let numbers = set.map(|v| v.to_string()).join(",");
    assert!(md.contains(&format!("--material {numbers}")), "{md}");
    let report = dir.join("report.json");
    let a = text(&predict(report.to_str().unwrap(), "2.0"));
    let b = text(&predict(&numbers, "2.0"));
    assert!(!a.0.is_empty() && a.0 == b.0, "{a:?} {b:?}");
}

/// A model whose domain is the box of its cases (no plan stated): the calibrated set lies on
/// its bounds, and the set printed to four decimals (term1_share 0.021607… below the bound
/// 0.021614…) is accepted, moved onto the bound with a note.
#[test]
fn a_set_printed_to_four_decimals_is_accepted_at_a_bound() {
    let dir = scratch("material_cli_tolerance");
    let mut m = Surrogate::load(&repo().join("models/as_modelled/actuator.json")).unwrap();
    m.training.plan_domain = None;
    let model = dir.join("cases_box.json");
    m.save(&model).unwrap();
    let o = run(&[
        "predict",
        "--model",
        model.to_str().unwrap(),
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "2.0",
        "--material",
        "0.0382,5.9961,-5.1949,-1.9965",
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("note: term1_share = 0.0216")
            && err.contains("note: alpha2 = -1.9965")
            && err.contains("predicted at the end"),
        "{err}"
    );
    assert!(out.contains("\"in_domain\": true"), "{out}");
}

/// The shipped model's domain is the plan's nominal 1.4–2.6 mm, not the span of its cases.
#[test]
fn predict_accepts_the_plans_wall_thickness_range() {
    for t in ["1.4", "2.6"] {
        let o = predict("ogden_002", t);
        assert!(o.status.success(), "T = {t}: {}", text(&o).1);
    }
    let o = predict("ogden_002", "1.39");
    let err = text(&o).1;
    assert!(
        !o.status.success()
            && err.contains("wall_thickness_mm = 1.39 outside the training domain [1.4, 2.6]"),
        "{err}"
    );
}

/// `train` on a merged snapshot set states the domain of the plan beside it.
#[test]
fn train_states_the_plans_domain_in_the_model_file() {
    let dir = scratch("material_cli_train");
    let plan = dir.join("plan.json");
    let cases = dir.join("cases");
    let set = dir.join("set.csv");
    let model = dir.join("model.json");
    let p = |p: &Path| p.to_str().unwrap().to_string();
    for args in [
        vec![
            "snapshots".to_string(),
            "plan".into(),
            "--cases".into(),
            "24".into(),
            "--seed".into(),
            "5".into(),
            "--n-values".into(),
            "9,11,13".into(),
            "--pressures".into(),
            "3:0.5".into(),
            "--out".into(),
            p(&plan),
        ],
        vec![
            "snapshots".into(),
            "run".into(),
            "--plan".into(),
            p(&plan),
            "--out".into(),
            p(&cases),
            "--runner".into(),
            "analytic".into(),
            "--quiet".into(),
        ],
        vec![
            "snapshots".into(),
            "merge".into(),
            "--from".into(),
            p(&cases),
            "--out".into(),
            p(&set),
        ],
    ] {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&args);
        assert!(o.status.success(), "{args:?}: {}", text(&o).1);
    }
    let o = run(&[
        "train",
        "--data",
        &p(&set),
        "--folds",
        "2",
        "--quiet",
        "--out",
        &p(&model),
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(out.contains("domain (the plan's nominal ends"), "{out}");
    let m = Surrogate::load(&model).unwrap();
    let stated = m.training.plan_domain.as_ref().expect("stated");
    assert!(
        stated.plan.contains("set.plan.json (plan "),
        "{}",
        stated.plan
    );
    assert_eq!(stated.plan_cases, 24);
    let plan = surrogate::snapshots::plan::Plan::read(&plan).unwrap();
    assert_eq!(
        *stated,
        plan.stated_domain(&m.sampled_domain(), &p(&dir.join("set.plan.json")))
    );
    assert_eq!(m.domain(), plan.sampled_domain());
}
