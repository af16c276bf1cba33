//! The blind study's noise (`surrogate::diagnose::study`): the twins that the README's two
//! processes make (`twin-study --stage twins --groups`, the effect groups in one, the null
//! groups in the other) are byte for byte those of one run of the whole plan, every twin
//! draws its own noise, and the committed twins are those this code makes. The twins are
//! made from the committed FE ramps: the test checks first that every ramp is in the cache,
//! so no FE runs here.

use std::path::{Path, PathBuf};

use surrogate::calibrate::synthetic::{noisy_recordings, TrueOutputs};
use surrogate::calibrate::twin::TwinKey;
use surrogate::calibrate::Recordings;
use surrogate::diagnose::study::{make_twins, ramps_to_run, StudyDirs, StudyPlan, NOISE_SEEDS};

const STUDY: &str = "fe_reference/diagnosis/blind";

/// The study's directories under `root`, the FE read from the committed cache.
fn study_under(root: &Path) -> StudyDirs {
    StudyDirs {
        cache: StudyDirs::under(Path::new(STUDY)).cache,
        ..StudyDirs::under(root)
    }
}

/// Every file under `dir`, by its path relative to `dir`, with its bytes.
fn files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                let bytes = std::fs::read(&p).unwrap();
                out.push((p.strip_prefix(dir).unwrap().to_path_buf(), bytes));
            }
        }
    }
    out.sort();
    out
}

fn key(path: &Path) -> TwinKey {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn the_readme_s_two_processes_make_the_twins_of_one_run() {
    let plan = StudyPlan::read(&Path::new(STUDY).join("plan.json")).unwrap();
    let shipped = Recordings::read_dir(Path::new("training_data")).unwrap();
    let committed = StudyDirs::under(Path::new(STUDY));
    // no FE: every ramp of every group is in the committed cache
    assert_eq!(ramps_to_run(&plan, &shipped, &committed).unwrap(), vec![]);
    let root = std::env::temp_dir().join(format!("surrogate_study_noise_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let one = study_under(&root.join("one"));
    make_twins(&plan, &shipped, &one, &|_| {}).unwrap();
    // the README's split: the effect groups, then the null groups, each run alone
    let two = study_under(&root.join("two"));
    let (nulls, effects): (Vec<String>, Vec<String>) = plan
        .groups
        .iter()
        .map(|g| g.id.clone())
        .partition(|id| id.starts_with("null_"));
    assert_eq!((effects.len(), nulls.len()), (12, 6));
    for ids in [&effects, &nulls] {
        make_twins(&plan.only(ids).unwrap(), &shipped, &two, &|_| {}).unwrap();
    }
    let (twins, keys) = (files(&one.twins), files(&one.keys));
    assert_eq!((twins.len(), keys.len()), (54 * 3, 54));
    assert!(
        twins == files(&two.twins),
        "the split runs' recordings differ"
    );
    assert!(keys == files(&two.keys), "the split runs' keys differ");
    // every twin its own seed, its origin in the key
    let mut seeds: Vec<u64> = Vec::new();
    for (g, replicate, name) in plan.twins() {
        let id = &plan.groups[g].id;
        let k = key(&one.keys.join(format!("{name}.json")));
        assert_eq!(k.seed, plan.noise_seed(id, replicate), "{name}");
        let origin = k.seed_origin.unwrap();
        assert!(
            origin.contains(&format!("noise seeds {NOISE_SEEDS}"))
                && origin.ends_with(&format!("group {id}, replicate {replicate}")),
            "{origin}"
        );
        seeds.push(k.seed);
        // the committed twin is the one this code makes
        let made = files(&one.twins.join(&name));
        assert!(made == files(&committed.twins.join(&name)), "{name}");
        assert_eq!(
            k.seed,
            key(&committed.keys.join(format!("{name}.json"))).seed
        );
    }
    seeds.sort_unstable();
    seeds.dedup();
    assert_eq!(seeds.len(), 54);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn no_two_twins_of_the_plan_draw_the_same_noise() {
    let plan = StudyPlan::read(&Path::new(STUDY).join("plan.json")).unwrap();
    let shipped = Recordings::read_dir(Path::new("training_data")).unwrap();
    // a truth of zeros at every recorded configuration: the recordings are the noise
    let zero: Vec<TrueOutputs> = shipped
        .bending
        .iter()
        .map(|b| TrueOutputs {
            n_bellows: b.n_bellows,
            wall_thickness_mm: b.wall_thickness_mm,
            pressure_bar: b.pressure_bar,
            tip_uz_mm: 0.0,
            tip_uy_mm: 0.0,
            angle_deg: 0.0,
            force_n: 0.0,
        })
        .collect();
    // each twin's noise: tip, angle and force, every number in units of its rms over the twins
    let mut noise: Vec<(String, Vec<f64>)> = plan
        .twins()
        .into_iter()
        .map(|(g, replicate, name)| {
            let seed = plan.noise_seed(&plan.groups[g].id, replicate);
            let r = noisy_recordings(&zero, &shipped, seed, "twin").unwrap();
            let mut z: Vec<f64> = r
                .bending
                .iter()
                .flat_map(|b| [b.tip_uz_mm, b.tip_uy_mm, b.angle_deg])
                .collect();
            z.extend(r.force.iter().map(|f| f.force_n));
            (name, z)
        })
        .collect();
    let rms: Vec<f64> = (0..noise[0].1.len())
        .map(|j| (noise.iter().map(|(_, z)| z[j] * z[j]).sum::<f64>() / 54.0).sqrt())
        .collect();
    for (_, z) in &mut noise {
        z.iter_mut().zip(&rms).for_each(|(v, s)| *v /= s);
    }
    assert_eq!(noise.len(), 54);
    let corr = |a: &[f64], b: &[f64]| {
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(u, v)| u * v).sum::<f64>();
        dot(a, b) / (dot(a, a) * dot(b, b)).sqrt()
    };
    for (i, (a, za)) in noise.iter().enumerate() {
        assert!(za.len() >= 100 && za.iter().all(|v| v.is_finite()), "{a}");
        for (b, zb) in &noise[i + 1..] {
            assert_ne!(za, zb, "{a} and {b} draw the same noise");
            let c = corr(za, zb);
            assert!(c.abs() < 0.6, "{a} and {b}: noise correlated by {c:.2}");
        }
    }
}
