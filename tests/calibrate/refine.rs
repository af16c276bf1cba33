//! Adaptive refinement (`surrogate::calibrate::refine`): the rounds' mechanics on the analytic
//! stand-in for the FE (a surrogate trained on few cases, refined until it agrees with the
//! "FE" at the calibrated set), and the committed FE round of the coarse model reproduced by
//! the code that plans it.

use surrogate::calibrate::refine::{
    data_space_shift, refine, round_plan, HighFidelity, RefineSettings, RefineStop, Refinement,
    TrainingSet,
};
use surrogate::calibrate::{OgdenSet, Recordings, Selection};
use surrogate::rom::{train, Surrogate, TrainConfig};
use surrogate::snapshots::plan::{Plan, PlanSettings, PlannedCase};
use surrogate::snapshots::run::{AnalyticRunner, CaseOutcome, CaseRunner};

use crate::analytic::{
    quick_calibration, quick_training, recordings, run_plan, shipped_plan, trained_model,
};

fn scratch(name: &str) -> std::path::PathBuf {
    crate::analytic::scratch("refine", name)
}

/// The refinement's settings in these tests.
fn settings(max_rounds: usize, train: TrainConfig, data_tolerance: f64) -> RefineSettings {
    RefineSettings {
        max_rounds,
        train,
        calibration: quick_calibration(),
        threads: None,
        data_tolerance,
    }
}

const TRUTH: OgdenSet = OgdenSet {
    mu1_mpa: 5.0 / 3.0,
    alpha1: 3.0,
    mu2_mpa: -5.0,
    alpha2: -1.0,
};

/// The "FE" of the refinement: the analytic runner with the displacements 4 % larger than in
/// the training cases, as a finer model would give (the surrogate's own error bars cannot know
/// it, so the first round disagrees).
fn fe(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    let mut o = AnalyticRunner::default().run(case, settings);
    for s in &mut o.steps {
        s.tip_uz_mm *= 1.04;
        s.tip_uy_mm *= 1.04;
        for m in &mut s.markers {
            m[0] *= 1.04;
            m[1] *= 1.04;
        }
        s.angle_deg = (-s.tip_uy_mm).atan2(92.0 - s.tip_uz_mm).to_degrees();
    }
    o
}

/// The case of design `(n, t)` at `set`.
fn case_at(n: usize, t: f64, set: &OgdenSet) -> PlannedCase {
    surrogate::calibrate::refine::case_at(0, n, t, set)
}

/// A surrogate trained on 30 analytic cases of the shipped coarse plan's ranges, its training
/// set, and noisy recordings of the "FE" at `TRUTH`.
fn analytic_model(dir: &std::path::Path) -> (Surrogate, TrainingSet, Recordings, TrainConfig) {
    let shipped = shipped_plan();
    let plan = Plan::generate(30, 11, shipped.ranges.clone(), shipped.settings.clone()).unwrap();
    let cfg = quick_training();
    let rec = recordings(&fe, &plan.settings, &TRUTH);
    let (m0, training) = trained_model(plan, dir, &AnalyticRunner::default(), &cfg);
    (m0, training, rec, cfg)
}

/// The refinement of [`analytic_model`]'s surrogate against [`fe`] in `dir/refine`, up to 4
/// rounds, and what it was made from.
fn analytic_refinement(
    dir: &std::path::Path,
    data_tolerance: f64,
) -> (
    Refinement,
    Surrogate,
    TrainingSet,
    Recordings,
    RefineSettings,
) {
    let (m0, training, rec, cfg) = analytic_model(dir);
    let settings = settings(4, cfg, data_tolerance);
    let r = refine(
        &m0,
        &training,
        &rec,
        &settings,
        &fe,
        &dir.join("refine"),
        &|_| {},
    )
    .unwrap();
    println!("{}", r.summary_markdown());
    (r, m0, training, rec, settings)
}

#[test]
fn refinement_adds_the_fe_at_the_optimum_until_the_surrogate_agrees() {
    let dir = scratch("analytic");
    // this test is about agreement: the data-space stop is tested below
    let (r, m0, training, rec, settings) = analytic_refinement(&dir, 0.0);
    let first = &r.rounds[0];
    assert!(
        first.verification.disagreements > 0,
        "the surrogate of the training cases disagrees with the finer \"FE\" at its optimum"
    );
    assert_ne!(r.stop, RefineStop::MaxRounds, "{}", r.summary_markdown());
    for (k, round) in r.rounds.iter().enumerate() {
        assert_eq!(round.model_cases, 30 + 9 * k, "round {}", round.round);
        assert_eq!(round.verification.rows.len(), 27);
        assert_eq!(round.verification.incomplete, 0);
    }
    // the round's FE values are the runner's at the round's set
    let row = &first.verification.rows[0];
    let case = case_at(
        row.config.n_bellows as usize,
        row.config.wall_thickness_mm,
        &first.set,
    );
    let o = fe(&case, &training.plan.settings);
    let k = training
        .plan
        .settings
        .pressures_bar
        .iter()
        .position(|&p| p == row.config.pressure_bar)
        .unwrap();
    assert!((o.steps[k].tip_uz_mm - row.fe.uz_sim_mm).abs() < 1e-9);
    assert!((o.steps[k].force_n - row.fe.force_sim_n).abs() < 1e-9);
    // the surrogate ends closer to the FE than it started
    let last = r.final_verification();
    assert!(
        last.max_abs_sur_fe[0] < 0.5 * first.verification.max_abs_sur_fe[0]
            && last.max_abs_sur_fe[1] < 0.5 * first.verification.max_abs_sur_fe[1],
        "{}",
        r.summary_markdown()
    );
    // a rerun reads every round back (no case is run again) and reports the same
    let again = refine(
        &m0,
        &training,
        &rec,
        &settings,
        &fe,
        &dir.join("refine"),
        &|_| {},
    )
    .unwrap();
    assert!(again.rounds.iter().all(|x| x.fe_cases_run == 0));
    assert_eq!(again.final_round().set, r.final_round().set);
    // the report reads back from its file, and one without rounds is refused at the door
    let text = serde_json::to_string(&r).unwrap();
    let back: Refinement = serde_json::from_str(&text).unwrap();
    assert_eq!(back.final_round().set, r.final_round().set);
    let mut empty: serde_json::Value = serde_json::from_str(&text).unwrap();
    empty["rounds"] = serde_json::json!([]);
    let err = serde_json::from_value::<Refinement>(empty)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("refinement rounds = []: expected at least one round"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The analytic "FE" sees the material only through μ0 = ½Σμᵢαᵢ and the exponents: the
/// split of μ0 between the two terms is a direction the recordings cannot determine. Two sets
/// along it are the same answer in data space; a set with another μ0 is not.
#[test]
fn sets_along_an_undetermined_direction_are_the_same_in_data_space() {
    let dir = scratch("data_space");
    let (r, m0, training, rec, settings) = analytic_refinement(&dir, 1.0);
    let sel = Selection::default();
    // TRUTH: μ1α1 = 5, μ2α2 = 5 (μ0 = 5 MPa); the split moved to 6 + 4, μ0 and the α kept
    let split = OgdenSet {
        mu1_mpa: 2.0,
        alpha1: 3.0,
        mu2_mpa: -4.0,
        alpha2: -1.0,
    };
    assert!((split.mu0_mpa() - TRUTH.mu0_mpa()).abs() < 1e-12);
    let along = data_space_shift(&m0, &rec, &sel, &TRUTH, &split, 1).unwrap();
    println!("{}", along.describe());
    // tip Uz, Uy and angle at 27 configurations, force at 27
    assert_eq!(along.observations, 27 * 4);
    assert!(
        along.max_abs_z < 0.5,
        "a set along the undetermined direction moves nothing the recordings see: {}",
        along.describe()
    );
    // 20 % more μ0: the actuator bends less, by more than twice the noise somewhere
    let stiffer = OgdenSet {
        mu1_mpa: 1.2 * TRUTH.mu1_mpa,
        mu2_mpa: 1.2 * TRUTH.mu2_mpa,
        ..TRUTH
    };
    let across = data_space_shift(&m0, &rec, &sel, &TRUTH, &stiffer, 1).unwrap();
    println!("{}", across.describe());
    assert!(across.max_abs_z > 2.0, "{}", across.describe());
    assert!(across.chi2_to > across.chi2_from);
    // a set outside the training domain is refused, not extrapolated
    let outside = OgdenSet {
        mu1_mpa: 50.0,
        ..TRUTH
    };
    let err = data_space_shift(&m0, &rec, &sel, &TRUTH, &outside, 1).unwrap_err();
    assert!(err.to_string().contains("training domain"), "{err}");

    // the refinement with the data-space stop
    // the refit walks along the undetermined split after the first retraining (the parameters
    // move, OptimumUnchanged cannot fire), but nothing the recordings see moves
    assert_eq!(
        r.stop,
        RefineStop::PredictionsUnchanged,
        "{}",
        r.summary_markdown()
    );
    assert_eq!(r.shifts.len(), r.rounds.len());
    for (k, sh) in r.shifts.iter().enumerate() {
        assert_eq!(sh.round, k + 1);
        assert_eq!(sh.from, r.rounds[k].set);
    }
    let last = r.shifts.last().unwrap();
    assert!(last.max_abs_z <= 1.0);
    assert_ne!(last.to, last.from);
    assert_eq!(last.from, r.final_round().set);
    assert_eq!(r.final_verification().rows.len(), 27);
    assert!(r.final_check.is_some());
    // a tolerance that is not a number of standard deviations is refused
    let bad = RefineSettings {
        data_tolerance: f64::NAN,
        ..settings
    };
    let err = refine(&m0, &training, &rec, &bad, &fe, &dir.join("bad"), &|_| {}).unwrap_err();
    assert!(err.to_string().contains("data_tolerance"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_shipped_multi_fidelity_model_names_both_of_its_sets() {
    let m =
        surrogate::rom::Surrogate::load(std::path::Path::new("models/as_modelled/actuator.json"))
            .unwrap();
    let t = TrainingSet::of_model(&m, std::path::Path::new(".")).unwrap();
    assert_eq!(t.snapshots.source, "./training_data/snapshots_coarse.csv");
    assert_eq!(t.plan.settings.mesh.level.name(), "coarse");
    let h = t
        .high
        .expect("the shipped model is corrected by the standard set");
    assert_eq!(h.snapshots.source, "./training_data/snapshots_standard.csv");
    assert_eq!(h.plan.settings.mesh.level.name(), "standard");
    assert!(h.pressure_warp);
}

/// The "FE" of both fidelities: the analytic runner on the low-fidelity mesh, 4 % larger
/// displacements on the high-fidelity one.
fn two_meshes(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    if settings.mesh.level.name() == "standard" {
        fe(case, settings)
    } else {
        AnalyticRunner::default().run(case, settings)
    }
}

#[test]
fn a_multi_fidelity_model_is_refined_on_both_meshes() {
    let dir = scratch("two_meshes");
    let shipped = shipped_plan();
    let low_plan =
        Plan::generate(30, 11, shipped.ranges.clone(), shipped.settings.clone()).unwrap();
    let high_plan = low_plan
        .subset(
            6,
            surrogate::fe::mesh::MeshOptions::level(surrogate::fe::mesh::MeshLevel::Standard),
        )
        .unwrap();
    let sets = [
        run_plan(&low_plan, &dir, "low", &two_meshes),
        run_plan(&high_plan, &dir, "high", &two_meshes),
    ];
    let cfg = quick_training();
    let (corrected, info) = surrogate::rom::fidelity::correct_low_fidelity(
        &sets[0],
        &sets[1],
        &cfg,
        false,
        false,
        &|_| {},
    )
    .unwrap();
    let mut m0 = train(
        &corrected.into_cases().unwrap(),
        "two meshes",
        0,
        &cfg,
        &|_, _| {},
    )
    .unwrap()
    .surrogate;
    m0.training.correction = Some(info);
    let rec = recordings(&fe, &low_plan.settings, &TRUTH);
    let training = TrainingSet {
        snapshots: sets[0].clone(),
        plan: low_plan,
        high: Some(HighFidelity {
            snapshots: sets[1].clone(),
            plan: high_plan,
            pressure_warp: false,
        }),
    };
    let settings = settings(3, cfg, 1.0);
    let r = refine(
        &m0,
        &training,
        &rec,
        &settings,
        &two_meshes,
        &dir.join("refine"),
        &|_| {},
    )
    .unwrap();
    println!("{}", r.summary_markdown());
    // both meshes ran every round, the high-fidelity one is what the surrogate is checked against
    for round in &r.rounds {
        let k = round.round;
        for sub in [format!("round_{k}"), format!("round_{k}_low")] {
            let n = std::fs::read_dir(dir.join("refine").join(&sub).join("cases"))
                .unwrap()
                .count();
            assert_eq!(n, 9, "{sub}");
        }
        assert_eq!(round.model_cases, 30 + 9 * (k - 1));
        assert_eq!(round.fe_cases_run, 18);
        let row = &round.verification.rows[4];
        let case = case_at(
            row.config.n_bellows as usize,
            row.config.wall_thickness_mm,
            &round.set,
        );
        let o = fe(&case, &training.high.as_ref().unwrap().plan.settings);
        let p = training
            .plan
            .settings
            .pressures_bar
            .iter()
            .position(|&p| p == row.config.pressure_bar);
        assert!((o.steps[p.unwrap()].tip_uy_mm - row.fe.uy_sim_mm).abs() < 1e-9);
    }
    assert_ne!(r.stop, RefineStop::MaxRounds, "{}", r.summary_markdown());
    if r.rounds.len() > 1 {
        let m = surrogate::rom::Surrogate::load(&r.models[0]).unwrap();
        let c = m.training.correction.expect("a corrected model");
        assert_eq!(c.matched_cases, 6 + 9);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_committed_coarse_round_is_the_plan_the_code_makes() {
    let dir = std::path::Path::new("fe_reference/calibration/refine_coarse/refine/round_1");
    let committed = std::fs::read_to_string(dir.join("plan_hash")).unwrap();
    let training = Plan::read(std::path::Path::new(
        "training_data/snapshots_coarse.plan.json",
    ))
    .unwrap();
    let designs: Vec<(usize, f64)> = [9, 11, 13]
        .iter()
        .flat_map(|&n| [1.6, 2.0, 2.4].map(|t| (n, t)))
        .collect();
    let set = OgdenSet {
        mu1_mpa: 1.761,
        alpha1: 5.996,
        mu2_mpa: -0.2839,
        alpha2: -1.996,
    };
    let plan = round_plan(&training, &designs, &set, 1).unwrap();
    assert_eq!(plan.hash(), committed.trim());
}

/// A model trained on appended sets (`train --add-data`) names them all in its source:
/// its training set is read back set by set, with the first set's plan.
#[test]
fn a_model_of_appended_sets_reads_them_all_back() {
    let mut m = surrogate::rom::Surrogate::load(std::path::Path::new("models/synthetic_demo.json"))
        .unwrap();
    let ext = "fe_reference/identification/design_space/extend";
    m.training.source = format!("{ext}/extend_1.csv + {ext}/extend_2.csv");
    m.training.correction = None;
    let t = TrainingSet::of_model(&m, std::path::Path::new(".")).unwrap();
    assert_eq!(
        t.snapshots.source,
        format!("./{ext}/extend_1.csv + ./{ext}/extend_2.csv")
    );
    assert_eq!(t.snapshots.clone().into_cases().unwrap().cases.len(), 72);
    let first = surrogate::snapshots::plan::Plan::read(std::path::Path::new(&format!(
        "{ext}/extend_1.plan.json"
    )))
    .unwrap();
    assert_eq!(t.plan.hash(), first.hash());
    // a part of the source that is no file is named
    m.training.source = format!("{ext}/extend_1.csv + box extension rounds 1..2");
    let err = TrainingSet::of_model(&m, std::path::Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(err.contains("box extension rounds 1..2"), "{err}");
}
