//! `surrogate simulate` from the command line: bad input is a clear error with a non-zero exit
//! code, and a small run writes the documented JSON and ParaView files.

use std::process::Command;

fn simulate(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_surrogate"))
        .arg("simulate")
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_input_is_a_named_error_with_nonzero_exit() {
    let cases: &[(&[&str], &str)] = &[
        (&["--material", "ogden_999"], "ogden_999"),
        (&["--material", "1.13,3.11,13.17,-0.6"], "mu2*alpha2"),
        (&["--material", "neo_hookean:-1"], "mu"),
        (&["--n", "16"], "n_bellows = 16"),
        (&["--t", "3.5"], "wall_thickness = 3.5"),
        (&["--n", "15", "--t", "2.8"], "no usable cavity"),
        (&["--pressures", "0,-1,2"], "-1"),
        (&["--pressures", "-1"], "pressure -1 bar at position 1 of the list is invalid: expected a gauge pressure ≥ 0 bar (a negative pressure"),
        (&["--pressures", "0,1,-2"], "position 3 of the list"),
        (&["--pressures", "0,1,x"], "entry 3 'x' is not a number"),
        (&["--pressures", "3:0"], "expected max ≥ 0 and step > 0"),
        (&["--pressures", "0,abc"], "'abc' is not a number"),
        (&["--pressures", "2,1"], "increasing"),
        (&["--mesh", "medium"], "unknown mesh level 'medium'"),
        (&["--bulk-ratio=-5"], "bulk_ratio"),
        (&["--element-size", "0"], "--element-size"),
        (&["--wall-elements", "0"], "--wall-elements 0"),
        (&["--rtol", "0.5"], "--rtol 0.5"),
        (&["--contact-stiffness", "0"], "contact stiffness = 0"),
        (&["--contact-smoothing", "2"], "contact smoothing = 2"),
        (&["--mode", "push"], "push"),
    ];
    for (args, needle) in cases {
        let (ok, _, err) = simulate(args);
        assert!(!ok, "{args:?} should fail");
        assert!(
            err.contains(needle),
            "{args:?}: stderr {err:?} should mention {needle:?}"
        );
    }
}

#[test]
fn small_run_writes_json_and_vtk() {
    let dir = std::env::temp_dir().join(format!("surrogate_fe_cli_{}", std::process::id()));
    let json = dir.join("r.json");
    let vtk = dir.join("vtk");
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, _, err) = simulate(&[
        "--n",
        "7",
        "--t",
        "2.4",
        "--pressures",
        "0.1:0.1",
        "--mesh",
        "coarse",
        "--no-gravity",
        "--out",
        json.to_str().unwrap(),
        "--vtk",
        vtk.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    // progress per step where no bar is drawn, and a final line naming the file
    assert!(err.contains("step 2/2: 0.1 bar"), "{err}");
    assert!(
        err.contains("wrote 2 steps") && err.contains(json.to_str().unwrap()),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 2);
    // the pressure as requested (not 0.1 recomputed through MPa), markers as `predict` writes
    assert_eq!(steps[1]["pressure_bar"].as_f64(), Some(0.1));
    let m = &steps[1]["markers"][8];
    assert!(m["uz_mm"].is_f64() && m["uy_mm"].is_f64(), "{m}");
    assert_eq!(m["uy_mm"], steps[1]["tip_uy_mm"]);
    for key in [
        "pressure_bar",
        "tip_uz_mm",
        "tip_uy_mm",
        "angle_deg",
        "newton_iterations",
        "converged",
    ] {
        assert!(!steps[1][key].is_null(), "missing {key}");
    }
    assert_eq!(steps[1]["markers"].as_array().unwrap().len(), 9);
    for key in ["nodes", "elements", "dofs", "wall_time_s"] {
        assert!(v[key].as_f64().unwrap() > 0.0, "{key}");
    }
    // pressurising bends the actuator down (Uy < 0) from the unloaded state
    assert_eq!(steps[0]["tip_uy_mm"].as_f64().unwrap(), 0.0);
    assert!(steps[1]["tip_uy_mm"].as_f64().unwrap() < 0.0);
    assert!(vtk.join("steps.pvd").exists());
    let vtu = std::fs::read_to_string(vtk.join("step_001.vtu")).unwrap();
    assert!(vtu.contains("Name=\"displacement\"") && vtu.contains("Name=\"von_mises\""));
    assert!(vtk.join("step_001_surfaces.vtu").exists());
    let contact = std::fs::read_to_string(vtk.join("step_001_contact.vtu")).unwrap();
    assert!(contact.contains("Name=\"gap_mm\"") && contact.contains("contact_pressure_mpa"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn force_mode_reports_the_plate_reaction() {
    let dir = std::env::temp_dir().join(format!("surrogate_fe_force_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("f.json");
    let (ok, _, err) = simulate(&[
        "--n",
        "7",
        "--t",
        "2.4",
        "--pressures",
        "0,0.1",
        "--mesh",
        "coarse",
        "--mode",
        "force",
        "--out",
        json.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let steps = v["steps"].as_array().unwrap();
    // the plate is 5 mm below the hanging tip: no force at P = 0 (the scale is tared)
    assert_eq!(steps[0]["force_n"].as_f64().unwrap(), 0.0);
    assert!(steps[1]["force_n"].as_f64().unwrap() >= 0.0);
    std::fs::remove_dir_all(&dir).ok();
}
