//! One training domain: the snapshot plan's report and the surrogate's check are the same
//! function on the same box, so they agree on every query (the shipped plan and model too).
use std::path::Path;

use surrogate::case::{Domain, OgdenSet, Query};
use surrogate::rom::Surrogate;
use surrogate::snapshots::plan::Plan;

fn repo(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn names(v: &[surrogate::case::DomainViolation]) -> Vec<String> {
    v.iter().map(|d| d.name.clone()).collect()
}

/// The shipped coarse model was trained on every case of the shipped coarse plan: its domain
/// is the plan's sampled domain, and both say the same of the literature sets (both inside:
/// ogden_005's α₂ = −0.0054 lies beyond the largest sampled α₂ but inside the plan's
/// −0.004, which the cases reach within one stratum; its μ₂ = −1214 MPa is an ordinary μ₂α₂)
/// and of queries across and beyond the box.
#[test]
fn shipped_plan_and_model_agree() {
    let plan = Plan::read(&repo("training_data/snapshots_coarse.plan.json")).unwrap();
    for model in [
        "models/as_modelled/actuator_coarse.json",
        "models/as_modelled/actuator.json",
    ] {
        let m = Surrogate::load(&repo(model)).unwrap();
        assert_eq!(m.domain(), plan.sampled_domain(), "{model}");
        for (name, outside) in plan.literature_in_sampled_domain().unwrap() {
            let set = surrogate::rom::batch::material_params(&name).unwrap();
            let q = Query::new(11, 2.0, 1.0, set);
            assert_eq!(m.domain_violations(&q), outside, "{model}, {name}");
            assert!(outside.is_empty(), "{name}: {outside:?}");
        }
        // a grid of queries over and beyond the box
        let mut seen_outside = 0;
        for (i, t) in [1.2, 1.5, 2.6, 3.0].into_iter().enumerate() {
            for p in [-1.0, 0.0, 2.0, 3.5, 5.0] {
                for (mu1, a1, mu2, a2) in [
                    (1.13, 3.11, -13.17, -0.6),
                    (0.13, 3.05, -1214.0, -0.0054),
                    (2.0, 7.5, -4.0, -2.5),
                    (0.5, 1.6, -30.0, -0.2),
                ] {
                    let q = Query::new(
                        [9, 11, 13, 11][i],
                        t,
                        p,
                        OgdenSet::from_array([mu1, a1, mu2, a2]),
                    );
                    let a = m.domain_violations(&q);
                    assert_eq!(a, plan.sampled_domain().violations(&q), "{q:?}");
                    seen_outside += usize::from(!a.is_empty());
                }
            }
        }
        assert!(seen_outside > 0);
    }
}

/// Outside the pressure grid the prediction is the value at the nearer end (clamped, and
/// flagged so); outside the feature box it extrapolates (flagged, not clamped).
#[test]
fn violations_say_whether_the_prediction_is_clamped() {
    let m = Surrogate::load(&repo("models/as_modelled/actuator_coarse.json")).unwrap();
    let base = Query::new(
        11,
        2.0,
        3.5,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    let at_end = m.predict(&base).unwrap().values;
    for p in [5.0, 3.6] {
        let q = Query { p_bar: p, ..base };
        let v = m.domain_violations(&q);
        assert_eq!(names(&v), ["pressure_bar"]);
        assert!(v[0].clamped && v[0].used() == 3.5);
        assert_eq!(m.predict(&q).unwrap().values, at_end);
    }
    let v = m.domain_violations(&Query {
        p_bar: -1.0,
        ..base
    });
    assert!(v[0].clamped && v[0].used() == 0.0);
    let v = m.domain_violations(&Query { t_mm: 5.0, ..base });
    assert_eq!(names(&v), ["wall_thickness_mm"]);
    assert!(!v[0].clamped && v[0].used() == 5.0);
    assert!(m.check_domain(&Query { t_mm: 5.0, ..base }, false).is_err());
    assert_eq!(
        m.check_domain(&Query { t_mm: 5.0, ..base }, true).unwrap(),
        v
    );
    // the gradient with respect to P is zero where P is clamped
    let mut pred = m.new_prediction();
    let mut jac = surrogate::rom::Jacobian::default();
    m.gradient_into(&Query { p_bar: 5.0, ..base }, &mut pred, &mut jac)
        .unwrap();
    assert!(jac.d.iter().all(|row| row[1] == 0.0));
}

/// The shipped models state the plan's nominal ranges (the 300 cases reach within one stratum
/// of every end): T = 1.4 and 2.6 mm are predicted in the domain, 1.39 and 2.61 are refused;
/// the stated ranges are what `train` derives from the committed plan, and a model file
/// without them (written before they existed) still loads, with the box of its cases.
#[test]
fn shipped_domain_is_the_plans_nominal_box() {
    let plan_path = "training_data/snapshots_coarse.plan.json";
    let plan = Plan::read(&repo(plan_path)).unwrap();
    for model in [
        "models/as_modelled/actuator_coarse.json",
        "models/as_modelled/actuator.json",
    ] {
        let m = Surrogate::load(&repo(model)).unwrap();
        let stated = m.training.plan_domain.clone().expect("stated ranges");
        assert_eq!(stated, plan.stated_domain(&m.sampled_domain(), plan_path));
        let d = m.domain();
        let nominal = &plan.ranges;
        assert_eq!(d.ranges[1], Some(nominal.wall_thickness_mm));
        assert_eq!(d.ranges[3], Some(nominal.mu0_mpa));
        assert_eq!(d.ranges[4], Some(nominal.term1_share));
        assert_eq!(d.ranges[5], Some(nominal.alpha1));
        assert_eq!(d.ranges[6], Some(nominal.alpha2));
        let q = |t: f64| Query::new(11, t, 2.0, OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]));
        for t in [1.4, 2.6] {
            assert_eq!(
                m.check_domain(&q(t), false).unwrap(),
                [],
                "{model}: T = {t}"
            );
            let p = m.predict(&q(t)).unwrap();
            assert!(p.tip_uz_mm().is_finite());
        }
        for t in [1.39, 2.61] {
            let e = m.check_domain(&q(t), false).unwrap_err().to_string();
            assert!(
                e.contains(&format!(
                    "wall_thickness_mm = {t} outside the training domain [1.4, 2.6]"
                )),
                "{e}"
            );
        }
        // the same model without the stated ranges: the box of its cases
        let mut old = m.clone();
        old.training.plan_domain = None;
        let old = Surrogate::from_json(&old.to_json().unwrap(), "old").unwrap();
        assert!(!old.to_json().unwrap().contains("plan_domain"));
        assert_eq!(old.domain(), old.sampled_domain());
        assert_eq!(
            names(&old.domain_violations(&q(1.4))),
            ["wall_thickness_mm"]
        );
    }
}

/// Where the cases come within one stratum of a nominal end (1/K of the range, μ0 in ln μ0),
/// the domain takes the end; where they miss it by more, it keeps the cases' extreme.
#[test]
fn plan_ends_are_taken_only_where_the_cases_cover_them() {
    let nominal = Domain {
        n_bellows: vec![9, 11],
        ranges: [
            None,
            Some([1.0, 2.0]),
            Some([0.0, 3.0]),
            Some([2.0, 8.0]),
            Some([0.0, 1.0]),
            Some([1.0, 5.0]),
            Some([-2.0, -1.0]),
        ],
    };
    let sampled = Domain {
        n_bellows: vec![9],
        ranges: [
            None,
            Some([1.09, 1.95]),
            Some([0.0, 3.5]),
            Some([2.0 * (4f64.ln() / 20.0).exp(), 7.9]),
            Some([0.3, 1.0]),
            Some([1.0, 5.0]),
            None,
        ],
    };
    // K = 10: one stratum is 0.1 of T's range, ln 4 / 10 of ln μ0's
    let d = sampled.with_plan_ends(&nominal, 10);
    assert_eq!(d.ranges[1], Some([1.0, 2.0]));
    assert_eq!(d.ranges[2], Some([0.0, 3.5]), "the pressure grid is kept");
    assert_eq!(d.ranges[3].unwrap()[1], 8.0);
    assert_eq!(d.ranges[4], Some([0.3, 1.0]), "0.3 misses 0 by 3 strata");
    assert_eq!(d.ranges[5], Some([1.0, 5.0]));
    assert_eq!(d.ranges[6], None, "unconstrained stays so");
    assert_eq!(d.n_bellows, [9], "N is never widened");
    // ln μ0: the cases' lowest lies half a stratum (ln 4 / 20) above the end
    assert_eq!(d.ranges[3].unwrap()[0], 2.0);
    // K = 100: T's ends are missed by more than a stratum
    let d = sampled.with_plan_ends(&nominal, 100);
    assert_eq!(d.ranges[1], Some([1.09, 1.95]));
}

/// A value beyond an end by at most `BOUND_TOLERANCE` of the range is inside and is moved onto
/// the end with a note; beyond that it is a violation. The calibrated set of the shipped
/// experiments lies on bounds of the box of the cases: printed to four decimals, it was
/// refused by that box (`term1_share = 0.021607… outside [0.021614…]`); it is accepted now.
#[test]
fn values_within_the_tolerance_of_an_end_are_moved_onto_it() {
    let mut m = Surrogate::load(&repo("models/as_modelled/actuator.json")).unwrap();
    m.training.plan_domain = None; // the box of the cases: its ends are the calibrated bounds
    let printed = Query::new(
        11,
        2.0,
        2.0,
        OgdenSet::from_array([0.0382, 5.9961, -5.1949, -1.9965]),
    );
    assert_eq!(m.domain_violations(&printed), []);
    let (snapped, notes) = m.snap_to_domain(&printed);
    assert_eq!(names_of(&notes), ["term1_share", "alpha2"]);
    let d = m.domain();
    let s_lo = d.ranges[4].unwrap()[0];
    let a2_lo = d.ranges[6].unwrap()[0];
    let sm = &snapped.material;
    assert_eq!(sm.alpha2, a2_lo);
    let s = sm.mu1_mpa * sm.alpha1 / (sm.mu1_mpa * sm.alpha1 + sm.mu2_mpa * sm.alpha2);
    assert!((s - s_lo).abs() < 1e-14, "{s} {s_lo}");
    assert_eq!(
        sm.alpha1, printed.material.alpha1,
        "α₁ = 5.9961 lies inside"
    );
    assert_eq!(m.domain_violations(&snapped), []);
    let note = notes[0].to_string();
    assert!(
        note.contains("term1_share = 0.0216")
            && note.contains("within the tolerance at the ends (1e-4 of the range)"),
        "{note}"
    );
    // beyond the tolerance: refused as before, and not moved
    let width = d.ranges[6].unwrap()[1] - a2_lo;
    let far = Query {
        material: OgdenSet {
            alpha2: a2_lo - 2.0 * surrogate::case::BOUND_TOLERANCE * width,
            ..snapped.material
        },
        ..snapped
    };
    assert_eq!(names(&m.domain_violations(&far)), ["alpha2"]);
    assert!(!names_of(&m.snap_to_domain(&far).1).contains(&"alpha2".to_string()));
    // inside: untouched
    let inside = Query::new(
        11,
        2.0,
        2.0,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    assert_eq!(m.snap_to_domain(&inside), (inside, vec![]));
}

fn names_of(v: &[surrogate::case::BoundSnap]) -> Vec<String> {
    v.iter().map(|d| d.name.clone()).collect()
}

/// A plan with a geometry preset and fixed effects states them in the model it trains
/// (`training.built_with`), and the model file carries them through a round trip; the shipped
/// plan names neither, so the shipped models carry none (their files are unchanged).
#[test]
fn models_state_the_geometry_their_cases_were_built_with() {
    use surrogate::fe::effects::Effects;
    use surrogate::fe::preset::Geometry;
    use surrogate::rom::data::SnapshotSet;
    let plan_path = "training_data/snapshots_coarse.plan.json";
    let mut plan = Plan::read(&repo(plan_path)).unwrap();
    let cases = SnapshotSet::read(&repo("training_data/snapshots_coarse.csv"))
        .unwrap()
        .into_cases()
        .unwrap();
    let shipped = Surrogate::load(&repo("models/as_modelled/actuator_coarse.json")).unwrap();
    assert_eq!(shipped.training.built_with, None);
    let mut m = shipped.clone();
    assert!(m.state_plan_domain(&plan, &cases, plan_path));
    assert_eq!(m.training.built_with, None);
    let identified = Geometry::load(&repo("data/geometry/identified.json")).unwrap();
    plan.settings.geometry = Some(identified.clone());
    plan.settings.effects = Effects::parse(["plate_offset=-4.5"]).unwrap();
    assert!(m.state_plan_domain(&plan, &cases, plan_path));
    let built = m.training.built_with.clone().expect("stated");
    assert_eq!(built.geometry, identified);
    assert_eq!(built.effects, plan.settings.effects);
    let back = Surrogate::from_json(&m.to_json().unwrap(), "round trip").unwrap();
    assert_eq!(back.training.built_with, Some(built));
}

/// Plans that build their cases alike (the design-space set and its box extension's rounds:
/// the identified geometry and plate) share one statement of it; a plan built otherwise (the
/// as-modelled coarse set) is found by its index.
#[test]
fn plans_built_alike_share_one_statement_and_another_is_found() {
    use surrogate::rom::provenance::BuiltWith;
    let read = |p: &str| Plan::read(&repo(p)).unwrap();
    let ds = read("training_data/snapshots_design_space_coarse.plan.json");
    let ext = read("fe_reference/identification/design_space/extend/extend_1.plan.json");
    let as_modelled = read("training_data/snapshots_coarse.plan.json");
    let built = BuiltWith::of_plans(&[&ds, &ext]).unwrap().expect("stated");
    assert_eq!(built, BuiltWith::of_plan(&ds).unwrap());
    assert_eq!(BuiltWith::of_plans(&[&ds, &ext, &as_modelled]), Err(2));
    assert_eq!(BuiltWith::of_plans(&[&as_modelled, &ds]), Err(1));
    assert_eq!(BuiltWith::of_plans(&[&as_modelled]), Ok(None));
    assert_eq!(BuiltWith::of_plans(&[]), Ok(None));
}
