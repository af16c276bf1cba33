//! Bad input is refused at the door with an error naming the field, the value and what was
//! expected.
use surrogate::design::{map, search, DesignBounds, DesignError, DesignSearch, Output, Target};
use surrogate::rom::Surrogate;

use crate::common::{angle_and_force, shipped, CALIBRATED};

/// The search's error, which must name `field` and contain every one of `needles`.
fn refused(
    model: &Surrogate,
    material: [f64; 4],
    targets: &[Target],
    bounds: DesignBounds,
    settings: DesignSearch,
    field: &str,
    needles: &[&str],
) {
    let e = search(model, material, targets, &bounds, &settings).unwrap_err();
    let text = e.to_string();
    match &e {
        DesignError::Invalid { field: f, .. } => assert_eq!(f, field, "{text}"),
        other => panic!("expected an invalid {field}, got {other:?}"),
    }
    for n in needles {
        assert!(text.contains(n), "{text} lacks {n:?}");
    }
}

#[test]
fn bad_targets_are_named() {
    let m = shipped();
    let (b, s) = (DesignBounds::of_model(m), DesignSearch::default());
    let ok = angle_and_force(40.0, 1.3);
    refused(
        m,
        CALIBRATED,
        &[],
        b,
        s,
        "targets",
        &["at least one target"],
    );
    let mut t = ok;
    t[0].value = f64::NAN;
    refused(
        m,
        CALIBRATED,
        &t,
        b,
        s,
        "targets[0].value",
        &["NaN", "finite angle_deg"],
    );
    let mut t = ok;
    t[1].tolerance = 0.0;
    refused(
        m,
        CALIBRATED,
        &t,
        b,
        s,
        "targets[1].tolerance",
        &["= 0", "> 0"],
    );
    let mut t = ok;
    t[1].tolerance = -1.0;
    refused(m, CALIBRATED, &t, b, s, "targets[1].tolerance", &["-1"]);
    let mut t = ok;
    t[0].p_bar = 5.0;
    refused(
        m,
        CALIBRATED,
        &t,
        b,
        s,
        "targets[0].p_bar",
        &["= 5", "[0, 3.5] bar"],
    );
    t[0].p_bar = f64::INFINITY;
    refused(m, CALIBRATED, &t, b, s, "targets[0].p_bar", &["inf"]);
}

#[test]
fn bad_bounds_are_named() {
    let m = shipped();
    let (t, s) = (angle_and_force(40.0, 1.3), DesignSearch::default());
    let bounds = |n, t| DesignBounds::new(n, t);
    refused(
        m,
        CALIBRATED,
        &t,
        bounds((13, 9), (1.4, 2.6)),
        s,
        "bounds.n",
        &["13..=9", "MIN ≤ MAX"],
    );
    refused(
        m,
        CALIBRATED,
        &t,
        bounds((7, 13), (1.4, 2.6)),
        s,
        "bounds.n",
        &["7..=13", "9..=13"],
    );
    refused(
        m,
        CALIBRATED,
        &t,
        bounds((10, 10), (1.4, 2.6)),
        s,
        "bounds.n",
        &["[9, 11, 13]"],
    );
    refused(
        m,
        CALIBRATED,
        &t,
        bounds((9, 13), (2.5, 1.5)),
        s,
        "bounds.t_mm",
        &["2.5..=1.5"],
    );
    refused(
        m,
        CALIBRATED,
        &t,
        bounds((9, 13), (0.5, 2.0)),
        s,
        "bounds.t_mm",
        &["0.5", "[1.4, 2.6] mm"],
    );
    refused(
        m,
        CALIBRATED,
        &t,
        bounds((9, 13), (1.4, f64::NAN)),
        s,
        "bounds.t_mm",
        &["NaN"],
    );
}

#[test]
fn bad_materials_and_settings_are_named() {
    let m = shipped();
    let (t, b) = (angle_and_force(40.0, 1.3), DesignBounds::of_model(m));
    let s = DesignSearch::default();
    let flipped = [CALIBRATED[0], -CALIBRATED[1], CALIBRATED[2], CALIBRATED[3]];
    refused(
        m,
        flipped,
        &t,
        b,
        s,
        "material",
        &["mu1*alpha1", "the model accepts"],
    );
    let nan = [f64::NAN, 1.0, -1.0, -1.0];
    refused(m, nan, &t, b, s, "material", &["finite"]);
    let stiff = [1.13, 3.11, -13.17, -0.6].map(|v| 10.0 * v);
    refused(
        m,
        stiff,
        &t,
        b,
        s,
        "material",
        &["training domain", "mu0_mpa"],
    );
    let zero = DesignSearch { starts: 0, ..s };
    refused(
        m,
        CALIBRATED,
        &t,
        b,
        zero,
        "settings.starts",
        &["at least 1"],
    );
    let zero = DesignSearch {
        step_tolerance_mm: 0.0,
        ..s
    };
    refused(
        m,
        CALIBRATED,
        &t,
        b,
        zero,
        "settings.step_tolerance_mm",
        &["> 0"],
    );
}

#[test]
fn bad_map_grids_are_named() {
    let m = shipped();
    let field = |r: Result<_, DesignError>| match r {
        Err(DesignError::Invalid { field, .. }) => field,
        other => panic!("expected an invalid field, got {other:?}"),
    };
    let angle = [Output::AngleDeg];
    let run =
        |o: &[Output], p: &[f64], n: &[u32], t: &[f64]| map(m, CALIBRATED, o, p, n, t).map(|_| ());
    assert_eq!(field(run(&[], &[2.0], &[11], &[2.0])), "outputs");
    assert_eq!(
        field(run(&angle, &[2.0, 4.0], &[11], &[2.0])),
        "pressures[1]"
    );
    assert_eq!(field(run(&angle, &[2.0], &[11, 12], &[2.0])), "n_values[1]");
    assert_eq!(field(run(&angle, &[2.0], &[11], &[2.0, 3.0])), "t_grid[1]");
    assert_eq!(field(run(&angle, &[2.0], &[11], &[])), "t_grid");
}
