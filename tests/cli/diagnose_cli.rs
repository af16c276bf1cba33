//! `surrogate diagnose` from the command line: the report on the shipped experiments, marker
//! recordings (the figure along the actuator), and bad input named before anything runs.
use std::path::Path;

use crate::common::{outcome, repo, run_in, scratch, text};

fn report(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("diagnosis.json")).unwrap()).unwrap()
}

#[test]
fn diagnoses_the_shipped_experiments() {
    let dir = scratch("diag_shipped");
    let out = dir.join("report");
    let (ok, stdout, stderr) = outcome(&["diagnose", "--out", out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    for f in [
        "diagnosis.json",
        "summary.md",
        "residual_map.svg",
        "residual_trends.svg",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    // no markers in the shipped recordings: no figure along the actuator, and it is said
    assert!(!out.join("along_actuator.svg").exists());
    let r = report(&out);
    assert_eq!(r["format"], "surrogate.diagnosis");
    assert_eq!(r["version"], 1);
    // the defaults are the repository's, and the report says so
    let root = repo();
    let in_repo = |p: &str| root.join(p).to_str().unwrap().to_string();
    // corrected by the mean of the shipped approximation error, and it says so
    assert_eq!(
        r["recordings"]["bending"],
        format!(
            "{}, corrected by the mean error of FE on 4 mm elements without effect",
            in_repo("training_data/bending_experiments.csv")
        )
    );
    let inputs: Vec<(&str, &str, bool)> = r["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            (
                f["role"].as_str().unwrap(),
                f["path"].as_str().unwrap(),
                f["default"].as_bool().unwrap(),
            )
        })
        .collect();
    // the setup the blind study scores: the coarse model, its approximation error against
    // FE on 4 mm elements, no mesh reference
    let (m, b, f, e, s) = (
        in_repo("models/actuator_coarse.json"),
        in_repo("training_data/bending_experiments.csv"),
        in_repo("training_data/blocked_force_experiments.csv"),
        in_repo("data/approximation_error/identified_coarse_vs_4mm.json"),
        in_repo("data/sensitivities/identified_calibrated_coarse.json"),
    );
    assert_eq!(
        inputs,
        [
            ("model", m.as_str(), true),
            ("bending", b.as_str(), true),
            ("force", f.as_str(), true),
            ("approximation error", e.as_str(), true),
            ("sensitivities", s.as_str(), true),
        ]
    );
    assert!(r["mesh_error"].is_null(), "{}", r["mesh_error"]);
    // the Name stage on the committed FE sensitivities
    assert_eq!(r["name"]["status"], "named");
    assert!(!r["name"]["candidates"].as_array().unwrap().is_empty());
    assert!(stdout.contains("Name (candidate physics): "), "{stdout}");
    assert_eq!(r["locate"]["cells"].as_array().unwrap().len(), 27 * 4);
    let missing = r["locate"]["missing"].as_array().unwrap();
    assert!(
        missing.iter().any(|m| m["kind"] == "markers"),
        "{missing:?}"
    );
    assert!(stdout.starts_with("Findings:\n- "), "{stdout}");
    assert!(stdout.contains("no marker recordings along the actuator"));
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.starts_with("# Diagnosis") && md.contains("## Findings"));
    assert!(
        md.contains(&format!(
            "Recordings: bending {b}, corrected by the mean error of FE on 4 mm elements"
        )),
        "{md}"
    );
    assert!(md.contains(&format!("| sensitivities | `{s}` | ")), "{md}");
    assert!(md.contains("- **Name**: ") && md.contains("## Name: candidate effects"));
    // ties with the first candidate get a plan of up to 3 measurements (the default)
    let plan = &r["measurement_plan"];
    let leader = plan["leader"].as_str().unwrap();
    let tied = r["name"]["indistinguishable"]
        .as_array()
        .unwrap()
        .iter()
        .any(|p| p["a"] == leader || p["b"] == leader);
    let items = plan["items"].as_array().unwrap();
    assert_eq!(tied, !items.is_empty(), "{plan}");
    assert!(items.len() <= 3);
    if tied {
        assert!(md.contains("## What to measure next"), "{md}");
        assert!(
            stdout.contains("What to measure next (to tell "),
            "{stdout}"
        );
        let lbf: Vec<f64> = items
            .iter()
            .map(|i| i["log_bayes_factor"].as_f64().unwrap())
            .collect();
        assert!(lbf
            .iter()
            .all(|v| *v >= plan["log_bayes_factor"].as_f64().unwrap()));
    }
    // the named effect is refitted (`--refit auto`): its size, the fit before and after,
    // every design held out
    let named = r["name"]["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["significant"] == true && c["plausible"] == true)
        .filter(|c| c["model_error"] != true)
        .map(|c| c["effect"].clone());
    match named {
        Some(e) => {
            assert_eq!(r["model_and_show"]["status"], "modelled");
            assert_eq!(r["model_and_show"]["effects"][0]["effect"], e);
            assert_eq!(
                r["model_and_show"]["held_out"]["designs"]
                    .as_array()
                    .unwrap()
                    .len(),
                9
            );
            assert!(
                stdout.contains("Model and show: Refitted with "),
                "{stdout}"
            );
            assert!(
                md.contains("## Model and show: the refit with the effect"),
                "{md}"
            );
            assert!(md.contains("### Held out: each design left out of both fits in turn"));
        }
        None => assert_eq!(r["model_and_show"]["status"], "not_run"),
    }
    // two effects asked for by name; `none` skips the stage and says why
    let out3 = dir.join("refit");
    let (ok, stdout, stderr) = outcome(&[
        "diagnose",
        "--refit",
        "pressure_loss,force_scale",
        "--out",
        out3.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let r3 = report(&out3);
    let effects = r3["model_and_show"]["effects"].as_array().unwrap();
    assert_eq!(effects.len(), 2);
    assert_eq!(effects[1]["effect"], "force_scale");
    assert!(
        stdout.contains("Model and show: Refitted with pressure_loss = "),
        "{stdout}"
    );
    // the standard-mesh model with its mesh direction, no approximation error (the setup
    // before 2026-12-06), on the geometry as modelled with that geometry's sweep: the model's
    // own mesh error against the other model beside it is a candidate too
    let out4 = dir.join("none");
    let (ok, stdout, stderr) = outcome(&[
        "diagnose",
        "--model",
        "models/as_modelled/actuator.json",
        "--sensitivities",
        "data/sensitivities/calibrated_coarse.json",
        "--mesh-reference",
        "auto",
        "--approximation-error",
        "none",
        "--refit",
        "none",
        "--out",
        out4.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let r4 = report(&out4);
    assert_eq!(r4["model_and_show"]["status"], "not_run");
    assert!(stdout.contains("Model and show: not run ("), "{stdout}");
    // beside the model as given
    assert_eq!(
        r4["mesh_error"]["reference"],
        "models/as_modelled/actuator_coarse.json"
    );
    assert!(r4["name"]["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .any(|c| c["effect"] == "model_mesh" && c["model_error"] == true));
    let md4 = std::fs::read_to_string(out4.join("summary.md")).unwrap();
    assert!(
        md4.contains("The model's own mesh error (candidate `model_mesh`)"),
        "{md4}"
    );
    // --objective and --exclude reach the calibration
    let out2 = dir.join("force");
    let (ok, _, stderr) = outcome(&[
        "diagnose",
        "--objective",
        "tip,force",
        "--exclude",
        "bending:11,1.6,1",
        "--out",
        out2.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let r = report(&out2);
    assert_eq!(r["calibration"]["objective"], "tip=1,force=1");
    assert_eq!(r["locate"]["cells"].as_array().unwrap().len(), 27 * 4 - 3);
    assert!(r["locate"]["missing"]
        .as_array()
        .unwrap()
        .iter()
        .any(|m| m["kind"] == "excluded"));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn marker_recordings_are_drawn_along_the_actuator() {
    let dir = scratch("diag_markers");
    let rec = dir.join("rec");
    std::fs::create_dir_all(&rec).unwrap();
    let root = repo();
    let bending =
        std::fs::read_to_string(root.join("training_data/bending_experiments.csv")).unwrap();
    std::fs::write(rec.join("bending_experiments.csv"), &bending).unwrap();
    // marker 9 = the recorded tip, std 3 mm; no force file
    let mut m =
        String::from("n_bellows,wall_thickness_mm,pressure_bar,marker,uz_mm,uy_mm,std_mm\n");
    for line in bending.lines().skip(1) {
        let v: Vec<&str> = line.split(',').collect();
        m.push_str(&format!(
            "{},{},{},9,{},{},3\n",
            v[0], v[1], v[2], v[3], v[4]
        ));
    }
    std::fs::write(rec.join("marker_experiments.csv"), m).unwrap();
    let out = dir.join("out");
    let (ok, stdout, stderr) = outcome(&[
        "diagnose",
        "--recordings",
        rec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(out.join("along_actuator.svg").exists());
    assert!(stdout.contains("no blocked-force recordings"), "{stdout}");
    let r = report(&out);
    assert_eq!(r["locate"]["along_actuator"], true);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_input_is_named_before_anything_runs() {
    let dir = scratch("diag_bad");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let empty_s = empty.to_str().unwrap();
    let cases: [(&[&str], String); 14] = [
        (
            &["--recordings", "no_such_recordings"],
            "--recordings no_such_recordings: not a directory".into(),
        ),
        (
            &["--recordings", empty_s],
            format!("{empty_s}/bending_experiments.csv"),
        ),
        (&["--objective", "tipp"], "objective = tipp".into()),
        (&["--exclude", "11,1.6"], "--exclude = 11,1.6".into()),
        (
            &["--alpha", "0.7"],
            "alpha = 0.7: expected a significance level in (0, 0.5]".into(),
        ),
        (
            &["--sensitivities", "no_such_sensitivities.json"],
            "--sensitivities no_such_sensitivities.json: expected the file".into(),
        ),
        (
            &["--refit", "force_scale,nope"],
            "--refit force_scale,nope: unknown effect \"nope\"".into(),
        ),
        (
            &["--confirm-fe", "coarsest"],
            "--confirm-fe coarsest: unknown mesh level".into(),
        ),
        (
            &["--rank-fe", "3"],
            "--rank-fe 3: needs the FE mesh to rank on, --confirm-fe coarse or standard".into(),
        ),
        (
            &["--rank-fe", "1", "--confirm-fe", "coarse"],
            "--rank-fe 1: a ranking compares candidates".into(),
        ),
        (
            &["--sweep-mesh", "fines"],
            "--sweep-mesh fines: unknown mesh level".into(),
        ),
        (
            &["--mesh-reference", "no_such_model.json"],
            "--mesh-reference no_such_model.json: expected auto, none or a surrogate model file"
                .into(),
        ),
        (
            &["--approximation-error", "models/as_modelled/actuator.json"],
            "--approximation-error models/as_modelled/actuator.json".into(),
        ),
        (
            &["--plan-measurements", "4"],
            "--plan-measurements 4: measurements to plan = 4: expected 1 to 3".into(),
        ),
    ];
    for (extra, want) in cases {
        let args: Vec<&str> = ["diagnose", "--out", o]
            .iter()
            .chain(extra)
            .copied()
            .collect();
        let (ok, _, stderr) = outcome(&args);
        assert!(!ok && stderr.contains(&want), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?}: nothing written");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn runs_from_any_folder_and_names_the_defaults_it_read() {
    let dir = scratch("diag_elsewhere");
    let out = run_in(&dir, &["diagnose", "--refit", "none", "--out", "report"]);
    let stderr = text(&out).1;
    assert!(out.status.success(), "{stderr}");
    let root = repo();
    for f in [
        "models/actuator_coarse.json",
        "training_data/bending_experiments.csv",
        "training_data/blocked_force_experiments.csv",
        "data/approximation_error/identified_coarse_vs_4mm.json",
        "data/sensitivities/identified_calibrated_coarse.json",
    ] {
        let p = root.join(f);
        assert!(
            stderr.contains(&format!("reading {} (the default)", p.display())),
            "{f}: {stderr}"
        );
    }
    let r = report(&dir.join("report"));
    assert!(r["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .all(|f| f["default"] == true));
    std::fs::remove_dir_all(dir).unwrap();
}

/// The recordings of `tests/data/diagnose_outside_sweep`: configurations the committed FE
/// sensitivities lack (T = 1.8 mm; 0.5 bar).
const OUTSIDE_SWEEP: &str = "tests/data/diagnose_outside_sweep";

#[test]
fn recordings_outside_the_sweep_get_the_locate_stage_and_the_missing_cells() {
    let dir = scratch("diag_outside_sweep");
    let out = dir.join("out");
    let (ok, stdout, stderr) = outcome(&[
        "diagnose",
        "--recordings",
        OUTSIDE_SWEEP,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let r = report(&out);
    // the Locate stage: every recorded number of the 8 rows
    assert_eq!(r["locate"]["cells"].as_array().unwrap().len(), 8 * 3);
    assert!(stdout.starts_with("Findings:\n"), "{stdout}");
    // the coverage: only the shipped N = 11, T = 2 mm, 1 bar row has sensitivities
    let c = &r["sensitivity_coverage"];
    assert_eq!(
        (c["cells"].as_u64(), c["covered"].as_u64()),
        (Some(24), Some(3))
    );
    assert_eq!(c["uncovered"].as_array().unwrap().len(), 7);
    let named = "the FE sensitivities cover 3 of the 24 cells of the residual table, fewer \
                 than the 7 the Name stage needs, so it does not run; none at N = 9, T = 1.8 mm \
                 at 1, 2 and 3 bar (bending); N = 11, T = 1.8 mm at 1, 2 and 3 bar (bending); \
                 N = 11, T = 2 mm at 0.5 bar (bending); `--sensitivities calibrated` computes \
                 them by FE";
    assert_eq!(r["name"]["status"], "not_run");
    let reason = r["name"]["reason"].as_str().unwrap();
    assert!(reason.starts_with(named), "{reason}");
    assert_eq!(r["model_and_show"]["status"], "not_run");
    assert!(
        stdout.contains(&format!("Name (candidate physics): not run ({named}")),
        "{stdout}"
    );
    assert!(stderr.contains(&format!("warning: {named}")), "{stderr}");
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("- **Locate**: run (this report)."), "{md}");
    assert!(
        md.contains(&format!("- **Name**: not run: {named}")),
        "{md}"
    );
    assert!(md.contains("## Findings"), "{md}");
    // an effect asked for by name cannot be refitted: the report is written, the run fails
    let out2 = dir.join("refit");
    let (ok, _, stderr) = outcome(&[
        "diagnose",
        "--recordings",
        OUTSIDE_SWEEP,
        "--refit",
        "force_scale",
        "--out",
        out2.to_str().unwrap(),
    ]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("--refit force_scale: not run, the FE sensitivities cover too few"),
        "{stderr}"
    );
    assert_eq!(report(&out2)["name"]["status"], "not_run");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn cells_outside_the_sweep_are_named_when_the_rest_suffice() {
    let dir = scratch("diag_partial_sweep");
    let rec = dir.join("rec");
    std::fs::create_dir_all(&rec).unwrap();
    let root = repo();
    let mut bending =
        std::fs::read_to_string(root.join("training_data/bending_experiments.csv")).unwrap();
    let extra =
        std::fs::read_to_string(root.join(OUTSIDE_SWEEP).join("bending_experiments.csv")).unwrap();
    // the shipped 27 rows and the 7 rows outside the sweep (its 1 bar row is a shipped one)
    for line in extra.lines().skip(1).filter(|l| !l.starts_with("11,2,1,")) {
        bending.push_str(line);
        bending.push('\n');
    }
    std::fs::write(rec.join("bending_experiments.csv"), bending).unwrap();
    let out = dir.join("out");
    let (ok, _, stderr) = outcome(&[
        "diagnose",
        "--recordings",
        rec.to_str().unwrap(),
        "--refit",
        "none",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let r = report(&out);
    assert_eq!(r["locate"]["cells"].as_array().unwrap().len(), 34 * 3);
    assert_eq!(r["sensitivity_coverage"]["covered"], 27 * 3);
    assert_eq!(r["name"]["status"], "named");
    assert_eq!(r["name"]["n_cells"], 27 * 3);
    let said = "the FE sensitivities cover 81 of the 102 cells of the residual table, the Name \
                and Model stages leave the others out; none at N = 9, T = 1.8 mm at 1, 2 and 3 \
                bar (bending)";
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains(&format!("- **FE sensitivities**: {said}")),
        "{md}"
    );
    assert!(stderr.contains(&format!("warning: {said}")), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// The help section of the flags that set a diagnosis up, in `surrogate CMD --help`.
fn setup_help(cmd: &str) -> String {
    let (ok, help, stderr) = outcome(&[cmd, "--help"]);
    assert!(ok, "{stderr}");
    let at = help
        .find("Diagnosis setup (")
        .unwrap_or_else(|| panic!("{cmd} --help: {help}"));
    help[at..].to_string()
}

#[test]
fn diagnose_and_twin_study_share_the_setup_flags() {
    // one definition: the same flags, the same help (both defaults stated in it)
    let help = setup_help("diagnose");
    assert_eq!(help, setup_help("twin-study"));
    for flag in [
        "--model <FILE>",
        "--sensitivities <FILE|calibrated|none>",
        "--mesh-reference <auto|none|FILE>",
        "--approximation-error <none|nulls|FILE>",
    ] {
        assert!(help.contains(flag), "{flag}: {help}");
    }
    assert!(help.contains("data/approximation_error/identified_coarse_vs_4mm.json for `diagnose`"));
    assert!(help.contains("data/approximation_error/coarse_vs_4mm.json for `twin-study`"));
    // both commands parse every spelling: each run is stopped by its own check after parsing
    let dir = scratch("diag_setup_flags");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let spellings: [&[&str]; 3] = [
        &[
            "--model",
            "models/as_modelled/actuator_coarse.json",
            "--sensitivities",
            "no_such_sensitivities.json",
            "--mesh-reference",
            "auto",
            "--approximation-error",
            "none",
        ],
        &[
            "--mesh-reference",
            "none",
            "--approximation-error",
            "e.json",
        ],
        &["--mesh-reference", "models/as_modelled/actuator.json"],
    ];
    let stopped_by: [(&[&str], &str); 2] = [
        (
            &["diagnose", "--recordings", "no_such_recordings", "--out", o],
            "--recordings no_such_recordings: not a directory",
        ),
        (
            &["twin-study", "--stage", "fe", "--out", o],
            "--stage fe: expected",
        ),
    ];
    for flags in spellings {
        for (cmd, want) in stopped_by {
            let args: Vec<&str> = cmd.iter().chain(flags).copied().collect();
            let (ok, _, stderr) = outcome(&args);
            assert!(!ok && stderr.contains(want), "{args:?}: {stderr}");
        }
    }
    // a choice of the other command's is refused before anything runs, naming the flag
    let refused: [(&[&str], &str); 3] = [
        (
            &["diagnose", "--approximation-error", "nulls", "--out", o],
            "--approximation-error = nulls: expected none or an approximation error file",
        ),
        (
            &["twin-study", "--sensitivities", "none", "--out", o],
            "--sensitivities = none: expected a file of FE sensitivities",
        ),
        (
            &["twin-study", "--sensitivities", "calibrated", "--out", o],
            "--sensitivities = calibrated: expected a file of FE sensitivities",
        ),
    ];
    for (args, want) in refused {
        let (ok, _, stderr) = outcome(args);
        assert!(!ok && stderr.contains(want), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?}: nothing written");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--rank-fe` when the Name stage leaves fewer than 2 candidates to rank: said, no FE run,
/// and the diagnosis written as without it (the identified model on the shipped
/// experiments, its committed sensitivities at the calibrated material).
#[test]
fn rank_fe_with_nothing_to_rank_says_so_and_writes_the_diagnosis() {
    let dir = scratch("diag_rank_nothing");
    let out = dir.join("report");
    let root = repo();
    let cached = root.join("fe_reference/identification/diagnosis/fe_sensitivities");
    std::fs::create_dir_all(out.join("fe_sensitivities")).unwrap();
    for f in std::fs::read_dir(&cached).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(
            &f,
            out.join("fe_sensitivities").join(f.file_name().unwrap()),
        )
        .unwrap();
    }
    let model = root.join("fe_reference/identification/design_space/extend/model_extend_2.json");
    let (ok, stdout, stderr) = outcome(&[
        "diagnose",
        "--model",
        model.to_str().unwrap(),
        "--objective",
        "tip,angle,force",
        "--sensitivities",
        "calibrated",
        "--approximation-error",
        "none",
        "--rank-fe",
        "3",
        "--confirm-fe",
        "coarse",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("FE ranking not run: 0 candidates are significant at a plausible size"),
        "{stderr}"
    );
    assert!(stdout.contains("nothing is named"), "{stdout}");
    assert!(!out.join("fe_ramps").exists(), "no FE was run");
    let r = report(&out);
    assert!(r["fe_ranking"].is_null(), "{}", r["fe_ranking"]);
}
