//! The blind study's closed loop (`surrogate::diagnose::study::close_loop`) on one committed
//! twin (no FE runs: the measurements are read from the twin's committed FE ramps): the plan's
//! measurements come from the menu the twins' FE holds, each is made with noise at its σ
//! around the FE's value, the random control adds as many, and planned one at a time the
//! first reading is the one planned together first.

use std::path::Path;

use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::Recordings;
use surrogate::diagnose::approx_error::ApproximationError;
use surrogate::diagnose::study::{
    close_loop, Diagnoser, LoopSettings, StudyDirs, StudyPlan, LOOP_KINDS,
};
use surrogate::rom::Surrogate;

const STUDY: &str = "fe_reference/diagnosis/blind";

#[test]
fn a_tied_twin_gets_its_planned_measurements_made_on_its_own_fe() {
    let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json")).unwrap();
    let sens =
        SweepSensitivities::read(Path::new("data/sensitivities/ogden002_coarse.json")).unwrap();
    let mut plan = StudyPlan::read(&Path::new(STUDY).join("plan.json"))
        .unwrap()
        .only(&["wall_bias_bellows_1".to_string()])
        .unwrap();
    plan.seeds = vec![1];
    let dirs = StudyDirs::under(Path::new(STUDY));
    let approximation =
        ApproximationError::read(&Path::new(STUDY).join("approximation_error.json")).unwrap();
    let by = Diagnoser {
        model: &model,
        sens: &sens,
        mesh_reference: None,
        markers: false,
        approximation: Some(&approximation),
    };
    let shipped = Recordings::shipped().unwrap();
    // k is checked before anything runs
    let settings = |k| LoopSettings {
        k,
        sequential: false,
    };
    assert!(close_loop(&plan, &shipped, &dirs, &by, &settings(4), &|_| {}).is_err());
    let r = close_loop(&plan, &shipped, &dirs, &by, &settings(2), &|_| {}).unwrap();
    assert_eq!((r.twins.len(), r.pending.len(), r.k), (1, 0, 2));
    let t = &r.twins[0];
    assert_eq!(t.before.truth.as_deref(), Some("wall_bias_bellows"));
    // this twin's diagnosis leaves ties, so the plan proposes measurements
    assert!(!t.planned.is_empty() && t.planned.len() <= 2, "{t:?}");
    assert_eq!(t.random.len(), t.planned.len());
    for m in t.planned.iter().chain(&t.random) {
        assert!(LOOP_KINDS.contains(&m.measurement.kind), "{m:?}");
        assert!(m.truth.is_finite(), "{m:?}");
        if let Some(v) = m.recorded {
            // noise at the measurement's σ around the FE's value
            assert!((v - m.truth).abs() < 6.0 * m.measurement.sigma, "{m:?}");
            assert_ne!(v, m.truth);
        }
    }
    // the visibility of the effect is judged before any measurement, in every column
    assert_eq!(t.after_planned.tip_move_sigma, t.before.tip_move_sigma);
    assert_eq!(t.after_random.tip_move_sigma, t.before.tip_move_sigma);
    // one at a time: the first reading is the one planned together first (both planned on
    // the recordings alone); the next ones on the diagnosis with it, each a reading not made
    // before
    let seq = close_loop(
        &plan,
        &shipped,
        &dirs,
        &by,
        &LoopSettings {
            k: 2,
            sequential: true,
        },
        &|_| {},
    )
    .unwrap();
    assert!(seq.sequential);
    let s = &seq.twins[0];
    assert_eq!(s.before, t.before);
    assert_eq!(s.planned[0].measurement, t.planned[0].measurement);
    assert!(s.planned.len() <= 2 && s.random.len() == s.planned.len());
    if let [a, b] = &s.planned[..] {
        let same_reading = a.measurement.n_bellows == b.measurement.n_bellows
            && a.measurement.wall_thickness_mm == b.measurement.wall_thickness_mm
            && a.measurement.pressure_bar == b.measurement.pressure_bar
            && a.measurement.output == b.measurement.output;
        assert!(!same_reading, "{s:?}");
        assert!(b.recorded.is_some(), "{s:?}");
    }
}
