//! Warm starts across cases (`surrogate::fe::warm_start`, `fe::solver::warm`): a ramp started
//! from a neighbouring case's converged states reaches the same answers as the cold ramp, in
//! far fewer Newton iterations.
//!
//! The comparison is made with the plain penalty contact (`augmented_updates = 0`) and a tight
//! residual tolerance, where the cold ramp's answer does not depend on its path: the
//! augmented-Lagrangian updates stop once every multiplier changes by less than
//! `AUGMENTED_GAP_TOL`, and where they stop depends on where they started, for a cold ramp as
//! for a warm one (`fe_reference/warm_start/README.md` measures both).

use surrogate::fe::effects::Effects;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, MaterialLaw, Ogden2, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::sensitivity::{sensitivities_with_fields, OgdenParameter, Parameter};
use surrogate::fe::simulate::{run_warm, Case, ContactSettings, Mode, Response};
use surrogate::fe::solver::SolverSettings;
use surrogate::fe::warm_start::{FieldSensitivities, WarmStart, WarmStartError};

fn ogden002() -> [f64; 4] {
    Material::from_spec("ogden_002", DEFAULT_BULK_RATIO)
        .unwrap()
        .ogden_set()
        .unwrap()
        .as_array()
}

fn case(n: usize, params: [f64; 4], mode: Mode, pressures_bar: Vec<f64>) -> Case {
    let [m1, a1, m2, a2] = params;
    Case {
        design: DesignParams::new(n, 2.0).validate().unwrap(),
        material: Material::new(
            MaterialLaw::Ogden(Ogden2::new(m1, a1, m2, a2).unwrap()),
            DEFAULT_BULK_RATIO,
        )
        .unwrap(),
        pressures_bar,
        gravity: true,
        mesh: MeshOptions::level(MeshLevel::Coarse),
        solver: SolverSettings {
            rtol: 1e-10,
            augmented_updates: 0,
            ..SolverSettings::default()
        },
        mode,
        contact: ContactSettings::default(),
        effects: Effects::neutral(),
    }
}

fn iterations(r: &Response) -> usize {
    r.steps.iter().map(|s| s.newton_iterations).sum()
}

/// Cold and warm (zeroth and first order) ramps at μ₁ + 5 % from the neighbour at Ogden 002:
/// the same tips (1e-6 relative) and forces (1e-6 N), the warm ones in under a third of the
/// iterations, every level started warm.
fn same_answers_fewer_iterations(mode: Mode, pressures_bar: Vec<f64>) {
    let base = ogden002();
    let parameters = [OgdenParameter::Mu1, OgdenParameter::Alpha1].map(Parameter::Material);
    let neighbour = sensitivities_with_fields(
        &case(9, base, mode, pressures_bar.clone()),
        &parameters,
        None,
        |_, _| {},
        |_, _, _| {},
    )
    .unwrap();
    let mut moved = base;
    moved[0] *= 1.05;
    let target = case(9, moved, mode, pressures_bar);
    let cold = run_warm(&target, None, |_, _| {}, |_, _, _| {}, false)
        .unwrap()
        .response;
    let starts = [
        WarmStart::new(neighbour.states.clone()),
        neighbour.warm_start(&[moved[0] - base[0], 0.0]).unwrap(),
    ];
    for warm in &starts {
        let r = run_warm(&target, Some(warm), |_, _| {}, |_, _, _| {}, false)
            .unwrap()
            .response;
        assert_eq!(r.steps.len(), cold.steps.len());
        for (a, b) in r.steps.iter().zip(&cold.steps) {
            assert!(
                a.warm_start,
                "level {} bar did not start warm",
                a.pressure_bar
            );
            let tip = (a.tip_uz_mm - b.tip_uz_mm).hypot(a.tip_uy_mm - b.tip_uy_mm);
            let size = b.tip_uz_mm.hypot(b.tip_uy_mm).max(1.0);
            assert!(
                tip <= 1e-6 * size,
                "{} bar: tip {tip:.3e} mm from the cold ramp's",
                a.pressure_bar
            );
            if let (Some(fa), Some(fb)) = (a.force_n, b.force_n) {
                assert!(
                    (fa - fb).abs() <= 1e-6,
                    "{} bar: force {fa} N against {fb} N",
                    a.pressure_bar
                );
            }
        }
        assert!(
            3 * iterations(&r) < iterations(&cold),
            "warm {} iterations against cold {}",
            iterations(&r),
            iterations(&cold)
        );
    }
}

#[test]
fn a_warm_bending_ramp_gives_the_cold_ramps_answers() {
    same_answers_fewer_iterations(Mode::Bending, vec![0.0, 1.0]);
}

#[test]
fn a_warm_blocked_force_ramp_gives_the_cold_ramps_answers() {
    same_answers_fewer_iterations(Mode::Force, vec![0.0, 1.0]);
}

/// A warm start from another design's mesh is not used: the ramp takes the load path and
/// gives the cold answer exactly.
#[test]
fn states_of_another_mesh_are_not_used() {
    let base = ogden002();
    let other = sensitivities_with_fields(
        &case(9, base, Mode::Bending, vec![0.0]),
        &[],
        None,
        |_, _| {},
        |_, _, _| {},
    )
    .unwrap();
    let target = case(11, base, Mode::Bending, vec![0.0]);
    let cold = run_warm(&target, None, |_, _| {}, |_, _, _| {}, false)
        .unwrap()
        .response;
    let warm = WarmStart::new(other.states);
    let r = run_warm(&target, Some(&warm), |_, _| {}, |_, _, _| {}, false)
        .unwrap()
        .response;
    assert!(!r.steps[0].warm_start);
    assert_eq!(r.steps[0].tip_uy_mm, cold.steps[0].tip_uy_mm);
    assert_eq!(
        r.steps[0].newton_iterations,
        cold.steps[0].newton_iterations
    );
}

#[test]
fn a_first_order_start_checks_its_parameter_steps() {
    let fields = FieldSensitivities {
        parameters: vec!["mu1".into()],
        du: vec![vec![vec![1.0; 3]]],
    };
    let err = WarmStart::moved(Vec::new(), &fields, &[0.1]).unwrap_err();
    assert!(matches!(err, WarmStartError::Mismatch { states: 0, .. }));
    let err = WarmStart::moved(Vec::new(), &FieldSensitivities::default(), &[0.1]).unwrap_err();
    assert!(matches!(err, WarmStartError::Mismatch { deltas: 1, .. }));
}

mod order {
    use super::*;
    use surrogate::fe::campaign::{Campaign, CampaignCase, CampaignError, WarmOrder};

    fn campaign(points: &[(usize, f64)], warm: WarmOrder) -> Campaign {
        Campaign {
            cases: points
                .iter()
                .map(|&(n, x)| CampaignCase {
                    case: case(n, ogden002(), Mode::Bending, vec![0.0]),
                    point: vec![x],
                })
                .collect(),
            parameters: vec![Parameter::Material(OgdenParameter::Mu1)],
            scales: vec![1.0],
            warm,
        }
    }

    /// Every case runs after its parent, a parent is of the same design, and on a line the
    /// tree links each point to a neighbour on the line (the minimum spanning tree of points on
    /// a line is the path through them in order).
    #[test]
    fn each_case_starts_from_a_nearest_neighbour_of_its_own_model_run_before_it() {
        let pts = [
            (9, 0.0),
            (11, 5.0),
            (9, 3.0),
            (9, 1.0),
            (11, 0.0),
            (9, 10.0),
            (11, 2.0),
        ];
        let c = campaign(&pts, WarmOrder::Zeroth);
        let order = c.order();
        assert_eq!(order.len(), pts.len());
        let mut seen = vec![false; pts.len()];
        let mut roots = 0;
        for l in &order {
            match l.parent {
                None => roots += 1,
                Some(p) => {
                    assert!(seen[p], "case {} before its parent {p}", l.case);
                    assert_eq!(pts[p].0, pts[l.case].0, "a parent of another design");
                    // the parent is the nearest on the line among those of its design
                    // on the side towards the root, i.e. no same-design point lies between
                    let (a, b) = (pts[p].1.min(pts[l.case].1), pts[p].1.max(pts[l.case].1));
                    assert!(!pts.iter().any(|q| q.0 == pts[p].0 && q.1 > a && q.1 < b));
                }
            }
            seen[l.case] = true;
        }
        assert_eq!(roots, 2, "one root per design");
        // the root is the case nearest its group's centroid: (0+3+1+10)/4 = 3.5 → x = 3
        assert!(order.iter().any(|l| l.case == 2 && l.parent.is_none()));
        let cold = campaign(&pts, WarmOrder::Cold).order();
        assert!(cold.iter().all(|l| l.parent.is_none()));
    }

    #[test]
    fn a_bad_campaign_is_refused_naming_the_field() {
        let mut c = campaign(&[(9, 0.0), (9, 1.0)], WarmOrder::Zeroth);
        c.scales = vec![0.0];
        assert!(
            matches!(c.validate(), Err(CampaignError::Value { what, .. }) if what == "scales[0]")
        );
        let mut c = campaign(&[(9, 0.0), (9, 1.0)], WarmOrder::Zeroth);
        c.cases[1].point = vec![1.0, 2.0];
        assert!(
            matches!(c.validate(), Err(CampaignError::Dimensions { what, got: 2, .. }) if what == "cases[1].point")
        );
        c.cases[1].point = vec![f64::NAN];
        assert!(c.run(|_, _, _| {}).is_err());
    }
}
