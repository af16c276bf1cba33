//! One training domain: the snapshot plan's report and the surrogate's check are the same
//! function on the same box, so they agree on every query (the shipped plan and model too).
use std::path::Path;

use surrogate::rom::{Query, Surrogate};
use surrogate::snapshots::plan::Plan;

fn repo(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn names(v: &[surrogate::rom::DomainViolation]) -> Vec<String> {
    v.iter().map(|d| d.name.clone()).collect()
}

/// The shipped coarse model was trained on every case of the shipped coarse plan: its domain
/// is the plan's sampled domain, and both say the same of the literature sets (ogden_005's
/// α₂ = −0.0054 lies beyond the largest sampled α₂, and only that: its μ₂ = −1214 MPa is an
/// ordinary μ₂α₂) and of queries across and beyond the box.
#[test]
fn shipped_plan_and_model_agree() {
    let plan = Plan::read(&repo("training_data/snapshots_coarse.plan.json")).unwrap();
    for model in ["models/actuator_coarse.json", "models/actuator.json"] {
        let m = Surrogate::load(&repo(model)).unwrap();
        assert_eq!(m.domain(), plan.sampled_domain(), "{model}");
        for (name, outside) in plan.literature_in_sampled_domain().unwrap() {
            let set = surrogate::rom::batch::material_params(&name).unwrap();
            let q = Query::new(11, 2.0, 1.0, set);
            assert_eq!(m.domain_violations(&q), outside, "{model}, {name}");
            let expected: &[&str] = if name == "ogden_005" {
                &["alpha2"]
            } else {
                &[]
            };
            assert_eq!(names(&outside), expected, "{name}");
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
                    let q = Query::new([9, 11, 13, 11][i], t, p, [mu1, a1, mu2, a2]);
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
    let m = Surrogate::load(&repo("models/actuator_coarse.json")).unwrap();
    let base = Query::new(11, 2.0, 3.5, [1.13, 3.11, -13.17, -0.6]);
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
