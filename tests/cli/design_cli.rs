//! `surrogate design` and `surrogate maps`: the table, the JSON report, the figures, and the
//! bad-input messages naming their flag.
use std::process::Output;

use crate::common::{fails_with, run, scratch, text, SHIPPED_REPORT as REPORT};

/// `surrogate design` on the shipped model with the material calibrated through it and `extra`
/// arguments.
fn design(extra: &[&str]) -> Output {
    let mut args = vec!["design", "--material", REPORT];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn design_prints_a_row_per_n_and_the_pick_with_its_errors() {
    let json = scratch("design_cli_json").join("report.json");
    let o = design(&[
        "--angle",
        "40@2",
        "--force",
        "1.3@2",
        "--json",
        json.to_str().unwrap(),
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("angle_deg@2") && out.contains("force_n@2"),
        "{out}"
    );
    for n in 7..=15 {
        assert!(
            out.lines()
                .any(|l| l.trim_start().starts_with(&format!("{n} "))),
            "no row for N = {n}: {out}"
        );
    }
    assert!(
        out.contains("<- pick") && out.contains("pick: N = "),
        "{out}"
    );
    assert!(
        out.contains("surrogate vs FE") && out.contains("model-form error"),
        "{out}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["designs"].as_array().unwrap().len(), 9);
    assert!(report["pick"]["t_mm"].as_f64().unwrap() > 1.0);
    assert!(
        err.contains("wrote") && err.contains("(the default)"),
        "{err}"
    );
}

#[test]
fn design_names_the_flag_of_a_bad_target() {
    fails_with(
        &design(&["--angle", "45"]),
        &["--angle \"45\"", "VALUE@PRESSURE"],
    );
    fails_with(
        &design(&["--angle", "abc@2"]),
        &["--angle", "\"abc\" is not a number"],
    );
    fails_with(
        &design(&["--force", "1@5"]),
        &["--force 1@5", "p_bar = 5", "3.5] bar"],
    );
    fails_with(
        &design(&["--angle", "45@2", "--angle-tolerance", "0"]),
        &["--angle-tolerance 0", "--angle 45@2", "> 0"],
    );
    // a target is required, and so is the material
    fails_with(&design(&[]), &["--angle"]);
    fails_with(&run(&["design", "--angle", "45@2"]), &["--material"]);
}

#[test]
fn design_names_the_flag_of_a_bad_range() {
    fails_with(
        &design(&["--angle", "45@2", "--n", "13..9"]),
        &["--n 13..=9", "MIN ≤ MAX"],
    );
    fails_with(
        &design(&["--angle", "45@2", "--n", "5..15"]),
        &["--n 5..=15", "7..=15"],
    );
    fails_with(
        &design(&["--angle", "45@2", "--n", "a..9"]),
        &["--n \"a..9\"", "MIN..MAX"],
    );
    fails_with(
        &design(&["--angle", "45@2", "--t", "1.0..2.0"]),
        &["--t 1..=2", "inside the model's T [1.201, 2.796] mm"],
    );
}

#[test]
fn maps_write_an_svg_per_output_and_the_grid() {
    let dir = scratch("design_cli_maps");
    let o = run(&[
        "maps",
        "--material",
        REPORT,
        "--t",
        "1.4..2.6",
        "--t-points",
        "4",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let (_, err) = text(&o);
    assert!(o.status.success(), "{err}");
    for name in ["angle_deg.svg", "force_n.svg"] {
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(svg.contains("<svg") && svg.contains("P = 3 bar"), "{name}");
    }
    let csv = std::fs::read_to_string(dir.join("maps.csv")).unwrap();
    // 9 N × 4 T × 3 P rows and the header
    assert_eq!(csv.lines().count(), 1 + 9 * 4 * 3, "{csv}");
    fails_with(
        &run(&[
            "maps",
            "--material",
            REPORT,
            "--pressures",
            "1,9",
            "--out",
            dir.to_str().unwrap(),
        ]),
        &["--pressures", "9"],
    );
}
