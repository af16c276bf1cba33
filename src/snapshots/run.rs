//! Running a shard: the case-runner abstraction, the resumable parallel driver, and an analytic
//! stand-in for the FE.
//!
//! [`run_shard`] reads top to bottom: open the directory (plan hash) → find the shard's cases
//! → skip the finished ones (validated) → remove the temporaries of the rest → run them in
//! parallel, each written atomically as soon as it finishes → summary. The running is the FE
//! campaign runner's ([`crate::fe::runner`]): the shard directory is its store, the case
//! runner its solver, every case on its own, in plan order.
//! Each case writes its own file, so the result does not depend on the thread count or on the
//! order in which cases finish.

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::plan::{Plan, PlanSettings, PlannedCase};
use super::shard::Shard;
use super::store::{read_case_file, CaseFile, ShardDir};
pub use super::store::{CaseOutcome, StepOutputs};
use super::SnapshotError;
use crate::fe::runner::{Batch, Independent, Link, Obtained, Store};

/// Computes one case. Implemented by every `Fn(&PlannedCase, &PlanSettings) -> CaseOutcome +
/// Sync`: the FE ([`super::fe_runner::fe_runner`]) or a cheap stand-in ([`AnalyticRunner`]).
pub trait CaseRunner: Sync {
    /// Runs the case's pressure ramp. A failure is part of the outcome, not a panic.
    fn run(&self, case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome;
}

impl<F> CaseRunner for F
where
    F: Fn(&PlannedCase, &PlanSettings) -> CaseOutcome + Sync,
{
    fn run(&self, case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
        self(case, settings)
    }
}

/// Options of [`run_shard`].
#[derive(Clone, Copy, Debug)]
pub struct RunOptions {
    /// The share of the plan to run.
    pub shard: Shard,
    /// Worker threads (cases in parallel); `None`: rayon's default (one per core).
    pub threads: Option<usize>,
    /// Run again the cases whose file records a failure (after a solver improvement); the
    /// new file replaces the old one atomically.
    pub retry_failed: bool,
}

/// Progress after each case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Cases finished in this run.
    pub done: usize,
    /// Of which failed.
    pub failed: usize,
    /// Cases this run has to do.
    pub total: usize,
}

/// What a shard run did.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    /// The shard.
    pub shard: Shard,
    /// Cases in the shard.
    pub cases: usize,
    /// Cases found finished (resume).
    pub skipped: usize,
    /// Cases run now.
    pub done: usize,
    /// Of which failed (recorded with their error).
    pub failed: usize,
    /// Wall time (s).
    pub wall_time_s: f64,
}

impl std::fmt::Display for RunSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "shard {}: {} cases done ({} failed), {} already done, {} of {} in the shard finished, {:.1} s",
            self.shard,
            self.done,
            self.failed,
            self.skipped,
            self.done + self.skipped,
            self.cases,
            self.wall_time_s
        )
    }
}

/// Runs the cases of `options.shard` not yet in `dir`, in parallel, calling `progress` once
/// before the first and after each case. Safe to call again after a kill: finished cases are skipped.
///
/// # Errors
/// Directory errors ([`ShardDir::create`]: another plan, not a snapshot directory), an
/// invalid existing case file, I/O errors; a runner's failure is recorded, not returned.
pub fn run_shard(
    plan: &Plan,
    dir: &Path,
    options: &RunOptions,
    runner: &dyn CaseRunner,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<RunSummary, SnapshotError> {
    let start = Instant::now();
    let store = ShardStore::open(ShardDir::create(dir, plan)?, plan, options.retry_failed)?;
    let cases = plan.shard_cases(options.shard);
    let batch = Batch::look_up(&cases, &store)?;
    let pending = batch.to_run();
    for &i in &pending {
        store.dir.remove_temporaries(cases[i].id)?;
    }
    let total = pending.len();
    progress(Progress {
        done: 0,
        failed: 0,
        total,
    });
    let solver = Independent(|case: &&PlannedCase| run_guarded(runner, case, &plan.settings));
    let order = Link::independent(&pending);
    let work = || {
        batch.run(&order, &solver, |t, _| {
            progress(Progress {
                done: t.ran,
                failed: t.failed,
                total: t.to_run,
            })
        })
    };
    let reports = match options.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| {
                SnapshotError::field("threads", n, &format!("a usable thread count ({e})"))
            })?
            .install(work)?,
        None => work()?,
    };
    let failed = reports
        .iter()
        .filter(|r| matches!(r.obtained, Obtained::Failed { .. }))
        .count();
    Ok(RunSummary {
        shard: options.shard,
        cases: cases.len(),
        skipped: cases.len() - total,
        done: total,
        failed,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// A shard directory as the runner's store: a case is held when its file exists and is valid
/// for the plan (and, with `retry_failed`, records no failure); a case run is written to its
/// own file atomically.
struct ShardStore<'p> {
    dir: ShardDir,
    files: BTreeMap<usize, PathBuf>,
    settings: &'p PlanSettings,
    retry_failed: bool,
}

impl<'p> ShardStore<'p> {
    /// The store of `dir` for `plan`, with the case files there now.
    fn open(dir: ShardDir, plan: &'p Plan, retry_failed: bool) -> Result<Self, SnapshotError> {
        Ok(Self {
            files: dir.case_ids()?,
            dir,
            settings: &plan.settings,
            retry_failed,
        })
    }
}

impl Store<&PlannedCase> for ShardStore<'_> {
    type Ramp = CaseOutcome;
    type Held = CaseFile;
    type Error = SnapshotError;

    fn held(&self, case: &&PlannedCase) -> Result<Option<CaseFile>, SnapshotError> {
        let Some(path) = self.files.get(&case.id) else {
            return Ok(None);
        };
        let file = read_case_file(path, case, self.settings)?;
        Ok((!(file.failed && self.retry_failed)).then_some(file))
    }

    fn keep(&self, case: &&PlannedCase, outcome: &CaseOutcome) -> Result<(), SnapshotError> {
        self.dir
            .write_case(case, self.settings, outcome)
            .map(|_| ())
    }
}

/// How far a shard is ([`shard_status`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ShardStatus {
    /// Cases in the shard.
    pub cases: usize,
    /// Of which finished (a case file exists, failed or not).
    pub finished: usize,
    /// Finished cases that failed: id and the solver's message (their converged steps are
    /// kept; the rest of the ramp has `converged = false`).
    pub failed: Vec<(usize, String)>,
    /// Rows with `converged = false` over the finished cases.
    pub unconverged_rows: usize,
}

/// How far a shard is, without running or writing anything.
///
/// # Errors
/// As [`run_shard`] before it runs anything: another plan in `dir`, an invalid case file.
pub fn shard_status(plan: &Plan, dir: &Path, shard: Shard) -> Result<ShardStatus, SnapshotError> {
    let mut status = ShardStatus {
        cases: plan.shard_cases(shard).len(),
        finished: 0,
        failed: Vec::new(),
        unconverged_rows: 0,
    };
    let Some(store) = ShardDir::existing(dir, plan)? else {
        return Ok(status);
    };
    let files = store.case_ids()?;
    for case in plan.shard_cases(shard) {
        if let Some(path) = files.get(&case.id) {
            let f = read_case_file(path, case, &plan.settings)?;
            status.finished += 1;
            status.unconverged_rows += f.unconverged_rows;
            if f.failed {
                status.failed.push((case.id, f.error.unwrap_or_default()));
            }
        }
    }
    Ok(status)
}

/// Runs one case, turning a panic into a failed outcome.
fn run_guarded(
    runner: &dyn CaseRunner,
    case: &PlannedCase,
    settings: &PlanSettings,
) -> CaseOutcome {
    match catch_unwind(AssertUnwindSafe(|| runner.run(case, settings))) {
        Ok(mut outcome) => {
            if outcome.steps.len() > settings.pressures_bar.len() {
                let n = outcome.steps.len();
                outcome.steps.truncate(settings.pressures_bar.len());
                outcome.error = Some(format!(
                    "runner returned {n} steps for {} pressures (extra steps dropped)",
                    settings.pressures_bar.len()
                ));
            }
            outcome
        }
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            CaseOutcome::failed(format!("runner panicked: {msg}"))
        }
    }
}

/// A cheap deterministic stand-in for the FE, for tests and dry runs of the distribution
/// machinery (shards, resume, merge, Slurm): smooth closed-form outputs of the case's inputs.
///
/// Every case whose `id % fail_every == fail_every − 1` (if `fail_every > 0`) stops after half
/// of its ramp with an error, to exercise the failure records.
#[derive(Clone, Copy, Debug, Default)]
pub struct AnalyticRunner {
    /// Sleep per case (to make runs long enough to kill in tests).
    pub delay: Duration,
    /// Every how many cases one fails (0: none).
    pub fail_every: usize,
}

impl CaseRunner for AnalyticRunner {
    fn run(&self, case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
        std::thread::sleep(self.delay);
        let mu0 = 0.5
            * (case.material.mu1_mpa * case.material.alpha1
                + case.material.mu2_mpa * case.material.alpha2);
        let fails = self.fail_every > 0 && case.id % self.fail_every == self.fail_every - 1;
        let reach = if fails {
            settings.pressures_bar.len() / 2
        } else {
            settings.pressures_bar.len()
        };
        let steps = settings.pressures_bar[..reach]
            .iter()
            .map(|&p| {
                // curvature ~ P / (μ0 T), a circular arc of length 92 mm
                let kappa = 0.02 * (p + 0.1) * case.n_bellows as f64
                    / (11.0 * mu0 * case.wall_thickness_mm)
                    * (1.0 + 0.05 * case.material.alpha1.ln() - 0.02 * case.material.alpha2);
                let arc = |s: f64| {
                    let th = kappa * s;
                    [s - th.sin() / kappa, -(1.0 - th.cos()) / kappa]
                };
                let markers = std::array::from_fn(|k| arc(92.0 * (k + 1) as f64 / 9.0));
                let tip = markers[8];
                StepOutputs {
                    tip_uz_mm: tip[0],
                    tip_uy_mm: tip[1],
                    angle_deg: (-tip[1]).atan2(92.0 - tip[0]).to_degrees(),
                    force_n: 0.4 * p * case.n_bellows as f64 / 11.0,
                    markers,
                    newton_iterations: 3 + (case.id % 4),
                    substeps: 1,
                    cutbacks: 0,
                    residual: 1e-9 / (1.0 + p),
                    min_gap_mm: 1.0 - 0.1 * p,
                    converged: true,
                }
            })
            .collect();
        CaseOutcome {
            steps,
            error: fails.then(|| {
                let p = settings
                    .pressures_bar
                    .get(reach)
                    .copied()
                    .unwrap_or(f64::NAN);
                format!("analytic runner: simulated non-convergence at {p} bar")
            }),
        }
    }
}
