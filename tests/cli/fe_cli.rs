//! `surrogate simulate` from the command line: bad input is a clear error with a non-zero exit
//! code, and a small run writes the documented JSON and ParaView files.

use crate::common::{outcome, scratch};

/// `surrogate simulate` with `args`: (success, stdout, stderr).
fn simulate(args: &[&str]) -> (bool, String, String) {
    outcome(&[&["simulate"], args].concat())
}

/// A geometry preset (the unstated dimensions) outside its physical range, or one that leaves
/// a design without a valid actuator, is refused by name before any FE; so are bad unknowns
/// and starts of `identify`.
#[test]
fn bad_geometries_and_identifications_are_refused_before_any_fe() {
    let dir = scratch("geometry");
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    let wide = write(
        "wide.json",
        r#"{"name":"wide","gap_mm":2.0,"base_thickness_mm":4.0,"duct_half_width_mm":2.0,"free_length_mm":92.0,"side_wall_mm":1.0}"#,
    );
    let closed = write(
        "closed.json",
        r#"{"name":"closed","gap_mm":0.0,"base_thickness_mm":4.0,"duct_half_width_mm":2.0,"free_length_mm":92.0}"#,
    );
    let typo = write(
        "typo.json",
        r#"{"name":"typo","gap":1.0,"base_thickness_mm":4.0,"duct_half_width_mm":2.0,"free_length_mm":92.0}"#,
    );
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--n", "13", "--t", "2.4", "--geometry", &wide],
            "geometry preset 'wide' at N = 13, T = 2.4 mm: design N = 13, T = 2.4 mm has no usable cavity: its cavity is 0.277 mm long",
        ),
        (
            vec!["--geometry", &closed],
            "gap_mm = 0 mm is outside its physical range: expected 0.2 … 2 mm",
        ),
        (vec!["--geometry", &typo], "unknown field `gap`"),
        (vec!["--geometry", "nominal"], "unknown geometry preset 'nominal'"),
    ];
    for (args, expected) in &cases {
        let (ok, _, err) = simulate(args);
        assert!(!ok, "{args:?} should fail");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(!err.contains("step"), "{args:?} ran FE steps: {err}");
    }
    let identify_out = dir.join("identify").display().to_string();
    let identify =
        |args: &[&str]| outcome(&[&["identify"], args, &["--out", &identify_out]].concat());
    for (args, expected) in [
        (vec!["--unknowns", "gap_bias"], "the dimension itself"),
        (vec!["--unknowns", "colour"], "unknown = colour"),
        (
            vec!["--set", "gap=0.1"],
            "gap_mm = 0.1 mm is outside its physical range",
        ),
        (vec!["--set", "plate_offset=-9"], "plate_offset"),
        (vec!["--set", "gap"], "expected NAME=VALUE"),
    ] {
        let (ok, _, err) = identify(&args);
        assert!(!ok, "{args:?} should fail");
        assert!(err.contains(expected), "{args:?}: {err}");
    }
    assert!(!dir.join("identify").join("fe_ramps").exists(), "no FE ran");
    std::fs::remove_dir_all(dir).unwrap();
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
        (&["--sensitivities", "mu1,wal_bias"], "unknown parameter 'wal_bias'"),
        (&["--sensitivities", "mu1,mu1"], "'mu1' is listed twice"),
        (
            &["--material", "neo_hookean:0.3", "--sensitivities", "mu1"],
            "mu1: the material is not a second-order Ogden law",
        ),
        (
            &[
                "--mode",
                "force",
                "--effect",
                "plate_compliance=0.1",
                "--sensitivities",
                "all",
            ],
            "derivatives at a compliant plate",
        ),
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

/// The attribute `name="…"` of the first tag that has one, parsed.
fn attribute<T: std::str::FromStr>(xml: &str, name: &str) -> T {
    let key = format!(" {name}=\"");
    let start = xml.find(&key).unwrap_or_else(|| panic!("no {name}")) + key.len();
    let len = xml[start..].find('"').unwrap();
    xml[start..start + len]
        .parse()
        .unwrap_or_else(|_| panic!("{name} = {:?}", &xml[start..start + len]))
}

/// The opening tag and the values of the `DataArray` named `name`.
fn data_array<'a>(xml: &'a str, name: &str) -> (&'a str, Vec<f64>) {
    let at = xml
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no DataArray {name}"));
    let open = xml[..at].rfind("<DataArray").unwrap();
    let body = open + xml[open..].find('>').unwrap() + 1;
    let end = body + xml[body..].find("</DataArray>").unwrap();
    let values = xml[body..end]
        .split_whitespace()
        .map(|x| x.parse().unwrap_or_else(|_| panic!("{name}: {x:?}")))
        .collect();
    (&xml[open..body], values)
}

/// A volume file of `simulate --vtk` is a complete VTK unstructured grid of the whole mesh:
/// balanced elements, one point per node, each hexahedron written as 8 linear ones (VTK type
/// 12) over those points, and a displacement, 3 components per point, that is not zero.
fn check_step_vtu(vtu: &str, nodes: usize, elements: usize) {
    assert!(vtu.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\""));
    assert!(vtu.trim_end().ends_with("</VTKFile>"));
    for tag in [
        "VTKFile",
        "UnstructuredGrid",
        "Piece",
        "Points",
        "Cells",
        "PointData",
        "CellData",
        "DataArray",
    ] {
        let opened =
            vtu.matches(&format!("<{tag} ")).count() + vtu.matches(&format!("<{tag}>")).count();
        assert_eq!(
            opened,
            vtu.matches(&format!("</{tag}>")).count(),
            "<{tag}> unbalanced"
        );
    }
    assert_eq!(vtu.matches("<Piece ").count(), 1);
    let piece = &vtu[vtu.find("<Piece ").unwrap()..];
    let points: usize = attribute(piece, "NumberOfPoints");
    let cells: usize = attribute(piece, "NumberOfCells");
    assert_eq!(points, nodes, "NumberOfPoints against the JSON's nodes");
    assert_eq!(
        cells,
        8 * elements,
        "NumberOfCells against the JSON's elements"
    );
    let (_, position) = data_array(vtu, "position");
    assert_eq!(position.len(), 3 * points);
    let (_, connectivity) = data_array(vtu, "connectivity");
    assert_eq!(connectivity.len(), 8 * cells);
    assert!(connectivity
        .iter()
        .all(|&n| n >= 0.0 && (n as usize) < points));
    let (_, offsets) = data_array(vtu, "offsets");
    assert_eq!(offsets.len(), cells);
    assert_eq!(offsets.last().copied(), Some((8 * cells) as f64));
    let (_, types) = data_array(vtu, "types");
    assert!(types.len() == cells && types.iter().all(|&t| t == 12.0));
    let (tag, displacement) = data_array(vtu, "displacement");
    assert_eq!(attribute::<usize>(tag, "NumberOfComponents"), 3);
    assert_eq!(displacement.len(), 3 * points);
    assert!(displacement.iter().all(|u| u.is_finite()));
    assert!(
        displacement.iter().any(|&u| u != 0.0),
        "no displacement at 0.1 bar"
    );
    let (_, von_mises) = data_array(vtu, "von_mises");
    assert_eq!(von_mises.len(), points);
}

#[test]
fn small_run_writes_json_and_vtk() {
    let dir = scratch("fe_cli");
    let json = dir.join("r.json");
    let vtk = dir.join("vtk");
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
    let nodes = v["nodes"].as_u64().unwrap() as usize;
    let elements = v["elements"].as_u64().unwrap() as usize;
    check_step_vtu(&vtu, nodes, elements);
    assert!(vtk.join("step_001_surfaces.vtu").exists());
    let contact = std::fs::read_to_string(vtk.join("step_001_contact.vtu")).unwrap();
    assert!(contact.contains("Name=\"gap_mm\"") && contact.contains("contact_pressure_mpa"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn force_mode_reports_the_plate_reaction() {
    let dir = scratch("fe_force");
    let json = dir.join("f.json");
    let (ok, _, err) = simulate(&[
        "--n",
        "7",
        "--t",
        "2.4",
        "--pressures",
        "0,1",
        "--mesh",
        "coarse",
        "--mode",
        "force",
        "--out",
        json.to_str().unwrap(),
        "--sensitivities",
        "plate_offset,force_scale",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let steps = v["steps"].as_array().unwrap();
    // the plate is 5 mm below the hanging tip: no force at P = 0 (the scale is tared); at 1 bar
    // the bent tip presses on it (about 0.005 N on this mesh)
    assert_eq!(steps[0]["force_n"].as_f64().unwrap(), 0.0);
    let force = steps[1]["force_n"].as_f64().unwrap();
    assert!(force > 0.0, "blocked force {force} N at 1 bar");
    // --sensitivities: beside --out, one entry per step and parameter; the load cell's scale
    // changes the force by the force itself, a plate further down lowers it
    let sens: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("f_sensitivities.json")).unwrap())
            .unwrap();
    assert_eq!(sens["format"], "surrogate-sensitivities");
    assert_eq!(sens["parameters"][0]["parameter"], "plate_offset");
    let last = &sens["steps"][1];
    // the same force, summed over the plate's faces in another order
    let f = last["values"]["force_n"].as_f64().unwrap();
    assert!((f - force).abs() <= 1e-9 * force, "{f} vs {force}");
    let d = |k: usize| last["derivatives"][k]["force_n"].as_f64().unwrap();
    assert!(d(0) < 0.0, "dF/d plate_offset = {} N/mm", d(0));
    assert!(
        (d(1) - force).abs() <= 1e-12 * force,
        "dF/d scale {} vs F {force}",
        d(1)
    );
    assert!(err.contains("derivatives at 1 bar"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
