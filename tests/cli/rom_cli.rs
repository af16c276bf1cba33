//! The `surrogate train / predict / export` subcommands, every flag and the bad-input messages.
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::OnceLock;

use crate::common::{bin, fails_with, shared_dir, text};

fn dir() -> PathBuf {
    shared_dir("rom_cli")
}

/// `surrogate train --force --synthetic <cases> --folds <folds> --quiet <extra…> --out <out>`.
fn train_synthetic(cases: usize, folds: usize, extra: &[&str], out: &Path) -> Output {
    bin()
        .args(["train", "--force", "--synthetic", &cases.to_string()])
        .args(["--folds", &folds.to_string(), "--quiet"])
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// Trains once (synthetic, 30 cases, 3 folds) and returns the model path.
fn model() -> &'static PathBuf {
    static MODEL: OnceLock<PathBuf> = OnceLock::new();
    MODEL.get_or_init(|| {
        let path = dir().join("model.json");
        let o = bin()
            .args([
                "train",
                "--force",
                "--synthetic",
                "30",
                "--folds",
                "3",
                "--quiet",
                "--out",
            ])
            .arg(&path)
            .arg("--held-out")
            .arg(dir().join("held_out.csv"))
            .arg("--plot")
            .arg(dir().join("held_out.svg"))
            .output()
            .unwrap();
        let (out, err) = text(&o);
        assert!(o.status.success(), "{err}");
        assert!(
            out.contains("validation: 3-fold by case") && out.contains("force_n"),
            "{out}"
        );
        assert!(out.contains("largest held-out error of tip_uz_mm"), "{out}");
        let held = std::fs::read_to_string(dir().join("held_out.csv")).unwrap();
        let mut lines = held.lines();
        assert_eq!(
            lines.next(),
            Some("case_id,n_bellows,repeat,fold,pressure_bar,output,fe,predicted,std,error")
        );
        // 30 cases × the synthetic grid × 4 scalar outputs
        assert_eq!(lines.count() % (30 * 4), 0);
        let svg = std::fs::read_to_string(dir().join("held_out.svg")).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("held-out RMSE"));
        path
    })
}

fn predict(args: &[&str]) -> Output {
    bin()
        .arg("predict")
        .arg("--model")
        .arg(model())
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn train_from_csv_file_reports_skipped_rows() {
    let cfg = surrogate::rom::synthetic::SyntheticConfig {
        n_cases: 20,
        unconverged_fraction: 0.2,
        ..Default::default()
    };
    let csv = dir().join("snap.csv");
    surrogate::rom::synthetic::write_csv(&cfg, std::fs::File::create(&csv).unwrap()).unwrap();
    let out = dir().join("from_csv.json");
    let o = bin()
        .args([
            "train", "--force", "--folds", "2", "--quiet", "--only", "poly", "--data",
        ])
        .arg(&csv)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let (stdout, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("unconverged rows skipped") && err.contains("dropped"),
        "{err}"
    );
    assert!(err.contains("unused (see --fill-truncated)"), "{err}");
    let o = bin()
        .args([
            "train",
            "--force",
            "--folds",
            "2",
            "--quiet",
            "--fill-truncated",
            "--data",
        ])
        .arg(&csv)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = text(&o).1;
    assert!(
        o.status.success() && err.contains("through gappy POD"),
        "{err}"
    );
    let m = surrogate::rom::Surrogate::load(&out).unwrap();
    assert!(m.training.filled_cases > 0);
    assert!(
        stdout.contains("direct/poly") || stdout.contains("field/poly"),
        "{stdout}"
    );
    assert!(!stdout.contains("/gp "), "{stdout}");
}

#[test]
fn prefer_poly_within_a_large_margin_selects_the_polynomial() {
    let out = dir().join("fast.json");
    let o = train_synthetic(20, 2, &["--prefer-poly-within", "1000"], &out);
    let (stdout, err) = text(&o);
    assert!(o.status.success(), "{err}");
    // the chosen table follows the candidates
    let chosen = stdout.split("validation:").nth(1).unwrap();
    assert!(
        chosen.contains("/poly") && !chosen.contains("/gp "),
        "{stdout}"
    );
    let o = bin()
        .args([
            "train",
            "--force",
            "--synthetic",
            "20",
            "--prefer-poly-within=-1",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    fails_with(&o, &["--prefer-poly-within"]);
}

#[test]
fn predict_single_query_prints_json_with_markers_and_std() {
    let o = predict(&[
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "2.0",
        "--material",
        "ogden_002",
        "--std",
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in ["tip_uz_mm", "tip_uy_mm", "angle_deg", "force_n"] {
        assert!(v[k].is_f64() && v["std"][k].is_f64(), "{k}: {out}");
    }
    assert_eq!(v["markers"].as_array().unwrap().len(), 9);
    assert!(v["tip_uy_mm"].as_f64().unwrap() < 0.0);
    // explicit Ogden numbers give the same result as the name
    let o2 = predict(&[
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "2.0",
        "--material",
        "1.13,3.11,-13.17,-0.6",
        "--std",
    ]);
    assert_eq!(text(&o2).0, out);
}

/// Outside the training domain is an error by default; `--allow-extrapolation` predicts and
/// the JSON says which inputs were outside and whether they were clamped.
#[test]
fn extrapolation_is_refused_by_default_and_flagged_when_allowed() {
    let q = |p: &str, t: &str| {
        vec![
            "--n".to_string(),
            "11".into(),
            "--t".into(),
            t.into(),
            "--pressure".into(),
            p.into(),
            "--material".into(),
            "ogden_002".into(),
        ]
    };
    let run = |args: Vec<String>| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        predict(&a)
    };
    for (p, t, name) in [
        ("5", "2.0", "pressure_bar = 5 outside"),
        ("-1", "2.0", "pressure_bar = -1 outside"),
        ("1", "5", "wall_thickness_mm = 5 outside"),
    ] {
        let o = run(q(p, t));
        fails_with(&o, &[name, "--allow-extrapolation"]);
        let mut strict = q(p, t);
        strict.push("--strict".into());
        fails_with(&run(strict), &[name]);
    }
    let end = run(q("3.5", "2.0"));
    let end: serde_json::Value = serde_json::from_str(&text(&end).0).unwrap();
    assert_eq!(end["in_domain"], true);
    let mut allowed = q("5", "2.0");
    allowed.push("--allow-extrapolation".into());
    let o = run(allowed);
    let (out, err) = text(&o);
    assert!(o.status.success() && err.contains("clamped"), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    // the pressure as given, the values of the grid's end, and the flags
    assert_eq!(v["pressure_bar"], 5.0);
    assert_eq!(v["in_domain"], false);
    assert_eq!(v["outside_domain"][0]["input"], "pressure_bar");
    assert_eq!(v["outside_domain"][0]["clamped"], true);
    assert_eq!(v["outside_domain"][0]["used"], 3.5);
    assert_eq!(v["tip_uz_mm"], end["tip_uz_mm"]);
    let mut allowed = q("1", "5");
    allowed.push("--allow-extrapolation".into());
    let v: serde_json::Value = serde_json::from_str(&text(&run(allowed)).0).unwrap();
    assert_eq!(v["outside_domain"][0]["input"], "wall_thickness_mm");
    assert_eq!(v["outside_domain"][0]["clamped"], false);
}

/// A batch outside the domain: one message with the count and the first rows (not one line
/// per row), and with `--allow-extrapolation` an `outside_domain` column.
#[test]
fn batch_outside_the_domain_is_one_message_and_a_column() {
    let d = dir();
    let input = d.join("far.csv");
    let mut csv = String::from("n_bellows,wall_thickness_mm,pressure_bar,material\n");
    csv.push_str("11,2.0,1.0,ogden_002\n");
    for i in 0..2000 {
        let p = if i % 2 == 0 { "5" } else { "-1" };
        csv.push_str(&format!("11,2.0,{p},ogden_002\n"));
    }
    std::fs::write(&input, csv).unwrap();
    let out = d.join("far_out.csv");
    let args = [
        "--csv",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let o = predict(&args);
    fails_with(
        &o,
        &[
            "2000 of 2001 rows outside the training domain (first 5): line 3: pressure_bar = 5",
            "line 4: pressure_bar = -1",
            "--allow-extrapolation",
        ],
    );
    assert!(text(&o).1.lines().count() <= 2, "{}", text(&o).1);
    let mut allowed = args.to_vec();
    allowed.push("--allow-extrapolation");
    let o = predict(&allowed);
    let err = text(&o).1;
    assert!(o.status.success() && err.lines().count() <= 3, "{err}");
    let mut r = csv::Reader::from_path(&out).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 2001);
    assert_eq!(&rows[0][col("in_domain")], "true");
    assert_eq!(&rows[0][col("outside_domain")], "");
    assert_eq!(&rows[1][col("in_domain")], "false");
    assert_eq!(
        &rows[1][col("outside_domain")],
        "pressure_bar=5 (clamped to 3.5)"
    );
    assert_eq!(&rows[2][col("pressure_bar")], "-1");
}

/// `export --ramp` of a design outside the domain is refused; allowed, the header says so.
#[test]
fn export_ramp_outside_the_domain_is_refused_or_flagged() {
    let rs = dir().join("far_ramp.rs");
    let _ = std::fs::remove_file(&rs);
    let export = |extra: &[&str]| {
        bin()
            .args([
                "export",
                "--ramp",
                "--n",
                "11",
                "--t",
                "5",
                "--material",
                "ogden_002",
            ])
            .args(extra)
            .arg("--model")
            .arg(model())
            .arg("--rust")
            .arg(&rs)
            .output()
            .unwrap()
    };
    fails_with(
        &export(&[]),
        &["wall_thickness_mm = 5 outside", "--allow-extrapolation"],
    );
    assert!(!rs.exists());
    let o = export(&["--allow-extrapolation"]);
    assert!(o.status.success(), "{}", text(&o).1);
    let h = std::fs::read_to_string(rs.with_extension("h")).unwrap();
    assert!(
        h.contains("#define SURROGATE_RAMP_IN_DOMAIN 0")
            && h.contains("OUTSIDE THE TRAINING DOMAIN")
            && h.contains("wall_thickness_mm = 5"),
        "{h}"
    );
    let src = std::fs::read_to_string(&rs).unwrap();
    assert!(src.contains("pub const IN_DOMAIN: bool = false;"));
}

#[test]
fn unknown_material_and_untrained_n_are_clear_errors() {
    let o = predict(&[
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "1",
        "--material",
        "ogden_999",
    ]);
    fails_with(&o, &["ogden_999", "ogden_002"]);
    let o = predict(&[
        "--n",
        "10",
        "--t",
        "2.0",
        "--pressure",
        "1",
        "--material",
        "ogden_002",
    ]);
    fails_with(&o, &["invalid n = 10", "[9, 11, 13]"]);
}

/// An untrained N is refused even with `--allow-extrapolation` (one query, a batch, an exported
/// ramp), and the message says that the flag does not apply to N.
#[test]
fn untrained_n_is_refused_even_with_allow_extrapolation() {
    const WHY: &str = "not even with --allow-extrapolation";
    let o = predict(&[
        "--n",
        "10",
        "--t",
        "2.0",
        "--pressure",
        "1",
        "--material",
        "ogden_002",
        "--allow-extrapolation",
    ]);
    fails_with(&o, &["invalid n = 10", "[9, 11, 13]", WHY]);
    let csv = dir().join("untrained_n.csv");
    std::fs::write(
        &csv,
        "n_bellows,wall_thickness_mm,pressure_bar,material\n10,2.0,1.5,ogden_002\n",
    )
    .unwrap();
    let out = dir().join("untrained_n_out.csv");
    let o = predict(&[
        "--csv",
        csv.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--allow-extrapolation",
    ]);
    fails_with(&o, &["line 2", "n_bellows", "[9, 11, 13]", WHY]);
    let rs = dir().join("untrained_n_ramp.rs");
    let o = bin()
        .args(["export", "--ramp", "--n", "10", "--t", "2.0"])
        .args([
            "--material",
            "ogden_002",
            "--allow-extrapolation",
            "--model",
        ])
        .arg(model())
        .arg("--rust")
        .arg(&rs)
        .output()
        .unwrap();
    fails_with(&o, &["invalid n = 10", WHY]);
    assert!(!rs.exists());
}

#[test]
fn batch_csv_round_trip_and_bad_rows() {
    let d = dir();
    let input = d.join("q.csv");
    std::fs::write(&input, "n_bellows,wall_thickness_mm,pressure_bar,material\n11,2.0,1.0,ogden_002\n9,1.6,2.5,\"1.0,3.0,-12,-0.5\"\n").unwrap();
    let out = d.join("q_out.csv");
    let o = predict(&[
        "--csv",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--std",
    ]);
    assert!(o.status.success(), "{}", text(&o).1);
    let res = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = res.lines().collect();
    assert_eq!(lines.len(), 3);
    assert!(
        lines[0].starts_with("material,n_bellows,")
            && lines[0].contains("force_n_std")
            && lines[0].ends_with("in_domain,outside_domain")
    );
    let mut r = csv::Reader::from_reader(res.as_bytes());
    let rec: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    assert_eq!(rec[1].len(), 1 + 7 + 22 + 22 + 2);
    assert_eq!(&rec[1][0], "1.0,3.0,-12,-0.5");
    let cases = [
        ("n_bellows,wall_thickness_mm,pressure_bar\n11,2,1\n", "missing column `mu1_mpa`: expected n_bellows, wall_thickness_mm, pressure_bar, mu1_mpa, alpha1, mu2_mpa, alpha2 (or a `material` column"),
        ("n_bellows,wall_thickness_mm,pressure_bar,material,tip_uz_mm\n11,2,1,ogden_002,3\n", "column `tip_uz_mm` would be overwritten"),
        ("n_bellows,wall_thickness_mm,pressure_bar,material\n9.5,2,1,ogden_002\n", "line 2, column `n_bellows`"),
        ("n_bellows,wall_thickness_mm,pressure_bar,material\n11,2,1,ogden_002\n11,NaN,1,ogden_002\n", "line 3, column `wall_thickness_mm`"),
        ("n_bellows,wall_thickness_mm,pressure_bar,material\n11,2,1,unobtainium\n", "line 2, column `material`"),
        ("n_bellows,wall_thickness_mm,pressure_bar,material\n8,2,1,ogden_002\n", "line 2, column `n_bellows`"),
        ("n_bellows,wall_thickness_mm,pressure_bar,mu1_mpa,alpha1,mu2_mpa,alpha2\n11,2,1,1.1,3,-13\n", "line 2, column `alpha2`"),
        ("n_bellows,wall_thickness_mm,pressure_bar,material\n11,2,1,ogden_002,7\n", "line 2, column `#5`"),
    ];
    for (i, (csv, want)) in cases.iter().enumerate() {
        let p = d.join(format!("bad{i}.csv"));
        std::fs::write(&p, csv).unwrap();
        let o = predict(&[
            "--csv",
            p.to_str().unwrap(),
            "--out",
            d.join("x.csv").to_str().unwrap(),
        ]);
        fails_with(&o, &[want]);
    }
}

#[test]
fn predict_prints_stored_validation() {
    let o = predict(&["--validation"]);
    let err = text(&o).0;
    assert!(
        o.status.success()
            && err.contains("validation: 3-fold by case")
            && err.contains("markers_mm"),
        "{err}"
    );
}

#[test]
fn export_writes_rust_tables_and_c_header() {
    let rs = dir().join("actuator_model.rs");
    let o = bin()
        .args(["export", "--model"])
        .arg(model())
        .arg("--rust")
        .arg(&rs)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    let src = std::fs::read_to_string(&rs).unwrap();
    assert!(
        src.contains("pub static MODEL: EmbeddedModel<'static, f32>")
            && src.contains("extern \"C\" fn surrogate_predict_f32")
    );
    // the tables need the `surrogate-predict` crate, not a copied module
    assert!(
        src.contains("Needs the `surrogate-predict` crate")
            && src.contains("use surrogate_predict::{evaluate, ")
            && !src.contains("crate::predict"),
        "{src}"
    );
    let h = std::fs::read_to_string(rs.with_extension("h")).unwrap();
    assert!(h.contains("surrogate_predict_f32"));
    let o = bin()
        .args(["export", "--precision", "f64", "--model"])
        .arg(model())
        .arg("--rust")
        .arg(dir().join("m64.rs"))
        .output()
        .unwrap();
    assert!(o.status.success());
}

#[test]
fn corrupt_model_file_is_a_clear_error() {
    let p = dir().join("corrupt.json");
    let mut t = std::fs::read_to_string(model()).unwrap();
    t.truncate(t.len() - 10);
    std::fs::write(&p, t).unwrap();
    let o = bin()
        .args(["predict", "--validation", "--model"])
        .arg(&p)
        .output()
        .unwrap();
    fails_with(&o, &["corrupt or truncated"]);
}

#[test]
fn speedup_benchmark_rejects_bad_input_before_any_fe_run() {
    let base = ["--n", "11", "--t", "2.0", "--material", "ogden_002"];
    let out = dir().join("speedup.json");
    let o = predict(
        &[&base[..], &["--bench-fe", "medium", "--bench-out"]]
            .concat()
            .into_iter()
            .chain([out.to_str().unwrap()])
            .collect::<Vec<_>>(),
    );
    fails_with(&o, &["medium", "coarse"]);
    let o = predict(&[&base[..], &["--bench-fe", "coarse"]].concat());
    fails_with(&o, &["--bench-out"]);
    let o = predict(&[
        "--n",
        "10",
        "--t",
        "2.0",
        "--material",
        "ogden_002",
        "--bench-fe",
        "coarse",
        "--bench-out",
        out.to_str().unwrap(),
    ]);
    fails_with(&o, &["invalid n = 10"]);
    assert!(!out.exists());
}

#[test]
fn learning_curve_prints_one_row_per_size_and_rejects_bad_sizes() {
    let out = dir().join("curve.json");
    let o = train_synthetic(24, 3, &["--learning-curve", "6,12,24"], &out);
    let (stdout, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let rows: Vec<Vec<f64>> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("learning curve: "))
        .map(|l| l.split(' ').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 3, "{stdout}");
    assert_eq!(
        rows.iter().map(|r| r[0]).collect::<Vec<_>>(),
        [6.0, 12.0, 24.0]
    );
    // 5 outputs per row; more cases, smaller tip error on this smooth synthetic set
    assert!(rows.iter().all(|r| r.len() == 6));
    assert!(rows[2][2] < rows[0][2], "{stdout}");
    // the last size is the whole set: the same errors as the model saved
    assert!(stdout.contains("validation:"));
    let o = train_synthetic(24, 3, &["--learning-curve", "2"], &out);
    fails_with(&o, &["--learning-curve size 2"]);
}

#[test]
fn export_ramp_writes_one_design_and_needs_it_named() {
    let rs = dir().join("ramp.rs");
    let o = bin()
        .args([
            "export",
            "--ramp",
            "--n",
            "11",
            "--t",
            "2.0",
            "--material",
            "ogden_002",
        ])
        .arg("--model")
        .arg(model())
        .arg("--rust")
        .arg(&rs)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    let src = std::fs::read_to_string(&rs).unwrap();
    assert!(
        src.contains("pub static RAMP: RampTables<'static, f32>")
            && src.contains("extern \"C\" fn surrogate_ramp_f32(p_bar: f32, out: *mut f32)")
            && src.contains("N = 11, T = 2 mm")
            && src.contains("use surrogate_predict::{evaluate_ramp, ModelFormTables, RampTables};")
            && src.contains("pub static MODEL_FORM: Option<ModelFormTables<'static>> = None;"),
        "{src}"
    );
    assert!(std::fs::read_to_string(rs.with_extension("h"))
        .unwrap()
        .contains("surrogate_ramp_f32"));
    // the design must be named, and only with --ramp
    let o = bin()
        .args(["export", "--ramp", "--n", "11", "--model"])
        .arg(model())
        .arg("--rust")
        .arg(&rs)
        .output()
        .unwrap();
    fails_with(&o, &["--ramp needs --n, --t and --material"]);
    let o = bin()
        .args(["export", "--n", "11", "--model"])
        .arg(model())
        .arg("--rust")
        .arg(&rs)
        .output()
        .unwrap();
    fails_with(&o, &["give --ramp too"]);
    // an untrained N is the library's clear error
    let o = bin()
        .args([
            "export",
            "--ramp",
            "--n",
            "10",
            "--t",
            "2.0",
            "--material",
            "ogden_002",
        ])
        .arg("--model")
        .arg(model())
        .arg("--rust")
        .arg(&rs)
        .output()
        .unwrap();
    fails_with(&o, &["n = 10"]);
}

/// What pandas writes: `9.0` in an integer column, an ID and other columns beside the inputs,
/// which come back in the output; `--out -` writes to stdout.
#[test]
fn batch_accepts_9_0_and_passes_extra_columns_through() {
    let d = dir();
    let input = d.join("pandas.csv");
    std::fs::write(
        &input,
        "id,n_bellows,wall_thickness_mm,pressure_bar,note,mu1_mpa,alpha1,mu2_mpa,alpha2\n\
         a-1,11.0,2.0,1.0,\"first, with a comma\",1.13,3.11,-13.17,-0.6\n\
         a-2,9,2.0,2.0,,1.13,3.11,-13.17,-0.6\n",
    )
    .unwrap();
    let o = predict(&["--csv", input.to_str().unwrap(), "--out", "-"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let mut r = csv::Reader::from_reader(out.as_bytes());
    let h = r.headers().unwrap().clone();
    assert_eq!(&h[0], "id");
    assert_eq!(&h[1], "note");
    assert_eq!(&h[2], "n_bellows");
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 2);
    assert_eq!(
        (&rows[0][0], &rows[0][1], &rows[0][2]),
        ("a-1", "first, with a comma", "11")
    );
    assert_eq!((&rows[1][0], &rows[1][1], &rows[1][2]), ("a-2", "", "9"));
    // the same query by flags gives the same tip
    let single = predict(&[
        "--n",
        "11",
        "--t",
        "2.0",
        "--pressure",
        "1.0",
        "--material",
        "1.13,3.11,-13.17,-0.6",
    ]);
    let v: serde_json::Value = serde_json::from_str(&text(&single).0).unwrap();
    let tip = h.iter().position(|c| c == "tip_uz_mm").unwrap();
    assert_eq!(
        rows[0][tip].parse::<f64>().unwrap(),
        v["tip_uz_mm"].as_f64().unwrap()
    );
}

/// `train` never overwrites a model by accident: `--out` is required, an existing file is an
/// error (before any training) unless `--force`, and the write is atomic.
#[test]
fn train_refuses_to_overwrite_without_force() {
    let o = bin()
        .args(["train", "--synthetic", "12", "--folds", "2", "--quiet"])
        .output()
        .unwrap();
    fails_with(&o, &["--out"]);
    // its own folder, so that other tests' atomic writes cannot be mistaken for leftovers
    let own = dir().join("overwrite");
    std::fs::create_dir_all(&own).unwrap();
    let path = own.join("existing.json");
    std::fs::write(&path, "precious").unwrap();
    let train = |extra: &[&str]| {
        bin()
            .args([
                "train",
                "--synthetic",
                "12",
                "--folds",
                "2",
                "--quiet",
                "--only",
                "poly",
                "--out",
            ])
            .arg(&path)
            .args(extra)
            .output()
            .unwrap()
    };
    fails_with(&train(&[]), &["exists: refusing to overwrite", "--force"]);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "precious");
    let o = train(&["--force"]);
    assert!(o.status.success(), "{}", text(&o).1);
    surrogate::rom::Surrogate::load(&path).unwrap();
    // no temporary file is left beside it
    let left: Vec<_> = std::fs::read_dir(&own)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// `--only` takes the name of any regressor of the registry, and refuses another naming the
/// flag, the value and the registered names.
#[test]
fn train_only_takes_a_registered_regressor_by_name() {
    let path = dir().join("only_gp.json");
    // a rerun finds the last run's model: the refusal below must not be judged by it
    let _ = std::fs::remove_file(&path);
    let train = |only: &str| train_synthetic(12, 2, &["--only", only], &path);
    let names = surrogate::rom::regression::Registry::builtin().names();
    let mut needles = vec!["--only", "'kriging'"];
    needles.extend(&names);
    fails_with(&train("kriging"), &needles);
    assert!(!path.exists(), "a refused flag wrote {}", path.display());
    for name in names {
        let o = train(name);
        assert!(o.status.success(), "--only {name}: {}", text(&o).1);
        let model = surrogate::rom::Surrogate::load(&path).unwrap();
        assert!(
            model.blocks.iter().all(|b| b.regressor.name() == name),
            "--only {name}: {:?}",
            model
                .blocks
                .iter()
                .map(|b| b.regressor.name())
                .collect::<Vec<_>>()
        );
    }
}

/// `--inducing` below twice the regression inputs is refused before any training, naming the
/// flag; a valid one trains a sparse GP on that many points, says so, and the model records it.
#[test]
fn train_inducing_is_checked_and_recorded() {
    let path = dir().join("inducing.json");
    // a rerun finds the last run's model: the refusal below must not be judged by it
    let _ = std::fs::remove_file(&path);
    let train = |m: &str| train_synthetic(30, 3, &["--only", "gp", "--inducing", m], &path);
    fails_with(&train("5"), &["invalid --inducing 5", "at least 12"]);
    assert!(!path.exists(), "a refused flag wrote {}", path.display());
    let o = train("16");
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(out.contains("GP: sparse on 16 inducing points"), "{out}");
    let model = surrogate::rom::Surrogate::load(&path).unwrap();
    assert_eq!(model.training.gp_inducing, Some(16));
    let gp = model.regressors.get::<surrogate::rom::regression::gp::Gp>();
    assert_eq!(gp.unwrap().n, 16);
}

/// A missing default model says where it was looked for, once (no repeated cause).
#[test]
fn a_missing_named_model_says_where_it_was_looked_for() {
    // the default model resolves against the repository from any folder
    // (`defaults_cli`); a relative path the user names starts from the current one
    let cwd = dir().join("empty_cwd");
    std::fs::create_dir_all(&cwd).unwrap();
    let o = bin()
        .current_dir(&cwd)
        .args([
            "predict",
            "--model",
            "models/actuator.json",
            "--n",
            "11",
            "--t",
            "2",
            "--pressure",
            "1",
            "--material",
            "ogden_002",
        ])
        .output()
        .unwrap();
    let looked = cwd.join("models/actuator.json");
    fails_with(
        &o,
        &[
            "models/actuator.json: not found",
            &format!("looked for {}", looked.display()),
            "--model",
        ],
    );
    let err = text(&o).1;
    assert_eq!(err.matches("not found").count(), 1, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

/// `--ordinal-n`: the model predicts every integer N between its trained ends; `--hold-out-n`
/// first trains without those N, prints their errors and stores them in the model; a held-out
/// N at an end, or `--hold-out-n` without `--ordinal-n`, is refused before training.
#[test]
fn ordinal_n_predicts_between_trained_n_and_hold_out_n_measures_it() {
    let path = dir().join("ordinal.json");
    let train = |extra: &[&str]| {
        bin()
            .args(["train", "--force", "--synthetic", "30", "--folds", "3"])
            .args(["--quiet", "--out"])
            .arg(&path)
            .args(extra)
            .output()
            .unwrap()
    };
    let o = train(&["--ordinal-n", "--hold-out-n", "11"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("held-out N") && out.contains("trained on N = [9, 13]"),
        "{out}"
    );
    let json = std::fs::read_to_string(&path).unwrap();
    assert!(json.contains("\"n_trained\"") && json.contains("\"held_out_n\""));
    let o = bin()
        .args(["predict", "--n", "10", "--t", "2.0", "--pressure", "1"])
        .args(["--material", "ogden_002", "--model"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    let o = bin()
        .args(["predict", "--validation", "--model"])
        .arg(&path)
        .output()
        .unwrap();
    let out = text(&o).0;
    assert!(
        out.contains("ordinal regression input") && out.contains("trained on N = [9, 13]"),
        "{out}"
    );
    fails_with(
        &train(&["--ordinal-n", "--hold-out-n", "13"]),
        &["13", "strictly between"],
    );
    fails_with(&train(&["--hold-out-n", "11"]), &["--ordinal-n"]);
}

/// `predict --check`: the model against the FE cases of a snapshot CSV, a table per case, per N
/// and overall, and the JSON; an unreadable file is refused naming the flag, and `--check`
/// does not mix with a single query.
#[test]
fn predict_check_scores_a_snapshot_set_and_refuses_bad_input() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let json = dir().join("check.json");
    let _ = std::fs::remove_file(&json);
    let run = |data: &Path, extra: &[&str]| {
        bin()
            .args(["predict", "--model"])
            .arg(root.join("models/as_modelled/actuator_coarse.json"))
            .arg("--check")
            .arg(data)
            .args(extra)
            .output()
            .unwrap()
    };
    let set = root.join("training_data/snapshots_coarse.csv");
    let o = run(&set, &["--check-json", json.to_str().unwrap()]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("300 cases of") && out.contains("case_000299"),
        "{out}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["n_values"], serde_json::json!([9, 11, 13]));
    assert_eq!(report["cases"].as_array().unwrap().len(), 300);
    fails_with(
        &run(&dir().join("no_such.csv"), &[]),
        &["--check", "no_such.csv"],
    );
    let o = run(&set, &["--n", "9"]);
    fails_with(&o, &["--check", "--n"]);
}

/// `--add-data` appends a box extension's rounds to a set: sets of the same actuator train
/// one model that states how they were built; a set built otherwise, or one without its plan,
/// is refused before any training, and nothing is written.
#[test]
fn add_data_appends_sets_built_alike_and_refuses_others() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let ext = |k: usize| {
        root.join(format!(
            "fe_reference/identification/design_space/extend/extend_{k}.csv"
        ))
    };
    let out = dir().join("add_data.json");
    let _ = std::fs::remove_file(&out);
    let train = |data: &Path, add: &Path| {
        bin()
            .args([
                "train", "--force", "--folds", "2", "--quiet", "--only", "poly",
            ])
            .arg("--data")
            .arg(data)
            .arg("--add-data")
            .arg(add)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    // the shipped as-modelled set and an identified-geometry round
    let coarse = root.join("training_data/snapshots_coarse.csv");
    fails_with(
        &train(&coarse, &ext(1)),
        &[
            "--add-data",
            "extend_1.csv",
            "builds its cases otherwise than",
        ],
    );
    // a set without its plan beside it
    let bare = dir().join("bare.csv");
    std::fs::copy(ext(2), &bare).unwrap();
    fails_with(
        &train(&ext(1), &bare),
        &["bare.csv: no plan beside it", "bare.plan.json"],
    );
    assert!(!out.exists(), "a refused set wrote {}", out.display());
    // the two rounds together: 72 cases of the identified geometry and force rig
    let o = train(&ext(1), &ext(2));
    let (stdout, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        stdout.contains("domain: the box of the cases (of --data and the 1 appended)"),
        "{stdout}"
    );
    let m = surrogate::rom::Surrogate::load(&out).unwrap();
    assert_eq!(m.training.n_cases, 72);
    assert!(
        m.training.source.ends_with("extend_1.csv + ")
            || m.training.source.contains("extend_1.csv + ")
    );
    let built = m.training.built_with.expect("stated");
    assert_eq!(
        built.geometry,
        surrogate::fe::preset::Geometry::identified()
    );
    assert!(built.effects.plate_offset_mm() == -4.5);
}
