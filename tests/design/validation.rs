//! Bad input is refused at the door with an error naming the field, the value and what was
//! expected.
use surrogate::case::OgdenSet;
use surrogate::design::{map, search, DesignBounds, DesignError, DesignSearch, Output, Target};
use surrogate::rom::Surrogate;

use crate::common::{angle_and_force, shipped, CALIBRATED};

/// The inputs of one search: a valid one changed in one place.
#[derive(Clone)]
struct Inputs {
    material: OgdenSet,
    targets: Vec<Target>,
    bounds: DesignBounds,
    settings: DesignSearch,
}

/// Asserts that the search on `inputs` is refused with an error that names `field` and
/// contains every one of `needles`.
fn refused(model: &Surrogate, inputs: &Inputs, field: &str, needles: &[&str]) {
    let Inputs {
        material,
        targets,
        bounds,
        settings,
    } = inputs;
    let e = search(model, *material, targets, bounds, settings).unwrap_err();
    let text = e.to_string();
    match &e {
        DesignError::Invalid { field: f, .. } => assert_eq!(f, field, "{text}"),
        other => panic!("expected an invalid {field}, got {other:?}"),
    }
    for n in needles {
        assert!(text.contains(n), "{text} lacks {n:?}");
    }
}

/// Each case changes one input of a valid search (the calibrated material, angle and force
/// targets at 2 bar, the model's bounds, the default settings).
#[test]
fn bad_targets_bounds_materials_and_settings_are_named() {
    let m = shipped();
    let valid = Inputs {
        material: CALIBRATED,
        targets: angle_and_force(40.0, 1.3).to_vec(),
        bounds: DesignBounds::of_model(m),
        settings: DesignSearch::default(),
    };
    let with = |change: &dyn Fn(&mut Inputs)| {
        let mut i = valid.clone();
        change(&mut i);
        i
    };
    let bounds = |n, t| with(&|i| i.bounds = DesignBounds::new(n, t));
    let cases: [(Inputs, &str, &[&str]); 17] = [
        // targets
        (
            with(&|i| i.targets.clear()),
            "targets",
            &["at least one target"],
        ),
        (
            with(&|i| i.targets[0].value = f64::NAN),
            "targets[0].value",
            &["NaN", "finite angle_deg"],
        ),
        (
            with(&|i| i.targets[1].tolerance = 0.0),
            "targets[1].tolerance",
            &["= 0", "> 0"],
        ),
        (
            with(&|i| i.targets[1].tolerance = -1.0),
            "targets[1].tolerance",
            &["-1"],
        ),
        (
            with(&|i| i.targets[0].p_bar = 5.0),
            "targets[0].p_bar",
            &["= 5", "[0, 3.5] bar"],
        ),
        (
            with(&|i| i.targets[0].p_bar = f64::INFINITY),
            "targets[0].p_bar",
            &["inf"],
        ),
        // bounds
        (
            bounds((13, 9), (1.4, 2.6)),
            "bounds.n",
            &["13..=9", "MIN ≤ MAX"],
        ),
        (
            bounds((7, 13), (1.4, 2.6)),
            "bounds.n",
            &["7..=13", "9..=13"],
        ),
        (bounds((10, 10), (1.4, 2.6)), "bounds.n", &["[9, 11, 13]"]),
        (bounds((9, 13), (2.5, 1.5)), "bounds.t_mm", &["2.5..=1.5"]),
        (
            bounds((9, 13), (0.5, 2.0)),
            "bounds.t_mm",
            &["0.5", "[1.4, 2.6] mm"],
        ),
        (bounds((9, 13), (1.4, f64::NAN)), "bounds.t_mm", &["NaN"]),
        // materials
        (
            with(&|i| i.material.alpha1 = -CALIBRATED.alpha1),
            "material",
            &["mu1*alpha1", "the model accepts"],
        ),
        (
            with(&|i| i.material = OgdenSet::from_array([f64::NAN, 1.0, -1.0, -1.0])),
            "material",
            &["finite"],
        ),
        (
            with(&|i| {
                i.material = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6].map(|v| 10.0 * v))
            }),
            "material",
            &["training domain", "mu0_mpa"],
        ),
        // settings
        (
            with(&|i| i.settings.starts = 0),
            "settings.starts",
            &["at least 1"],
        ),
        (
            with(&|i| i.settings.step_tolerance_mm = 0.0),
            "settings.step_tolerance_mm",
            &["> 0"],
        ),
    ];
    for (inputs, field, needles) in &cases {
        refused(m, inputs, field, needles);
    }
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
