//! `surrogate snapshots`: sampling plans, shard runs (resumable), merges.
//!
//! `surrogate snapshots --plan P --shard k/n --out DIR` is `snapshots run`.
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::fe::effects::Effects;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;
use surrogate::snapshots::fe_runner::fe_runner;
use surrogate::snapshots::merge::{merge_with, sidecar_path};
use surrogate::snapshots::run::{shard_status, AnalyticRunner, Progress};
use surrogate::snapshots::store::case_name;
use surrogate::snapshots::verify::resimulate;
use surrogate::snapshots::{run_shard, CaseRunner, Plan, PlanSettings, Ranges, RunOptions, Shard};

/// `surrogate snapshots subset`.
#[derive(Debug, Args)]
pub struct SubsetArgs {
    /// The parent plan.
    #[arg(long)]
    pub plan: PathBuf,
    /// Number of cases to keep.
    #[arg(long)]
    pub cases: usize,
    /// Mesh level of the subset: coarse | standard | fine.
    #[arg(long, default_value = "standard")]
    pub mesh: String,
    /// Element size override (mm).
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Output plan file.
    #[arg(long)]
    pub out: PathBuf,
}

/// `surrogate snapshots`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SnapshotsArgs {
    /// The subcommand (default: run).
    #[command(subcommand)]
    pub command: Option<SnapshotsCommand>,
    /// `run`'s options, accepted without the word `run`.
    #[command(flatten)]
    pub run: Option<RunArgs>,
}

/// Subcommands of `snapshots`.
#[derive(Debug, Subcommand)]
pub enum SnapshotsCommand {
    /// Write a sampling plan (maximin Latin hypercube, stratified over N).
    Plan(Box<PlanArgs>),
    /// Run a shard of a plan into a directory (resumes where a previous run stopped).
    Run(RunArgs),
    /// A subset of a plan's cases on another mesh (the high-fidelity part of a multi-fidelity
    /// set): greedy maximin, stratified over N, same case ids and inputs.
    Subset(SubsetArgs),
    /// Join shard directories into one snapshot CSV (identical to a single run).
    Merge(MergeArgs),
    /// Re-simulate random cases of a snapshot CSV and compare with the stored values.
    Verify(VerifyArgs),
}

/// Case runner.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum RunnerArg {
    /// The FE model.
    Fe,
    /// A closed-form stand-in: dry runs of the distribution machinery (tests, Slurm checks).
    Analytic,
}

/// `snapshots run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Plan file (from `snapshots plan`).
    #[arg(long)]
    pub plan: PathBuf,
    /// The share of the plan: k/n, 1 ≤ k ≤ n.
    #[arg(long, default_value = "1/1")]
    pub shard: String,
    /// Output (shard) directory.
    #[arg(long)]
    pub out: PathBuf,
    /// Cases run in parallel (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Case runner.
    #[arg(long, value_enum, default_value = "fe")]
    pub runner: RunnerArg,
    /// Analytic runner only: sleep per case (ms).
    #[arg(long, default_value_t = 0)]
    pub delay_ms: u64,
    /// Analytic runner only: every how many cases one fails half-way (0: none).
    #[arg(long, default_value_t = 0)]
    pub fail_every: usize,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Run the cases that failed again (e.g. after a solver improvement); their files are
    /// replaced atomically, finished cases are kept.
    #[arg(long)]
    pub retry_failed: bool,
    /// Check plan, shard and directory and print how far the shard is; run nothing.
    #[arg(long)]
    pub dry_run: bool,
}

/// `snapshots plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    /// Number of cases.
    #[arg(long)]
    pub cases: usize,
    /// Seed of the Latin hypercube.
    #[arg(long, default_value_t = 2024)]
    pub seed: u64,
    /// Output plan file.
    #[arg(long)]
    pub out: PathBuf,
    /// Values of N (comma list or a..b), e.g. 9,11,13.
    #[arg(long, default_value = "7..15")]
    pub n_values: String,
    /// Wall thickness range lo,hi (mm).
    #[arg(long, default_value = "1.2,2.8")]
    pub t_range: String,
    /// Initial shear modulus range lo,hi (MPa), log-uniform.
    #[arg(long, default_value = "1.5,15")]
    pub mu0_range: String,
    /// Range of term 1's share of μ0, inside (0, 1).
    #[arg(long, default_value = "0.02,0.95")]
    pub share_range: String,
    /// Range of α1 (> 0).
    #[arg(long, default_value = "1,8")]
    pub alpha1_range: String,
    /// Range of α2 (< 0).
    #[arg(long, default_value = "-3,-0.004", allow_hyphen_values = true)]
    pub alpha2_range: String,
    /// Pressure ramp in bar: a comma list, or max:step (e.g. 3.5:0.25 = 0, 0.25, …, 3.5).
    #[arg(long, default_value = "3.5:0.25", allow_hyphen_values = true)]
    pub pressures: String,
    /// Mesh level: coarse | standard | fine.
    #[arg(long, default_value = "standard")]
    pub mesh: String,
    /// Element size override (mm).
    #[arg(long)]
    pub element_size: Option<f64>,
    /// Bulk modulus as a multiple of μ0.
    #[arg(long, default_value_t = surrogate::fe::material::DEFAULT_BULK_RATIO)]
    pub bulk_ratio: f64,
    /// Switch self-weight off.
    #[arg(long)]
    pub no_gravity: bool,
    /// An effect fixed for every case, NAME=VALUE (repeatable; `surrogate effects` lists the
    /// names, units and ranges).
    #[arg(long, value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub effect: Vec<String>,
    /// An effect sampled as one more axis of the Latin hypercube, NAME=LO,HI (repeatable),
    /// uniform in [LO, HI] (inside the effect's range), e.g. --effect-range wall_bias=-0.2,0.2.
    #[arg(long, value_name = "NAME=LO,HI", allow_hyphen_values = true)]
    pub effect_range: Vec<String>,
    /// The unstated dimensions every case is built with: `as_modelled`, `identified` or a geometry preset
    /// file (`identify` writes one, `geometry.json`). It is stored in the plan, and T is
    /// sampled up to each N's buildability limit with it.
    #[arg(long, default_value = "as_modelled")]
    pub geometry: String,
}

/// `snapshots merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard directories.
    #[arg(long, num_args = 1.., required = true)]
    pub from: Vec<PathBuf>,
    /// Output CSV (the plan is copied beside it as <stem>.plan.json).
    #[arg(long)]
    pub out: PathBuf,
    /// Merge the finished cases only (to train on a set still running); missing cases are
    /// reported, not an error.
    #[arg(long)]
    pub partial: bool,
}

/// `snapshots verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Snapshot CSV (from `snapshots merge`).
    #[arg(long)]
    pub data: PathBuf,
    /// Plan of the data (default: the copy beside it, <stem>.plan.json).
    #[arg(long)]
    pub plan: Option<PathBuf>,
    /// Number of cases to re-simulate.
    #[arg(long, default_value_t = 3)]
    pub cases: usize,
    /// Seed of the choice of cases.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Largest accepted absolute difference.
    #[arg(long, default_value_t = 1e-9)]
    pub tolerance: f64,
    /// Case runner (as used for the data).
    #[arg(long, value_enum, default_value = "fe")]
    pub runner: RunnerArg,
    /// Analytic runner only: every how many cases one fails half-way (as used for the data).
    #[arg(long, default_value_t = 0)]
    pub fail_every: usize,
}

/// Runs the subcommand.
pub fn run(a: SnapshotsArgs) -> Result<()> {
    match (a.command, a.run) {
        (Some(SnapshotsCommand::Plan(p)), _) => plan(*p),
        (Some(SnapshotsCommand::Subset(s)), _) => subset(s),
        (Some(SnapshotsCommand::Run(r)), _) | (None, Some(r)) => run_plan(r),
        (Some(SnapshotsCommand::Merge(m)), _) => merge_dirs(m),
        (Some(SnapshotsCommand::Verify(v)), _) => verify(v),
        (None, None) => anyhow::bail!(
            "give a subcommand (plan, run, merge, verify) or --plan PLAN --shard k/n --out DIR"
        ),
    }
}

/// `lo,hi` of flag `flag`.
fn pair(flag: &str, s: &str) -> Result<[f64; 2]> {
    let v: Vec<&str> = s.split(',').collect();
    let parse = |t: &str| {
        t.trim().parse::<f64>().with_context(|| {
            format!(
                "--{flag} {s:?}: {:?} is not a number (expected lo,hi)",
                t.trim()
            )
        })
    };
    anyhow::ensure!(v.len() == 2, "--{flag} {s:?}: expected two numbers lo,hi");
    Ok([parse(v[0])?, parse(v[1])?])
}

/// `9,11,13` or `7..15`.
fn n_values(s: &str) -> Result<Vec<usize>> {
    let bad =
        || format!("--n-values {s:?}: expected a comma list of integers or a..b (e.g. 7..15)");
    if let Some((a, b)) = s.split_once("..") {
        let a: usize = a.trim().parse().with_context(bad)?;
        let b: usize = b.trim().parse().with_context(bad)?;
        return Ok((a..=b).collect());
    }
    s.split(',')
        .map(|t| t.trim().parse().with_context(bad))
        .collect()
}

/// `NAME=LO,HI` items of `--effect-range`, each name once (the plan checks names and ranges).
fn effect_ranges(items: &[String]) -> Result<BTreeMap<String, [f64; 2]>> {
    let mut out = BTreeMap::new();
    for item in items {
        let (name, r) = item.split_once('=').with_context(|| {
            format!("--effect-range {item:?}: expected NAME=LO,HI, e.g. wall_bias=-0.2,0.2")
        })?;
        let r = pair("effect-range", r)?;
        anyhow::ensure!(
            out.insert(name.trim().to_string(), r).is_none(),
            "--effect-range {name}: given twice, expected each effect at most once"
        );
    }
    Ok(out)
}

/// The plan's geometry preset: none for `as_modelled` (the plan then reads as before the
/// field existed, with the same hash), the preset otherwise.
fn plan_geometry(name: &str) -> Result<Option<Geometry>> {
    let g = Geometry::from_name(name).with_context(|| format!("--geometry {name}"))?;
    Ok((!g.is_as_modelled()).then_some(g))
}

/// A comma list, or `max:step` from 0.
fn plan(a: PlanArgs) -> Result<()> {
    let ranges = Ranges {
        n_bellows: n_values(&a.n_values)?,
        wall_thickness_mm: pair("t-range", &a.t_range)?,
        mu0_mpa: pair("mu0-range", &a.mu0_range)?,
        term1_share: pair("share-range", &a.share_range)?,
        alpha1: pair("alpha1-range", &a.alpha1_range)?,
        alpha2: pair("alpha2-range", &a.alpha2_range)?,
        effects: effect_ranges(&a.effect_range)?,
    };
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let settings = PlanSettings {
        pressures_bar: surrogate::fe::simulate::parse_pressures(&a.pressures)?,
        gravity: !a.no_gravity,
        mesh: MeshOptions {
            level,
            element_size: a.element_size,
            wall_elements: None,
        },
        bulk_ratio: a.bulk_ratio,
        effects: Effects::parse(a.effect.iter().map(String::as_str))?,
        geometry: plan_geometry(&a.geometry)?,
        ..PlanSettings::default()
    };
    let plan = Plan::generate(a.cases, a.seed, ranges, settings)?;
    crate::files::write_file(&a.out, plan.pretty_json().as_bytes())?;
    let inside: Vec<String> = plan
        .literature_in_sampled_domain()?
        .into_iter()
        .map(|(name, outside)| {
            if outside.is_empty() {
                format!("{name} inside")
            } else {
                let v: Vec<String> = outside.iter().map(|v| v.to_string()).collect();
                format!("{name} OUTSIDE ({})", v.join("; "))
            }
        })
        .collect();
    eprintln!(
        "wrote {}: {} cases, {} pressures, plan hash {}; literature Ogden sets in the sampled domain \
         (what a surrogate trained on this plan accepts): {}",
        a.out.display(),
        plan.cases.len(),
        plan.settings.pressures_bar.len(),
        plan.hash(),
        inside.join(", ")
    );
    Ok(())
}

fn subset(a: SubsetArgs) -> Result<()> {
    let parent = Plan::read(&a.plan)?;
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let mesh = MeshOptions {
        level,
        element_size: a.element_size,
        wall_elements: None,
    };
    let plan = parent.subset(a.cases, mesh)?;
    crate::files::write_file(&a.out, plan.pretty_json().as_bytes())?;
    let ids: Vec<String> = plan.cases.iter().map(|c| c.id.to_string()).collect();
    eprintln!(
        "wrote {}: {} of the {} cases of plan {} on the {} mesh, plan hash {}; ids {}",
        a.out.display(),
        plan.cases.len(),
        parent.cases.len(),
        parent.hash(),
        a.mesh,
        plan.hash(),
        ids.join(",")
    );
    Ok(())
}

fn run_plan(a: RunArgs) -> Result<()> {
    let plan = Plan::read(&a.plan)?;
    let shard: Shard = a.shard.parse()?;
    if let Some(t) = a.threads {
        anyhow::ensure!(t >= 1, "--threads {t}: expected at least 1");
    }
    if a.dry_run {
        let st = shard_status(&plan, &a.out, shard)?;
        eprintln!(
            "shard {shard} of {} (plan {}): {} of {} cases finished in {}, {} failed, {} \
             unconverged rows",
            a.plan.display(),
            plan.hash(),
            st.finished,
            st.cases,
            a.out.display(),
            st.failed.len(),
            st.unconverged_rows
        );
        for (id, error) in &st.failed {
            eprintln!("  case {id} failed: {error}");
        }
        return Ok(());
    }
    let analytic = AnalyticRunner {
        delay: Duration::from_millis(a.delay_ms),
        fail_every: a.fail_every,
    };
    let runner: &dyn CaseRunner = match a.runner {
        RunnerArg::Fe => &fe_runner,
        RunnerArg::Analytic => &analytic,
    };
    let n = plan.shard_cases(shard).len();
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(0)
    };
    bar.set_style(ProgressStyle::with_template(
        "{msg} [{bar:30}] {pos}/{len} cases, {elapsed_precise} elapsed, ETA {eta_precise}",
    )?);
    bar.set_message(format!("shard {shard}"));
    // in a batch log (Slurm, nohup) the bar is not drawn: one line per finished case instead
    let lines = !a.quiet && !std::io::stderr().is_terminal();
    let started = std::time::Instant::now();
    let progress = |p: Progress| {
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(format!(
            "shard {shard} ({} already done, {} failed)",
            n - p.total,
            p.failed
        ));
        if lines && p.done > 0 {
            let elapsed = started.elapsed().as_secs_f64();
            let eta = elapsed / p.done as f64 * (p.total - p.done) as f64;
            eprintln!(
                "shard {shard}: {}/{} cases of this run finished ({} failed, {} done before), \
                 {} elapsed, ETA {}",
                p.done,
                p.total,
                p.failed,
                n - p.total,
                hms(elapsed),
                hms(eta)
            );
        }
    };
    let options = RunOptions {
        shard,
        threads: a.threads,
        retry_failed: a.retry_failed,
    };
    let summary = run_shard(&plan, &a.out, &options, runner, &progress).with_context(|| {
        format!(
            "running shard {shard} of {} into {}",
            a.plan.display(),
            a.out.display()
        )
    })?;
    bar.finish_and_clear();
    eprintln!("{summary}");
    Ok(())
}

/// `h:mm:ss`.
fn hms(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
}

fn merge_dirs(a: MergeArgs) -> Result<()> {
    let s = merge_with(&a.from, &a.out, a.partial)?;
    eprintln!(
        "merged {} shard directories into {}: {} cases ({} failed), {} rows ({} unconverged), plan {}{}",
        a.from.len(),
        a.out.display(),
        s.cases,
        s.failed_cases,
        s.rows,
        s.unconverged_rows,
        s.plan_hash,
        if a.partial {
            format!("; {} plan cases not finished (partial merge)", s.missing_cases)
        } else {
            String::new()
        }
    );
    Ok(())
}

fn verify(a: VerifyArgs) -> Result<()> {
    anyhow::ensure!(
        a.tolerance.is_finite() && a.tolerance >= 0.0,
        "--tolerance {}: expected a finite number ≥ 0",
        a.tolerance
    );
    let plan_path = a.plan.clone().unwrap_or_else(|| sidecar_path(&a.data));
    let plan = Plan::read(&plan_path)?;
    let analytic = AnalyticRunner {
        delay: Duration::ZERO,
        fail_every: a.fail_every,
    };
    let runner: &dyn CaseRunner = match a.runner {
        RunnerArg::Fe => &fe_runner,
        RunnerArg::Analytic => &analytic,
    };
    let checks = resimulate(&a.data, &plan, a.cases, a.seed, runner)?;
    let mut ok = true;
    for c in &checks {
        let pass = c.same_convergence && c.max_abs_diff <= a.tolerance;
        ok &= pass;
        eprintln!(
            "{}: max |stored - re-simulated| = {:e}, converged flags {}: {}",
            case_name(c.id),
            c.max_abs_diff,
            if c.same_convergence {
                "equal"
            } else {
                "DIFFER"
            },
            if pass { "ok" } else { "FAIL" }
        );
    }
    anyhow::ensure!(
        ok,
        "re-simulated values differ by more than {}",
        a.tolerance
    );
    eprintln!("{} cases reproduce within {:e}", checks.len(), a.tolerance);
    Ok(())
}
