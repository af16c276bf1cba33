//! Box extension (`surrogate::calibrate::extend`) on an analytic stand-in for the FE that
//! determines all four material coordinates: a surrogate trained on a narrow box, recordings
//! of a material beyond it, the box extended until the optimum is inside (or at the physical
//! limits), resumed after an interruption, planned reproducibly, refused on bad input.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use surrogate::calibrate::extend::{
    extend_box, extension_case_id, extension_plan, high_fidelity_cases, BoxExtension,
    ExtendSettings, ExtendStop, MaterialBox, PhysicalLimits, FORMAT,
};
use surrogate::calibrate::refine::{HighFidelity, TrainingSet};
use surrogate::calibrate::summary::summary_markdown_extended;
use surrogate::calibrate::{MaterialCoords, OgdenSet, ParamSpace, Recordings};
use surrogate::rom::{train, Surrogate};
use surrogate::snapshots::plan::{Plan, PlanSettings, PlannedCase, Ranges};
use surrogate::snapshots::run::{AnalyticRunner, CaseOutcome, CaseRunner};

use crate::analytic::{
    quick_calibration, quick_training, recordings, run_plan, shipped_plan, trained_model,
};

fn scratch(name: &str) -> std::path::PathBuf {
    crate::analytic::scratch("extend", name)
}

/// The "FE": the analytic runner, its displacements scaled by a factor in which each
/// material coordinate has its own signature over the designs (`s` with the pressure, `α₁`
/// with `T`, `α₂` with `N`), so the 27 recorded configurations determine all four (the
/// analytic runner alone sees `α₁` and `α₂` only through one combination with `μ0`).
fn fe(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    let mut o = AnalyticRunner::default().run(case, settings);
    let c = case.material.coords();
    let (n, t) = (case.n_bellows as f64, case.wall_thickness_mm);
    for (s, &p) in o.steps.iter_mut().zip(&settings.pressures_bar) {
        let f = (1.0 + 0.4 * (c.share - 0.5) * (p - 2.0) / 2.0)
            * (1.0 + 0.1 * (c.alpha1 - 3.0) * (t - 2.0) / 0.4)
            * (1.0 + 0.3 * (c.alpha2 + 1.0) * (n - 11.0) / 2.0);
        s.tip_uz_mm *= f;
        s.tip_uy_mm *= f;
        for m in &mut s.markers {
            m[0] *= f;
            m[1] *= f;
        }
        s.angle_deg = (-s.tip_uy_mm).atan2(92.0 - s.tip_uz_mm).to_degrees();
    }
    o
}

/// The true material: μ0 = 5 MPa, beyond the training box's 2–4 MPa.
fn truth() -> OgdenSet {
    OgdenSet::from_coords(MaterialCoords {
        mu0_mpa: 5.0,
        share: 0.5,
        alpha1: 3.0,
        alpha2: -1.0,
    })
    .unwrap()
}

/// 30 cases of the recorded N over a narrow material box (μ0 2–4 MPa, s 0.3–0.7, α₁ 2–4,
/// α₂ −1.5 to −0.5), the shipped coarse plan's FE settings.
fn narrow_plan() -> Plan {
    let shipped = shipped_plan();
    let ranges = Ranges {
        n_bellows: vec![9, 11, 13],
        mu0_mpa: [2.0, 4.0],
        term1_share: [0.3, 0.7],
        alpha1: [2.0, 4.0],
        alpha2: [-1.5, -0.5],
        ..shipped.ranges
    };
    Plan::generate(30, 11, ranges, shipped.settings).unwrap()
}

/// The surrogate of [`narrow_plan`] (run by `runner`), its training set and the recordings of
/// [`fe`] at [`truth`].
fn narrow_model(dir: &Path, runner: &dyn CaseRunner) -> (Surrogate, TrainingSet, Recordings) {
    let plan = narrow_plan();
    let rec = recordings(&fe, &plan.settings, &truth());
    let (model, training) = trained_model(plan, dir, runner, &quick_training());
    (model, training, rec)
}

fn settings(max_rounds: usize) -> ExtendSettings {
    ExtendSettings {
        max_rounds,
        cases_per_round: 18,
        seed: 7,
        train: quick_training(),
        calibration: quick_calibration(),
        ..ExtendSettings::default()
    }
}

/// The model's training box.
fn model_box(m: &Surrogate) -> MaterialBox {
    MaterialBox::of_domain(&ParamSpace::training_domain(m).unwrap()).unwrap()
}

#[test]
fn an_optimum_beyond_the_box_is_brought_inside_and_matches_the_truth() {
    let dir = scratch("inside");
    let (m0, training, rec) = narrow_model(&dir, &fe);
    let e = extend_box(
        &m0,
        &training,
        &rec,
        &settings(3),
        &fe,
        &dir.join("extend"),
        &|_| {},
    )
    .unwrap();
    let md = e.summary_markdown();
    println!("{md}");
    assert!(
        e.start
            .active_bounds
            .iter()
            .any(|b| b.starts_with("mu0_mpa at its upper bound")),
        "{md}"
    );
    assert_eq!(e.stop, ExtendStop::Inside, "{md}");
    assert!((1..=3).contains(&e.rounds.len()), "{md}");
    let first = &e.rounds[0];
    let mu0 = first
        .pressed
        .iter()
        .find(|p| p.coordinate == "mu0_mpa")
        .unwrap();
    let b0 = model_box(&m0);
    assert_eq!(first.box_before, b0);
    // half the range of ln μ0 beyond its end
    let hi = (b0.mu0_mpa[1].ln() + 0.5 * b0.width(0)).exp();
    assert!((mu0.moved_to.unwrap() - hi).abs() < 1e-12 * hi);
    for (k, r) in e.rounds.iter().enumerate() {
        assert_eq!(r.cases, 18);
        assert!(r.failed.is_empty());
        assert_eq!(r.refit.model_cases, 30 + 18 * (k + 1));
        assert!(r.model.is_file());
        let cases = std::fs::read_dir(r.fe_dir.join("cases")).unwrap().count();
        assert_eq!(cases, 18);
        assert!(r
            .fe_dir
            .join("cases")
            .join(format!("case_{:06}.csv", extension_case_id(k + 1, 17)))
            .is_file());
    }
    // the optimum through the last surrogate: the true μ0 within 3 %, and every coordinate
    // inside its profile interval
    let last = e.final_optimum();
    assert!(last.active_bounds.is_empty());
    assert!(
        (last.coords.mu0_mpa - 5.0).abs() < 0.15,
        "{:?}",
        last.coords
    );
    let t = truth().coords().as_array();
    for (p, v) in e
        .last
        .as_ref()
        .unwrap()
        .identifiability
        .profiles
        .iter()
        .zip(t)
    {
        assert!(
            p.interval[0] <= v && v <= p.interval[1],
            "{} = {v} outside [{}, {}]",
            p.name,
            p.interval[0],
            p.interval[1]
        );
    }
    // the summary of the last calibration carries the extension's section
    let summary = summary_markdown_extended(e.last.as_ref().unwrap(), None, Some(&e));
    assert!(summary.contains("No bound of the training domain is active"));
    assert!(summary.contains("## Box extension"));
    assert!(summary.contains("Stopped: the optimum lies inside the box"));
    // the report reads back, and one of another version is refused by name
    let text = serde_json::to_string(&e).unwrap();
    let back = BoxExtension::from_json(&text).unwrap();
    assert_eq!(back.rounds, e.rounds);
    assert_eq!(back.format, FORMAT);
    assert!(back.last.is_none());
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["version"] = 2.into();
    let err = BoxExtension::from_json(&v.to_string())
        .unwrap_err()
        .to_string();
    assert!(err.contains("version = 2"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_interrupted_extension_resumes_from_its_round_directory() {
    let dir = scratch("resume");
    let (m0, training, rec) = narrow_model(&dir, &fe);
    let out = dir.join("extend");
    let first = extend_box(&m0, &training, &rec, &settings(1), &fe, &out, &|_| {}).unwrap();
    let r1 = &first.rounds[0];
    assert_eq!(r1.cases_run, 18);
    // an interruption: five cases never finished
    for j in [0, 3, 8, 12, 17] {
        let f = r1
            .fe_dir
            .join("cases")
            .join(format!("case_{:06}.csv", extension_case_id(1, j)));
        std::fs::remove_file(f).unwrap();
    }
    let again = extend_box(&m0, &training, &rec, &settings(1), &fe, &out, &|_| {}).unwrap();
    let r = &again.rounds[0];
    assert_eq!(r.plan_hash, r1.plan_hash);
    assert_eq!((r.cases_run, r.cases_read_back), (5, 13));
    assert_eq!(r.refit.set, r1.refit.set);
    // and a complete round is only read back
    let third = extend_box(&m0, &training, &rec, &settings(1), &fe, &out, &|_| {}).unwrap();
    assert_eq!(third.rounds[0].cases_run, 0);
    assert!(third.summary_markdown().contains("read back"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_optimum_beyond_a_physical_limit_stops_there_and_says_so() {
    let dir = scratch("limit");
    let (m0, training, rec) = narrow_model(&dir, &fe);
    let b0 = model_box(&m0);
    // a material known to lie in the trained box but for μ0, which may reach 4.5 MPa
    let limits = PhysicalLimits {
        mu0_mpa: [b0.mu0_mpa[0], 4.5],
        term1_share: b0.term1_share,
        alpha1: b0.alpha1,
        alpha2: b0.alpha2,
    };
    let s = ExtendSettings {
        limits,
        ..settings(3)
    };
    let e = extend_box(&m0, &training, &rec, &s, &fe, &dir.join("extend"), &|_| {}).unwrap();
    let md = e.summary_markdown();
    println!("{md}");
    assert_eq!(e.rounds.len(), 1, "{md}");
    assert_eq!(e.rounds[0].pressed[0].moved_to, Some(4.5), "{md}");
    assert_eq!(e.final_box.mu0_mpa[1], 4.5);
    let ExtendStop::PhysicalLimit { bounds, .. } = &e.stop else {
        panic!("{md}");
    };
    assert!(
        bounds
            .iter()
            .any(|b| b.starts_with("mu0_mpa upper") && b.ends_with("(its physical limit 4.500)")),
        "{bounds:?}"
    );
    let summary = summary_markdown_extended(e.last.as_ref().unwrap(), None, Some(&e));
    assert!(
        summary.contains("**The physical limits truncate this optimum**"),
        "{summary}"
    );
    // limits at the trained box: no round, no FE
    let none = ExtendSettings {
        limits: PhysicalLimits {
            mu0_mpa: b0.mu0_mpa,
            ..limits
        },
        ..settings(3)
    };
    let e = extend_box(&m0, &training, &rec, &none, &fe, &dir.join("none"), &|_| {}).unwrap();
    assert!(e.rounds.is_empty());
    assert!(matches!(e.stop, ExtendStop::PhysicalLimit { .. }));
    assert!(!dir.join("none").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_round_plan_is_reproducible_and_fills_the_slabs() {
    let training = narrow_plan();
    let old = MaterialBox {
        mu0_mpa: [2.0, 4.0],
        term1_share: [0.3, 0.7],
        alpha1: [2.0, 4.0],
        alpha2: [-1.5, -0.5],
    };
    let new = MaterialBox {
        mu0_mpa: [2.0, 8.0],
        alpha1: [1.0, 4.0],
        ..old
    };
    let plan = |seed| extension_plan(&training, &[9, 11, 13], &old, &new, 2, 18, seed).unwrap();
    let (a, b, c) = (plan(7), plan(7), plan(8));
    assert_eq!(a.hash(), b.hash());
    assert_ne!(a.hash(), c.hash());
    assert_eq!(a.settings, training.settings);
    assert_eq!(a.ranges.mu0_mpa, new.mu0_mpa);
    assert_eq!(a.cases.len(), 18);
    let inside = |v: f64, r: [f64; 2]| r[0] - 1e-12 <= v && v <= r[1] + 1e-12;
    for (j, case) in a.cases.iter().enumerate() {
        assert_eq!(case.id, 25_000 + j);
        let coords = case.material.coords().as_array();
        let in_new = (0..4).all(|i| inside(coords[i], new.range(i)));
        let in_old = (0..4).all(|i| inside(coords[i], old.range(i)));
        assert!(in_new && !in_old, "case {}: {coords:?}", case.id);
    }
    // both slabs get every N (3 each first), and every N gets its share
    for n in [9, 11, 13] {
        let k = a.cases.iter().filter(|c| c.n_bellows == n).count();
        assert!(k >= 5, "N = {n}: {k} cases");
    }
    let beyond_mu0 = a.cases.iter().filter(|c| {
        c.material.mu1_mpa * c.material.alpha1 + c.material.mu2_mpa * c.material.alpha2 > 8.0
    });
    assert!(beyond_mu0.count() >= 3);
    // a box that is not larger has no slab
    let err = extension_plan(&training, &[9, 11, 13], &old, &old, 1, 18, 7).unwrap_err();
    assert!(
        err.to_string().contains("a box larger than the last one"),
        "{err}"
    );
}

/// Counts the cases it is asked to run.
struct Counting(AtomicUsize);

impl CaseRunner for Counting {
    fn run(&self, case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
        self.0.fetch_add(1, Ordering::SeqCst);
        fe(case, settings)
    }
}

#[test]
fn bad_settings_and_a_training_set_not_the_models_are_refused_before_any_fe() {
    let dir = scratch("bad");
    let (m0, training, rec) = narrow_model(&dir, &fe);
    let runner = Counting(AtomicUsize::new(0));
    let out = dir.join("extend");
    let refused = |s: &ExtendSettings, t: &TrainingSet| {
        extend_box(&m0, t, &rec, s, &runner, &out, &|_| {})
            .unwrap_err()
            .to_string()
    };
    let with = |f: &dyn Fn(&mut ExtendSettings)| {
        let mut s = settings(2);
        f(&mut s);
        refused(&s, &training)
    };
    let e = with(&|s| s.step = 0.0);
    assert!(
        e.starts_with("step = 0: expected a finite fraction > 0"),
        "{e}"
    );
    assert!(with(&|s| s.step = f64::NAN).starts_with("step = NaN"));
    let e = with(&|s| s.cases_per_round = 5);
    assert!(
        e.contains(
            "cases_per_round = 5: expected 6 ..= 5000 (at least 2 per trained value of N: 3"
        ),
        "{e}"
    );
    assert!(with(&|s| s.max_rounds = 0).starts_with("max_rounds = 0"));
    assert!(with(&|s| s.limits.alpha1 = [0.0, 20.0]).contains("physical limits of alpha1"));
    // 20 of the 30 training cases
    let ids: Vec<String> = {
        let mut v: Vec<String> = training
            .snapshots
            .rows
            .iter()
            .map(|r| r.case_id.clone())
            .collect();
        v.dedup();
        v
    };
    let mut fewer = training.clone();
    fewer
        .snapshots
        .rows
        .retain(|r| ids[..20].contains(&r.case_id));
    let e = refused(&settings(2), &fewer);
    assert!(
        e.contains("(20 cases): expected the set the model was trained on (30 cases"),
        "{e}"
    );
    // a training case with an extension id
    let mut clash = training.clone();
    for r in &mut clash.snapshots.rows {
        if r.case_id == ids[0] {
            r.case_id = format!("case_{:06}", extension_case_id(2, 3));
        }
    }
    let e = refused(&settings(2), &clash);
    assert!(e.contains("training set case id = case_025003"), "{e}");
    // a high fidelity the model was not corrected by
    let mut two = training.clone();
    two.high = Some(HighFidelity {
        snapshots: training.snapshots.clone(),
        plan: training.plan.clone(),
        pressure_warp: false,
    });
    assert!(refused(&settings(2), &two).contains("no multi-fidelity correction"));
    assert_eq!(runner.0.load(Ordering::SeqCst), 0);
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// [`fe`], failing half-way in every extension case whose id ends in 5 (and, with `all`,
/// failing at once in every extension case).
fn failing(all: bool) -> impl Fn(&PlannedCase, &PlanSettings) -> CaseOutcome + Sync {
    move |case, settings| {
        if case.id < 10_000 {
            return fe(case, settings);
        }
        if all {
            return CaseOutcome::failed("stand-in: no convergence at the first step");
        }
        let mut o = fe(case, settings);
        if case.id % 10 == 5 {
            o.steps.truncate(settings.pressures_bar.len() / 2);
            o.error = Some("stand-in: no convergence half-way".into());
        }
        o
    }
}

#[test]
fn failed_cases_are_reported_and_left_out_and_a_round_of_failures_is_an_error() {
    let dir = scratch("failed");
    let (m0, training, rec) = narrow_model(&dir, &fe);
    let e = extend_box(
        &m0,
        &training,
        &rec,
        &settings(1),
        &failing(false),
        &dir.join("extend"),
        &|_| {},
    )
    .unwrap();
    let r = &e.rounds[0];
    let ids: Vec<usize> = r.failed.iter().map(|f| f.id).collect();
    assert_eq!(ids, vec![15_005, 15_015]);
    assert!(r
        .failed
        .iter()
        .all(|f| f.mesh == "coarse" && f.error.contains("half-way")));
    assert_eq!(r.refit.model_cases, 30 + 16);
    let err = extend_box(
        &m0,
        &training,
        &rec,
        &settings(1),
        &failing(true),
        &dir.join("all"),
        &|_| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("round 1: all 18 cases failed on the coarse mesh"),
        "{err}"
    );
    assert!(err.contains("no convergence at the first step"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The "FE" of both fidelities: [`fe`] on the low-fidelity mesh, 4 % larger displacements on
/// the high-fidelity one.
fn two_meshes(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    let mut o = fe(case, settings);
    if settings.mesh.level.name() == "standard" {
        for s in &mut o.steps {
            s.tip_uz_mm *= 1.04;
            s.tip_uy_mm *= 1.04;
        }
    }
    o
}

#[test]
fn a_multi_fidelity_model_is_extended_on_both_meshes() {
    let dir = scratch("two_meshes");
    let low_plan = narrow_plan();
    let standard =
        surrogate::fe::mesh::MeshOptions::level(surrogate::fe::mesh::MeshLevel::Standard);
    let high_plan = low_plan.subset(6, standard).unwrap();
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
    let rec = recordings(&two_meshes, &high_plan.settings, &truth());
    let training = TrainingSet {
        snapshots: sets[0].clone(),
        plan: low_plan,
        high: Some(HighFidelity {
            snapshots: sets[1].clone(),
            plan: high_plan,
            pressure_warp: false,
        }),
    };
    let out = dir.join("extend");
    let e = extend_box(
        &m0,
        &training,
        &rec,
        &settings(1),
        &two_meshes,
        &out,
        &|_| {},
    )
    .unwrap();
    println!("{}", e.summary_markdown());
    let r = &e.rounds[0];
    let high = high_fidelity_cases(18, 30, 6, 3);
    assert_eq!(high, 4);
    assert_eq!(r.high_fidelity_cases, high);
    assert_eq!(r.cases_run, 18 + high);
    let count = |sub: &str| {
        std::fs::read_dir(out.join(sub).join("cases"))
            .unwrap()
            .count()
    };
    assert_eq!((count("extend_1"), count("extend_1_high")), (18, high));
    let m1 = Surrogate::load(&r.model).unwrap();
    let c = m1.training.correction.expect("a corrected model");
    assert_eq!(c.matched_cases, 6 + high);
    // without its high-fidelity set the corrected model is refused
    let one = TrainingSet {
        high: None,
        ..training
    };
    let err = extend_box(
        &m0,
        &one,
        &rec,
        &settings(1),
        &two_meshes,
        &dir.join("one"),
        &|_| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("retraining without it would drop the correction"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The stand-in FE of [`fe`] with `α₂`'s signature shrunk to 1 % per unit: the recordings pull `α₂`
/// to a bound without determining it (its profile is flat over the box).
fn fe_alpha2_trace(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    let mut o = fe(case, settings);
    let c = case.material.coords();
    let base = fe(
        &PlannedCase {
            material: OgdenSet {
                alpha2: -1.0,
                mu2_mpa: OgdenSet::from_coords(MaterialCoords { alpha2: -1.0, ..c })
                    .unwrap()
                    .mu2_mpa,
                ..case.material
            },
            ..case.clone()
        },
        settings,
    );
    // the steps of the case at α₂ = −1, moved by a trace of α₂
    for (s, b) in o.steps.iter_mut().zip(&base.steps) {
        let f = 1.0 + 1e-2 * (c.alpha2 + 1.0);
        s.tip_uz_mm = b.tip_uz_mm * f;
        s.tip_uy_mm = b.tip_uy_mm * f;
        for (m, mb) in s.markers.iter_mut().zip(&b.markers) {
            *m = [mb[0] * f, mb[1] * f];
        }
        s.angle_deg = (-s.tip_uy_mm).atan2(92.0 - s.tip_uz_mm).to_degrees();
    }
    o
}

#[test]
fn a_bound_of_a_coordinate_the_recordings_do_not_determine_is_not_extended() {
    let dir = scratch("undetermined");
    let plan = narrow_plan();
    // a material inside the trained box, α₂ pulled to its upper bound by a trace
    let inside = OgdenSet::from_coords(MaterialCoords {
        mu0_mpa: 3.0,
        share: 0.5,
        alpha1: 3.0,
        alpha2: -0.1,
    })
    .unwrap();
    let rec = recordings(&fe_alpha2_trace, &plan.settings, &inside);
    let (m0, training) = trained_model(plan, &dir, &fe_alpha2_trace, &quick_training());
    let e = extend_box(
        &m0,
        &training,
        &rec,
        &settings(2),
        &fe_alpha2_trace,
        &dir.join("extend"),
        &|_| {},
    )
    .unwrap();
    let md = e.summary_markdown();
    println!("{md}");
    assert!(e.rounds.is_empty(), "{md}");
    let ExtendStop::Undetermined { bounds } = &e.stop else {
        panic!("{md}");
    };
    assert!(bounds.iter().all(|b| b.contains("alpha2")), "{bounds:?}");
    assert!(!dir.join("extend").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The surrogates a box extension retrains are built and trained like the one it extends: the
/// plan's fixed effects (the force rig's plate) stay stated in them, so that FE runs compared
/// with them use the same actuator, and a sparse GP with `N` ordinal stays one.
#[test]
fn retrained_surrogates_keep_how_the_cases_were_built_and_trained() {
    let dir = scratch("built_with");
    let mut plan = narrow_plan();
    plan.settings.effects = plan
        .settings
        .effects
        .clone()
        .with(
            surrogate::fe::effects::Effect::from_name("plate_offset").unwrap(),
            -2.0,
        )
        .unwrap();
    let rec = recordings(&fe, &plan.settings, &truth());
    let mut cfg = quick_training();
    cfg.ordinal_n = true;
    cfg.gp.inducing = Some(24);
    let (mut m0, training) = trained_model(plan, &dir, &fe, &cfg);
    let cases = training.snapshots.clone().into_cases().unwrap();
    assert!(m0.state_plan_domain(&training.plan, &cases, "narrow"));
    let built = m0
        .training
        .built_with
        .clone()
        .expect("the plan fixes the plate");
    let s = ExtendSettings {
        train: quick_training().like(&m0.training),
        ..settings(1)
    };
    let e = extend_box(&m0, &training, &rec, &s, &fe, &dir.join("extend"), &|_| {}).unwrap();
    let r = &e.rounds[0];
    let m1 = Surrogate::load(&r.model).unwrap();
    assert_eq!(m1.training.built_with.as_ref(), Some(&built));
    assert_eq!(m1.training.gp_inducing, Some(24));
    assert!(m1.training.ordinal_n());
    assert_eq!(m1.training.n_cases, 30 + 18);
    let _ = std::fs::remove_dir_all(&dir);
}
