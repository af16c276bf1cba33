//! The search recovers a design from its own predictions, reports a target out of reach on a
//! bound, and visits every N inside the bounds.
use surrogate::case::{OgdenSet, Query};
use surrogate::design::{search, DesignBounds, DesignSearch, Side, TLimit};
use surrogate::rom::Surrogate;

use crate::common::{angle_and_force, search_all, shipped, synthetic, CALIBRATED, OGDEN_002};

/// A cost this small is a design that meets every target (residuals of 10⁻⁴ tolerances).
const MET: f64 = 1e-8;

/// Asks for the angle and force `(n, t)` gives at 2 bar; the pick is `(n, t)`, or another
/// `N` that meets both targets as well while `n` does too, at `t`.
fn assert_recovers(model: &Surrogate, material: OgdenSet, n: u32, t: f64) {
    let pred = model.predict(&Query::new(n, t, 2.0, material)).unwrap();
    let targets = angle_and_force(pred.angle_deg(), pred.force_n());
    let report = search_all(model, material, &targets);
    let pick = &report.pick;
    let at_n = report.at(n).and_then(|d| d.best.as_ref()).unwrap();
    assert!(
        at_n.cost < MET && (at_n.t_mm - t).abs() < 0.01,
        "N = {n}: T = {} (cost {}), expected {t}: {report:#?}",
        at_n.t_mm,
        at_n.cost
    );
    if pick.n == n {
        assert!((pick.t_mm - t).abs() < 0.01, "{report:#?}");
    } else {
        assert!(
            pick.cost < MET,
            "pick N = {} instead of {n}: {report:#?}",
            pick.n
        );
    }
    assert!(pick.bound.is_none(), "{:?}", pick.bound);
    for o in &pick.outputs {
        assert!(
            o.surrogate_std.is_finite() && o.surrogate_std >= 0.0,
            "{o:?}"
        );
        assert!(
            (o.predicted - o.target.value).abs() < 1e-3 * o.target.tolerance,
            "{o:?}"
        );
    }
}

#[test]
fn the_shipped_model_recovers_a_design() {
    assert_recovers(shipped(), CALIBRATED, 11, 2.0);
    assert_recovers(shipped(), CALIBRATED, 13, 1.63);
}

#[test]
fn a_synthetic_model_over_nine_n_recovers_a_design() {
    assert_recovers(synthetic(), OGDEN_002, 12, 1.9);
    assert_recovers(synthetic(), OGDEN_002, 15, 2.1);
}

#[test]
fn the_search_visits_every_n_inside_the_bounds() {
    let model = synthetic();
    assert_eq!(model.n_allowed, (7..=15).collect::<Vec<u32>>());
    let targets = angle_and_force(40.0, 1.2);
    let all = search_all(model, OGDEN_002, &targets);
    let ns: Vec<u32> = all.designs.iter().map(|d| d.n).collect();
    assert_eq!(ns, model.n_allowed);
    assert!(all.designs.iter().all(|d| d.best.is_some()));
    let bounds = DesignBounds::new((8, 14), (1.5, 2.5));
    let some = search(
        model,
        OGDEN_002,
        &targets,
        &bounds,
        &DesignSearch::default(),
    )
    .unwrap();
    let ns: Vec<u32> = some.designs.iter().map(|d| d.n).collect();
    assert_eq!(ns, (8..=14).collect::<Vec<u32>>());
    for d in &some.designs {
        let c = d.best.as_ref().unwrap();
        assert!(c.t_mm >= 1.5 && c.t_mm <= 2.5, "{d:?}");
    }
}

#[test]
fn a_target_out_of_reach_puts_t_on_the_bound_that_comes_closest() {
    let model = synthetic();
    // no wall bends 500°: the thinnest comes closest
    let report = search_all(model, OGDEN_002, &angle_and_force(500.0, 1.0)[..1]);
    for d in &report.designs {
        let c = d.best.as_ref().unwrap();
        let hit = c.bound.unwrap_or_else(|| panic!("{d:?}"));
        assert_eq!((hit.side, hit.limit), (Side::Lower, TLimit::Model), "{d:?}");
        assert_eq!(c.t_mm, d.t_min_mm);
    }
    // no wall pushes 100 N: the thickest buildable comes closest
    let report = search_all(model, OGDEN_002, &angle_and_force(0.0, 100.0)[1..]);
    for d in &report.designs {
        let c = d.best.as_ref().unwrap();
        let hit = c.bound.unwrap_or_else(|| panic!("{d:?}"));
        assert_eq!((hit.side, c.t_mm), (Side::Upper, d.t_max_mm), "{d:?}");
    }
    let limit = |n: u32| {
        report
            .at(n)
            .unwrap()
            .best
            .as_ref()
            .unwrap()
            .bound
            .unwrap()
            .limit
    };
    // 15 bellows leave a cavity up to T = 2.32 mm, 7 up to 5.8 mm (beyond the model's range)
    assert_eq!(limit(15), TLimit::Buildable);
    assert_eq!(limit(7), TLimit::Model);
    assert!(report.at(15).unwrap().t_max_mm < 2.33);
    assert_eq!(report.pick.bound.map(|b| b.side), Some(Side::Upper));
}

#[test]
fn the_pick_states_whether_its_accuracy_is_known() {
    let targets = angle_and_force(40.0, 1.3);
    let shipped_report = search_all(shipped(), CALIBRATED, &targets);
    let known = shipped().model_form().is_some();
    assert_eq!(
        matches!(
            shipped_report.accuracy,
            surrogate::design::Accuracy::Known { .. }
        ),
        known
    );
    assert!(shipped_report
        .pick
        .outputs
        .iter()
        .all(|o| o.model_form.is_some() == known));
    let synthetic_report = search_all(synthetic(), OGDEN_002, &targets);
    assert_eq!(
        synthetic_report.accuracy,
        surrogate::design::Accuracy::Unknown
    );
    assert!(synthetic_report.accuracy.to_string().contains("unknown"));
    assert!(synthetic_report
        .pick
        .outputs
        .iter()
        .all(|o| o.model_form.is_none()));
    // the report is written as JSON
    let json = serde_json::to_string(&synthetic_report).unwrap();
    assert!(
        json.contains("\"pick\"") && json.contains("\"angle_deg\""),
        "{json}"
    );
}

#[test]
fn buildability_follows_the_geometry_the_model_was_trained_with() {
    use surrogate::design::map;
    use surrogate::fe::preset::Geometry;
    use surrogate::rom::provenance::BuiltWith;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fe_reference/identification/wall_law/geometry.json");
    let geometry = Geometry::load(&path).unwrap();
    let mut model = synthetic().clone();
    model.training.built_with = Some(BuiltWith {
        geometry: geometry.clone(),
        effects: Default::default(),
    });
    let force = &angle_and_force(0.0, 100.0)[1..];
    let report = search_all(&model, OGDEN_002, force);
    let as_modelled = search_all(synthetic(), OGDEN_002, force);
    assert_eq!(report.geometry, geometry.name);
    // the model's own range: the largest T of the plain search at N = 7 (5.8 mm buildable)
    let model_t_max = as_modelled.at(7).unwrap().t_max_mm;
    for d in &report.designs {
        let limit = geometry.max_wall_thickness(d.n as usize).unwrap();
        let expected = if limit < model_t_max {
            (limit, TLimit::Buildable)
        } else {
            (model_t_max, TLimit::Model)
        };
        assert_eq!((d.t_max_mm, d.t_max_limit), expected, "{d:?}");
    }
    let (wall_law, plain) = (report.at(15).unwrap(), as_modelled.at(15).unwrap());
    assert!(wall_law.t_max_mm < plain.t_max_mm, "{wall_law:?} {plain:?}");
    let m = map(
        &model,
        OGDEN_002,
        &[surrogate::design::Output::ForceN],
        &[2.0],
        &[15],
        &[2.0],
    )
    .unwrap();
    assert_eq!(m.t_max_buildable_mm, vec![wall_law.t_max_mm]);
}
