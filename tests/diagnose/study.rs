//! The blind study's plan and scoring (`surrogate::diagnose::study`): the summary counts what
//! each target asks, the standard plan is reproducible, every twin draws its own noise, and
//! a plan of an older noise-seed derivation is refused.

use std::path::Path;

use surrogate::calibrate::twin::TwinKey;
use surrogate::calibrate::{OgdenSet, ParamSpace, Recordings};
use surrogate::diagnose::study::{
    make_twins, summarise, StudyDirs, StudyPlan, TwinGroup, TwinScore, NOISE_SEEDS,
};
use surrogate::rom::Surrogate;

fn twin(
    truth: Option<(&str, f64)>,
    named: Option<&str>,
    first: &str,
    rank: Option<usize>,
) -> TwinScore {
    TwinScore {
        twin: "t".into(),
        truth: truth.map(|t| t.0.to_string()),
        true_value: truth.map(|t| t.1),
        material: String::new(),
        tip_move_sigma: 3.0,
        named: named.map(str::to_string),
        first: Some(first.into()),
        rank,
        indistinguishable_from_first: false,
        tied_with_first: (0, 16),
        name_estimate: None,
        refit_value: None,
        held_out_be: None,
        verdict: String::new(),
        model_error_best: false,
    }
}

#[test]
fn the_summary_counts_what_each_target_asks() {
    let mut a = twin(
        Some(("gap_bias", -0.3)),
        Some("gap_bias"),
        "gap_bias",
        Some(1),
    );
    a.refit_value = Some((-0.35, -0.4, -0.32)); // 17 % off: recovered
    a.held_out_be = Some((4.0, 3.0, 3.0)); // within 1.2 × noise
    let mut b = twin(
        Some(("gap_bias", -0.1)),
        Some("wall_bias"),
        "wall_bias",
        Some(2),
    );
    b.indistinguishable_from_first = true;
    b.tied_with_first = (3, 16);
    let mut c = twin(
        Some(("pressure_loss", 0.05)),
        Some("pressure_loss"),
        "pressure_loss",
        Some(1),
    );
    c.refit_value = Some((0.08, 0.07, 0.09)); // 60 % off, interval misses: not recovered
    c.held_out_be = Some((4.0, 3.7, 3.0)); // 1.23 × noise: outside
    let mut d = twin(Some(("plate_offset", -0.6)), None, "pressure_loss", Some(4));
    d.tip_move_sigma = 0.5; // invisible in the tip: outside the visible subset
    let mut mesh = twin(None, None, "model_mesh", None);
    mesh.model_error_best = true; // the model's own error, not physics: no false alarm
    let nulls = [
        twin(None, None, "anisotropy", None),
        twin(None, Some("gap_bias"), "gap_bias", None),
        mesh,
    ];
    let mut all = vec![a, b, c, d];
    all.extend(nulls);
    let s = summarise(&all);
    assert_eq!(s.visible, 3);
    assert_eq!(s.visible_first, 2);
    assert_eq!(s.visible_first_or_indistinguishable, 3);
    assert_eq!(s.visible_mean_tied, (1.0, 16.0));
    assert_eq!(s.visible_named, 2);
    assert_eq!((s.effect_twins, s.effect_first), (4, 2));
    assert_eq!((s.nulls, s.false_alarms), (3, 1));
    assert_eq!(s.model_error_best, (0, 1));
    assert_eq!(s.sizes_recovered, (1, 2));
    assert_eq!(s.held_out_within, (1, 2));
    let count = |r: &str, c: &str| {
        s.confusion
            .iter()
            .find(|x| x.0 == r && x.1 == c)
            .map_or(0, |x| x.2)
    };
    assert_eq!(count("gap_bias", "gap_bias"), 1);
    assert_eq!(count("gap_bias", "wall_bias"), 1);
    assert_eq!(count("plate_offset", "nothing"), 1);
    assert_eq!(count("none", "nothing"), 1);
    assert_eq!(count("none", "nothing (model's mesh)"), 1);
    assert_eq!(count("none", "gap_bias"), 1);
}

#[test]
fn the_standard_plan_is_reproducible_and_inside_the_domain() {
    let model = Surrogate::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/as_modelled/actuator_coarse.json"),
    )
    .unwrap();
    let domain = ParamSpace::training_domain(&model).unwrap();
    let a = StudyPlan::standard(&domain, 7).unwrap();
    assert_eq!(a, StudyPlan::standard(&domain, 7).unwrap());
    assert_ne!(a.groups, StudyPlan::standard(&domain, 8).unwrap().groups);
    assert_eq!(a.groups.len(), 18);
    assert_eq!(a.twins().len(), 54);
    for g in &a.groups {
        let m = g
            .material
            .split(',')
            .map(|v| v.parse::<f64>().unwrap())
            .collect::<Vec<_>>();
        let set = OgdenSet::new(m[0], m[1], m[2], m[3]).unwrap();
        assert!(domain.contains(&set), "{}", g.material);
        g.settings(&a, 1, Path::new("/tmp")).unwrap();
    }
    assert_eq!(a.groups.iter().filter(|g| g.effects.is_empty()).count(), 6);
    assert_eq!(a.noise_seeds, NOISE_SEEDS);
}

/// The README's two processes: the effect groups in one, the null groups in the other.
fn readme_split(plan: &StudyPlan) -> [Vec<String>; 2] {
    let (nulls, effects): (Vec<&TwinGroup>, Vec<&TwinGroup>) =
        plan.groups.iter().partition(|g| g.effects.is_empty());
    [effects, nulls].map(|gs| gs.iter().map(|g| g.id.clone()).collect())
}

fn seeds(plan: &StudyPlan) -> Vec<(String, u64)> {
    plan.twins()
        .into_iter()
        .map(|(g, r, name)| (name, plan.noise_seed(&plan.groups[g].id, r)))
        .collect()
}

#[test]
fn every_twin_draws_its_own_noise_whichever_groups_a_run_is_given() {
    let model = Surrogate::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/as_modelled/actuator_coarse.json"),
    )
    .unwrap();
    let plan = StudyPlan::standard(&ParamSpace::training_domain(&model).unwrap(), 2026).unwrap();
    let all = seeds(&plan);
    let mut distinct: Vec<u64> = all.iter().map(|s| s.1).collect();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), 54);
    // two runs split by `--groups`, and one run per group: the seeds of the whole plan
    let [effects, nulls] = readme_split(&plan);
    assert_eq!((effects.len(), nulls.len()), (12, 6));
    let mut split: Vec<(String, u64)> = [effects, nulls]
        .iter()
        .flat_map(|ids| seeds(&plan.only(ids).unwrap()))
        .collect();
    split.sort();
    let mut whole = all.clone();
    whole.sort();
    assert_eq!(split, whole);
    for g in &plan.groups {
        let one = seeds(&plan.only(std::slice::from_ref(&g.id)).unwrap());
        assert!(one.iter().all(|s| all.contains(s)), "{}", g.id);
    }
    // the groups given in another order: the plan's order, the same seeds
    let reversed: Vec<String> = plan.groups.iter().rev().map(|g| g.id.clone()).collect();
    assert_eq!(seeds(&plan.only(&reversed).unwrap()), all);
    // another draw seed, other noise
    let other = StudyPlan {
        draw_seed: 2027,
        ..plan.clone()
    };
    assert!(seeds(&other).iter().all(|s| !distinct.contains(&s.1)));
    // a group the plan lacks is named with the plan's groups
    let e = plan.only(&["null_9".to_string()]).unwrap_err().to_string();
    assert!(e.contains("null_9") && e.contains("null_6"), "{e}");
}

#[test]
fn a_plan_of_an_older_noise_seed_derivation_reads_as_such_and_makes_no_twins() {
    let dir = std::env::temp_dir().join(format!("surrogate_study_plan_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plan.json");
    let committed = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fe_reference/diagnosis/blind/plan.json"),
    )
    .unwrap();
    let plan = StudyPlan::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("fe_reference/diagnosis/blind/plan.json"),
    )
    .unwrap();
    assert_eq!(plan.noise_seeds, NOISE_SEEDS);
    plan.check_noise_seeds().unwrap();
    let field = format!("\"noise_seeds\": {NOISE_SEEDS}");
    assert!(committed.contains(&field));
    for (old, scheme) in [
        ("\"independent_noise\": true", 1),
        ("\"independent_noise\": false", 0),
    ] {
        std::fs::write(&path, committed.replace(&field, old)).unwrap();
        let p = StudyPlan::read(&path).unwrap();
        assert_eq!(p.noise_seeds, scheme);
        let e = p.check_noise_seeds().unwrap_err().to_string();
        assert!(
            e.contains(&format!(
                "plan noise_seeds = {scheme}: expected {NOISE_SEEDS}"
            )),
            "{e}"
        );
        let dirs = StudyDirs::under(&dir);
        let shipped = Recordings::shipped().unwrap();
        assert!(make_twins(&p, &shipped, &dirs, &|_| {}).is_err());
        assert!(!dirs.twins.exists() && !dirs.keys.exists());
    }
    // a key holds the plan's seed; one of another derivation is refused, named
    let key_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fe_reference/diagnosis/blind/keys/null_1_s1.json");
    let mut key: TwinKey =
        serde_json::from_str(&std::fs::read_to_string(key_path).unwrap()).unwrap();
    plan.check_key("null_1", 1, &key).unwrap();
    assert!(plan.check_key("null_1", 2, &key).is_err());
    key.seed = 18_273_785_850_258_396_930; // derivation 1, the first group of a run
    let e = plan.check_key("null_1", 1, &key).unwrap_err().to_string();
    assert!(
        e.starts_with("seed of null_1_s1 = 18273785850258396930: expected"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
