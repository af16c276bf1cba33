//! Snapshots: FE results over the design / material space, for training the surrogate.
//!
//! ```text
//!   plan (JSON) ──shard k/n──► run_shard ──one case file per case──► DIR/cases/case_000123.csv
//!        │                        │ (rayon over cases, resumable)             │
//!        └─ plan hash ────────────┴──────────────► DIR/plan_hash            merge ──► one CSV
//! ```
//!
//! * [`plan`]: the sampling plan — ranges, a seeded maximin Latin hypercube stratified over
//!   `N`, the pressure ramp and the solver/mesh settings, and the explicit list of cases.
//! * [`shard`]: the deterministic share `k/n` of a plan.
//! * [`store`]: a case's outcome ([`CaseOutcome`]), the snapshot CSV columns and the atomic
//!   per-case files of a shard directory.
//! * [`mod@merge`]: shard directories → one snapshot CSV, identical to a single run.
//! * [`run`]: the case runner abstraction ([`CaseRunner`]), the shard driver with resume (the FE
//!   campaign runner, [`crate::fe::runner`], with the shard directory as its store), and a
//!   cheap analytic runner for tests and dry runs of the distribution machinery.
//! * [`fe_runner`]: the real runner: per case, the FE bending ramp and the blocked-force ramp
//!   ([`fe_runner::blocked_force_ramp`]) through the plan's pressures.
//! * [`verify`]: re-simulates random cases of a snapshot file and compares the outputs.
//!
//! ## One case, one ramp
//!
//! Pressure is not sampled: each case `(N, T, μ₁, α₁, μ₂, α₂)` is one FE pressure ramp through
//! the plan's pressures (default 0, 0.25, …, 3.5 bar: 15 levels), and every level is one
//! snapshot row. Continuation along the ramp makes the extra levels nearly free.
//!
//! ## Plan format (`plan.json`, `format_version` 1)
//!
//! ```json
//! { "format_version": 1, "seed": 2024, "sampler": "…",
//!   "ranges": { "n_bellows": [7, 8, …, 15], "wall_thickness_mm": [1.2, 2.8],
//!               "mu0_mpa": [1.5, 15.0], "term1_share": [0.02, 0.95],
//!               "alpha1": [1.0, 8.0], "alpha2": [-3.0, -0.004] },
//!   "settings": { "pressures_bar": [0.0, 0.25, …, 3.5], "gravity": true,
//!                 "mesh": { "level": "standard", "element_size": null },
//!                 "bulk_ratio": 1000.0, "solver": { "rtol": 1e-7, … } },
//!   "cases": [ { "id": 0, "n_bellows": 9, "wall_thickness_mm": 1.87,
//!                "mu1_mpa": 1.2, "alpha1": 3.3, "mu2_mpa": -9.1, "alpha2": -0.7 }, … ] }
//! ```
//!
//! A plan with effects ([`plan`], "Effects") adds `settings.effects` (`{name: value}`, fixed
//! for every case), `ranges.effects` (`{name: [lo, hi]}`, sampled) and `cases[i].effects` (the
//! sampled values); a plan without effects has none of these fields.
//!
//! The cases are explicit: a plan can be edited by hand (every case is validated on load), and
//! the sampler only matters when a plan is generated. The **plan hash** is the CRC-32 of the
//! plan's canonical compact JSON (the parsed plan re-serialised, so formatting does not count).
//!
//! ## Store layout and guarantees
//!
//! ```text
//! DIR/plan.json               canonical copy of the plan
//! DIR/plan_hash               "<8 hex digits>\n": CRC-32 of the canonical plan
//! DIR/cases/case_000123.csv   one finished case: header + one row per plan pressure
//! ```
//!
//! * **Atomic per case**: a case file is written to a temporary file in the same directory,
//!   flushed to disk (`fsync`) and renamed; a case file either exists complete or not at all.
//! * **Resume**: a run skips every case of its shard whose file exists (and is validated); a run
//!   killed at any point resumes where it stopped, never duplicating or losing a case.
//!   Temporary files of the shard's own cases left by a kill are removed on resume.
//! * **Failures are data**: a case whose FE solve stops keeps its converged steps; the remaining
//!   pressures get `converged = false`, `NaN` outputs and the error message in `error`. A
//!   failed case is finished like any other (a resume does not retry it: delete its file to).
//!   A runner that panics is recorded the same way (`runner panicked: …`).
//! * **Plan identity**: a directory created for one plan refuses another plan (different hash).
//! * **Determinism**: a case file depends only on the plan and the case; shard count, thread
//!   count and resume history do not change a byte of the merged file.
//!
//! ## Snapshot CSV
//!
//! The 31 columns of the snapshot contract ([`crate::schema::SNAPSHOT_COLUMNS`]) followed by
//! the provenance columns `newton_iterations, substeps, cutbacks, residual, min_gap_mm, mesh,
//! element_size_mm, bulk_ratio, gravity, solver_rtol, code_version, error` (see [`store`];
//! units and meanings: [`crate::schema`]).
//! Floats are written in Rust's shortest round-trip form, so values re-read are bit-identical.
//!
//! ## Commands
//!
//! ```sh
//! # the sampling plan (ranges, mesh, pressures: see `snapshots plan --help`)
//! surrogate snapshots plan --cases 200 --seed 2024 --out training_data/plan.json
//! # one machine: all cases, in parallel, resumable (run it again after a kill)
//! surrogate snapshots --plan training_data/plan.json --out snapshot_runs/all
//! surrogate snapshots merge --from snapshot_runs/all --out training_data/snapshots.csv
//! # or by shards (`snapshots` = `snapshots run`), then one merge
//! surrogate snapshots run --plan P --shard 2/4 --out snapshot_runs/shard_2 --threads 2
//! surrogate snapshots merge --from snapshot_runs/shard_* --out training_data/snapshots.csv
//! # how far a shard is, without running anything
//! surrogate snapshots run --plan P --shard 2/4 --out snapshot_runs/shard_2 --dry-run
//! # re-simulate 3 random cases of a merged file, compare every output to 1e-9
//! surrogate snapshots verify --data training_data/snapshots.csv --cases 3
//! # dry run of the machinery with a closed-form stand-in for the FE
//! surrogate snapshots --plan P --out /tmp/dry --runner analytic
//! ```
//!
//! ## Slurm
//!
//! `slurm/submit.sh PLAN N OUT MERGED` submits `slurm/snapshots.sbatch` as a job array of `N`
//! tasks (task `i` of `--array=0-(N−1)` runs shard `i+1/N` into `OUT/shard_<i+1>`, with
//! `--threads $SLURM_CPUS_PER_TASK`) and the same script again as the merge job, with
//! `--dependency=afterok:<array>`. A task killed by a time limit loses only its running cases:
//! resubmit and every shard resumes. `slurm/local_cluster.sh` starts a single-node Slurm
//! (munge, slurmctld, slurmd) on a Debian machine; `slurm/local_run.sh` runs a tiny real-FE
//! plan through it and writes `slurm/local_run.log` (merged file identical to a single run).

pub mod fe_runner;
pub mod merge;
pub mod plan;
pub mod run;
pub mod shard;
pub mod store;
pub mod verify;

pub use merge::{merge, MergeSummary};
pub use plan::{Plan, PlanSettings, PlannedCase, Ranges};
pub use run::{run_shard, CaseRunner, RunOptions, RunSummary};
pub use shard::Shard;
pub use store::{CaseOutcome, ShardDir, StepOutputs};

use thiserror::Error;

/// Version of the code that produced a snapshot: the crate version, plus `+<describe>` when the
/// binary was built with `SURROGATE_GIT_DESCRIBE` set (e.g. to `git describe --always --dirty`).
pub fn code_version() -> String {
    let version = env!("CARGO_PKG_VERSION");
    match option_env!("SURROGATE_GIT_DESCRIBE") {
        Some(describe) if !describe.is_empty() => format!("{version}+{describe}"),
        _ => version.to_owned(),
    }
}

/// Errors of plans, shard directories and merges.
#[derive(Debug, Error)]
pub enum SnapshotError {
    /// Input/output failure with the path involved.
    #[error("{path}: {source}")]
    Io {
        /// File or directory involved.
        path: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A plan file that is not valid JSON or misses a field.
    #[error("plan {path}: {message}")]
    PlanSyntax {
        /// The plan file.
        path: String,
        /// The parser's message (names the field, line and column).
        message: String,
    },
    /// A plan field (or a plan generation setting) with an invalid value.
    #[error("plan field {field} = {value}: expected {expected}")]
    PlanField {
        /// Field path, e.g. `cases[12].wall_thickness_mm` or `ranges.alpha2`.
        field: String,
        /// The value as given.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// A shard specification that is not `k/n` with `1 ≤ k ≤ n`.
    #[error("shard {spec:?}: expected {expected}")]
    Shard {
        /// The specification as given.
        spec: String,
        /// What was expected.
        expected: String,
    },
    /// An output directory that holds a different plan.
    #[error(
        "{dir} holds snapshots of a different plan (plan hash {found}, this plan has {expected}): \
         use another output directory, or the plan that directory was made for"
    )]
    PlanMismatch {
        /// The directory.
        dir: String,
        /// Hash recorded in the directory.
        found: String,
        /// Hash of the plan given.
        expected: String,
    },
    /// A directory that exists but is not a snapshot directory.
    #[error("{dir} is not a snapshot directory: {reason}")]
    NotSnapshotDir {
        /// The directory.
        dir: String,
        /// What is wrong.
        reason: String,
    },
    /// A case file that cannot be read back.
    #[error("case file {path}: line {line}: {message}")]
    CaseFile {
        /// The file.
        path: String,
        /// 1-based line (1 = header).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Shard directories that do not add up to the plan.
    #[error("merge: {message}")]
    Merge {
        /// What is wrong (missing or duplicate case ids, different plans).
        message: String,
    },
}

impl SnapshotError {
    /// An [`SnapshotError::Io`] for `path`.
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        SnapshotError::Io {
            path: path.display().to_string(),
            source,
        }
    }

    /// A [`SnapshotError::PlanField`].
    pub(crate) fn field(field: impl Into<String>, value: impl ToString, expected: &str) -> Self {
        SnapshotError::PlanField {
            field: field.into(),
            value: value.to_string(),
            expected: expected.to_owned(),
        }
    }
}
