//! The unit tests of `src/fe/runner/mod.rs`.
//!
//! Tests of the runner: the same answers at any thread count, a run interrupted (a store that
//! stops writing) or started on a partial cache resumes with the same answers and runs only
//! what is missing, failures are reported with their message, and the FE ramp cache as a store.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::runner::*;
use surrogate::fe::simulate::{Case, Mode};

/// A toy case: its seed; a toy result: a number made of the seed and the parent's number, and
/// a failure for every seed ending in 4.
#[derive(Clone, Debug, PartialEq)]
struct Toy {
    value: u64,
    error: Option<String>,
}

impl Outcome for Toy {
    fn failure(&self) -> Option<&str> {
        self.error.as_deref()
    }
}

fn mix(a: u64, b: u64) -> u64 {
    (a ^ b.rotate_left(17)).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// The toy solver: counts its calls, and takes a little time so that threads interleave.
struct ToySolver {
    calls: AtomicUsize,
}

impl Solver<u64> for ToySolver {
    type Ramp = Toy;
    type Kept = u64;

    fn solve(&self, seed: &u64, parent: Option<(&u64, &u64)>) -> Solved<Toy, u64> {
        self.calls.fetch_add(1, Ordering::SeqCst);
        std::thread::sleep(std::time::Duration::from_millis(1 + seed % 3));
        let value = mix(*seed, parent.map_or(0, |(_, v)| *v));
        let error = (seed % 10 == 4).then(|| format!("toy solver stopped at seed {seed}"));
        Solved {
            ramp: Toy {
                value,
                error: error.clone(),
            },
            kept: error.is_none().then_some(value),
            from_parent: parent.is_some(),
        }
    }
}

/// A toy store: one file per seed in a directory, written atomically; after `limit` writes it
/// fails (an interrupted run).
struct ToyStore {
    dir: PathBuf,
    limit: usize,
    writes: AtomicUsize,
}

impl ToyStore {
    fn new(dir: &Path, limit: usize) -> Self {
        std::fs::create_dir_all(dir).unwrap();
        Self {
            dir: dir.to_path_buf(),
            limit,
            writes: AtomicUsize::new(0),
        }
    }

    fn path(&self, seed: u64) -> PathBuf {
        self.dir.join(format!("toy_{seed}.txt"))
    }
}

impl Store<u64> for ToyStore {
    type Ramp = Toy;
    type Held = Toy;
    type Error = String;

    fn held(&self, seed: &u64) -> Result<Option<Toy>, String> {
        let Ok(text) = std::fs::read_to_string(self.path(*seed)) else {
            return Ok(None);
        };
        let (value, error) = text.split_once('\n').ok_or("a damaged toy file")?;
        Ok(Some(Toy {
            value: value.parse().map_err(|_| "a damaged toy value")?,
            error: (!error.is_empty()).then(|| error.to_string()),
        }))
    }

    fn keep(&self, seed: &u64, ramp: &Toy) -> Result<(), String> {
        if self.writes.fetch_add(1, Ordering::SeqCst) >= self.limit {
            return Err("the store stopped (a kill)".into());
        }
        let text = format!("{}\n{}", ramp.value, ramp.error.clone().unwrap_or_default());
        surrogate::io::write_atomic(&self.path(*seed), text.as_bytes()).map_err(|e| e.to_string())
    }
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("runner_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// Seeds and a tree over them: case `i` starts from case `(i − 1) / 2` (a binary tree).
fn toy_cases() -> (Vec<u64>, Vec<Link>) {
    let seeds: Vec<u64> = (0..23).map(|i| 1000 + 7 * i).collect();
    let links = (0..seeds.len())
        .map(|i| Link {
            case: i,
            parent: (i > 0).then(|| (i - 1) / 2),
        })
        .collect();
    (seeds, links)
}

/// The value and failure of each case, and the parent it started from.
fn answers(reports: &[CaseReport<Toy, Toy>]) -> Vec<(u64, Option<String>, Option<usize>)> {
    reports
        .iter()
        .map(|r| {
            let toy = match &r.obtained {
                Obtained::Cache(t) | Obtained::Run(t) => t,
                Obtained::Failed { ramp, message } => {
                    assert_eq!(ramp.error.as_deref(), Some(message.as_str()));
                    ramp
                }
            };
            (toy.value, toy.error.clone(), r.parent)
        })
        .collect()
}

#[test]
fn the_answers_do_not_depend_on_the_thread_count() {
    let (seeds, links) = toy_cases();
    let mut runs = Vec::new();
    for threads in [1, 2, 3, 8] {
        let solver = ToySolver {
            calls: AtomicUsize::new(0),
        };
        let tallies = Mutex::new(Vec::new());
        let reports = pool(threads).install(|| {
            let store = NoStore::new();
            let Ok(batch) = Batch::look_up(&seeds, &store);
            let Ok(r) = batch.run(&links, &solver, |t, _| tallies.lock().unwrap().push(*t));
            r
        });
        assert_eq!(solver.calls.load(Ordering::SeqCst), seeds.len());
        // one tally per case, one at a time: `ran` counts up, the failures never go down
        let tallies = tallies.into_inner().unwrap();
        let ran: Vec<usize> = tallies.iter().map(|t| t.ran).collect();
        assert_eq!(ran, (1..=seeds.len()).collect::<Vec<_>>());
        assert!(tallies.windows(2).all(|w| w[0].failed <= w[1].failed));
        let last = tallies.last().unwrap();
        assert_eq!((last.cases, last.held, last.to_run), (23, 0, 23));
        assert_eq!(last.failed, 3, "seeds 1014, 1084 and 1154 fail");
        runs.push(answers(&reports));
    }
    assert!(runs.windows(2).all(|w| w[0] == w[1]), "{runs:?}");
    // a case starts from its parent unless the parent failed
    let first = &runs[0];
    for (i, (_, _, parent)) in first.iter().enumerate() {
        let p = (i > 0).then(|| (i - 1) / 2);
        let expected = p.filter(|&p| first[p].1.is_none());
        assert_eq!(*parent, expected, "case {i}");
    }
}

#[test]
fn an_interrupted_run_resumes_with_the_same_answers_running_only_what_is_missing() {
    let (seeds, _) = toy_cases();
    let order = Link::independent(&(0..seeds.len()).rev().collect::<Vec<_>>());
    // the reference: one clean run
    let clean_dir = scratch("clean");
    let solver = ToySolver {
        calls: AtomicUsize::new(0),
    };
    let store = ToyStore::new(&clean_dir, usize::MAX);
    let clean = pool(2).install(|| {
        Batch::look_up(&seeds, &store)
            .unwrap()
            .run(&order, &solver, |_, _| {})
            .unwrap()
    });
    // a run killed after 9 cases were written
    let dir = scratch("killed");
    let killed = ToyStore::new(&dir, 9);
    let err = pool(2).install(|| {
        Batch::look_up(&seeds, &killed)
            .unwrap()
            .run(&order, &solver, |_, _| {})
            .err()
    });
    assert_eq!(err.as_deref(), Some("the store stopped (a kill)"));
    let written = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(written, 9);
    // the resume, on another thread count: the 9 from the store, the rest run
    let solver = ToySolver {
        calls: AtomicUsize::new(0),
    };
    let store = ToyStore::new(&dir, usize::MAX);
    let resumed = pool(3).install(|| {
        let batch = Batch::look_up(&seeds, &store).unwrap();
        assert_eq!(batch.held_count(), 9);
        batch.run(&order, &solver, |_, _| {}).unwrap()
    });
    assert_eq!(solver.calls.load(Ordering::SeqCst), seeds.len() - 9);
    let held = resumed
        .iter()
        .filter(|r| matches!(r.obtained, Obtained::Cache(_)))
        .count();
    assert_eq!(held, 9);
    assert_eq!(answers(&resumed), answers(&clean));
    // a third run finds everything
    let solver = ToySolver {
        calls: AtomicUsize::new(0),
    };
    let again = Batch::look_up(&seeds, &store)
        .unwrap()
        .run(&order, &solver, |_, _| {})
        .unwrap();
    assert_eq!(solver.calls.load(Ordering::SeqCst), 0);
    assert_eq!(answers(&again), answers(&clean));
    // a damaged entry stops the run before anything runs
    std::fs::write(store.path(seeds[3]), "nonsense").unwrap();
    assert!(Batch::look_up(&seeds, &store).is_err());
    for d in [clean_dir, dir] {
        std::fs::remove_dir_all(d).unwrap();
    }
}

#[test]
fn in_order_returns_by_item_and_runs_each_once() {
    let items: Vec<usize> = (0..17).collect();
    let order: Vec<usize> = (0..17).rev().collect();
    let seen = Mutex::new(BTreeMap::new());
    let out = pool(3).install(|| {
        in_order(&items, &order, |&i| {
            *seen.lock().unwrap().entry(i).or_insert(0) += 1;
            i * i
        })
    });
    assert_eq!(out, items.iter().map(|i| i * i).collect::<Vec<_>>());
    assert!(seen.into_inner().unwrap().values().all(|&n| n == 1));
}

/// A tiny FE case that stops at once (no Newton iteration allowed): its ramp fails quickly.
fn stopping_case(n: usize) -> Case {
    let solver = surrogate::fe::solver::SolverSettings {
        max_iterations: 1,
        max_cutbacks: 0,
        ..Default::default()
    };
    Case {
        design: DesignParams::new(n, 2.0).validate().unwrap(),
        material: Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap(),
        pressures_bar: vec![0.0, 0.5],
        gravity: true,
        mesh: MeshOptions {
            level: MeshLevel::Coarse,
            element_size: Some(20.0),
            wall_elements: None,
        },
        solver,
        mode: Mode::Bending,
        contact: Default::default(),
        effects: Default::default(),
    }
}

/// The FE ramp cache as the runner's store: ramps already there are reported from the cache
/// and not run, the missing one runs (and stops, with the solver's message), is written, and
/// a second run finds all three.
#[test]
fn the_ramp_cache_resumes_a_campaign() {
    let dir = scratch("ramp_cache");
    let cases: Vec<RampCase> = [7, 9, 11]
        .map(|n| RampCase::plain(stopping_case(n)))
        .to_vec();
    let store = RampDir::create(&dir).unwrap();
    let done = Ramp {
        error: Some("computed before".into()),
        ..Ramp::default()
    };
    for c in &cases[..2] {
        store.file(c).store(&done).unwrap();
    }
    let order = Link::independent(&[2, 1, 0]);
    let reports = run_campaign(&cases, &order, &Start::Cold, &store, |_, _| {}).unwrap();
    for r in &reports[..2] {
        assert!(
            matches!(&r.obtained, Obtained::Cache(h) if h.error.as_deref() == Some("computed before"))
        );
    }
    let Obtained::Failed { message, ramp } = &reports[2].obtained else {
        panic!("{:?}", reports[2].obtained);
    };
    assert!(!message.is_empty() && ramp.response.is_none());
    let again = run_campaign(&cases, &order, &Start::Cold, &store, |_, _| {}).unwrap();
    assert!(again
        .iter()
        .all(|r| matches!(r.obtained, Obtained::Cache(_))));
    assert!(matches!(&again[2].obtained, Obtained::Cache(h) if h.error.as_ref() == Some(message)));
    std::fs::remove_dir_all(dir).unwrap();
}

/// A cached ramp is reused only under its own key: another setting with the same file name is
/// not found, a ramp with sensitivities has its own file, a damaged file is not trusted.
#[test]
fn a_cached_ramp_is_reused_only_for_the_same_settings() {
    let dir = scratch("ramp_keys");
    std::fs::create_dir_all(&dir).unwrap();
    let case = |stiffness: f64| Case {
        design: DesignParams::new(11, 2.0).validate().unwrap(),
        material: Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap(),
        pressures_bar: vec![0.0, 1.0, 2.0],
        gravity: true,
        mesh: MeshOptions::level(MeshLevel::Standard),
        solver: surrogate::fe::solver::SolverSettings::default(),
        mode: Mode::Force,
        contact: surrogate::fe::simulate::ContactSettings {
            stiffness,
            ..Default::default()
        },
        effects: Default::default(),
    };
    let c = RampFile::at(&dir, &case(20.0), &[]);
    assert!(
        c.path.ends_with("n11_t2_force.json"),
        "{}",
        c.path.display()
    );
    assert!(c.load().is_none(), "nothing cached yet");
    let ramp = Ramp {
        error: Some("stopped at 1.5 bar".into()),
        ..Ramp::default()
    };
    c.store(&ramp).unwrap();
    let back = c.load().unwrap();
    assert_eq!(
        (back.steps.len(), back.error.as_deref()),
        (0, Some("stopped at 1.5 bar"))
    );
    // another setting: same file name, other key, not reused
    let other = RampFile::at(&dir, &case(40.0), &[]);
    assert_eq!(other.path, c.path);
    assert!(other.load().is_none());
    // a ramp with sensitivities: its own file and key
    let sens = RampFile::at(
        &dir,
        &case(20.0),
        &surrogate::fe::sensitivity::Parameter::all(),
    );
    assert!(sens.path.ends_with("n11_t2_force_sensitivities.json"));
    assert!(sens.load().is_none());
    // a damaged file is recomputed, not trusted
    std::fs::write(&c.path, "{\"key\": ").unwrap();
    assert!(c.load().is_none());
    std::fs::remove_dir_all(dir).unwrap();
}
