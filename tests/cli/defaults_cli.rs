//! Defaults resolve against the repository the program was built from, not the working
//! directory, and a default that was read is said with its path; a file the user names is
//! read where the user is.
use crate::common::{repo, run_in, scratch, text};

/// The set calibrated through the shipped model (`fe_reference/identification/shipped_surrogate/`),
/// inside its training domain, as Ogden 002 is not.
const CALIBRATED: &str = "0.2108,18.1271,-1.2232,-1.9958";

#[test]
fn predict_runs_from_another_folder_and_names_the_default_model() {
    let dir = scratch("defaults_predict");
    let default = repo().join("models/actuator.json");
    let said = format!("--model: reading {} (the default)", default.display());
    // one query: the shipped model of the repository, said on stderr
    let out = run_in(
        &dir,
        &[
            "predict",
            "--n",
            "11",
            "--t",
            "2.0",
            "--pressure",
            "1.5",
            "--material",
            CALIBRATED,
        ],
    );
    let stderr = text(&out).1;
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains(&said), "{stderr}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["tip_uz_mm"].as_f64().is_some_and(f64::is_finite), "{v}");
    // a batch whose query file is named relative to the working directory
    std::fs::write(
        dir.join("queries.csv"),
        format!(
            "id,n_bellows,wall_thickness_mm,pressure_bar,material\na,11,2.0,1.5,\"{CALIBRATED}\"\n"
        ),
    )
    .unwrap();
    let out = run_in(
        &dir,
        &[
            "predict",
            "--csv",
            "queries.csv",
            "--out",
            "predictions.csv",
        ],
    );
    let stderr = text(&out).1;
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains(&said), "{stderr}");
    let written = std::fs::read_to_string(dir.join("predictions.csv")).unwrap();
    assert_eq!(written.lines().count(), 2, "{written}");
    // a model named by the user is read where the user is: nothing is said, a missing one
    // is an error that gives the shipped models' full paths
    let out = run_in(
        &dir,
        &["predict", "--model", "models/actuator.json", "--validation"],
    );
    let stderr = text(&out).1;
    assert!(!out.status.success());
    assert!(!stderr.contains("(the default)"), "{stderr}");
    assert!(
        stderr.contains(&format!("the shipped models are {}", default.display())),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
