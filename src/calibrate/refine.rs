//! Adaptive refinement: where the surrogate and the FE model disagree at the calibrated set,
//! the FE runs at that set become training cases, the surrogate is retrained and the material
//! refitted, round after round, until the two agree.
//!
//! ```text
//!   model M₀, its training set S₀ ──► calibrate ──► θ₀
//!   round k = 1, 2, …:
//!     FE ramps of every recorded design at θ_{k−1} (the training plan's settings and pressures,
//!     run as a snapshot plan: cached per case, resumable) ──► compare with M_{k−1} at θ_{k−1}
//!       agree (every |FE − surrogate| ≤ 2σ of the surrogate)      ──► stop: Agree
//!       k = max_rounds                                             ──► stop: MaxRounds
//!     S_k = S_{k−1} + the round's cases ──► retrain M_k ──► calibrate ──► θ_k
//!       θ_k = θ_{k−1} (as reported, 4 significant digits)          ──► stop: OptimumUnchanged
//!       M_k(θ_k) − M_k(θ_{k−1}) within noise on every recorded number ──► stop: PredictionsUnchanged
//! ```
//!
//! The last test is the one that ends a refinement whose data leave a direction of the
//! parameters undetermined: the refit then walks along that valley from round to round (another
//! split of the initial shear modulus between the two Ogden terms, say) while nothing the
//! recordings see changes. Through the retrained surrogate `M_k`, every recorded number
//! (tip, angle, force, markers: whatever the recordings hold, at the calibration's
//! configurations) is predicted at the refit `θ_k` and at the verified `θ_{k−1}`; when no
//! prediction moves by more than `data_tolerance` of its standard deviation (the calibrator's
//! noise model, [`super::objective`]), the two sets are the same answer to these recordings,
//! and the FE at `θ_{k−1}` (already run) verifies it ([`data_space_shift`]).
//!
//! The FE cases of a round are a [`Plan`] with the training plan's settings (mesh, pressures,
//! solver, contact, gravity, bulk ratio), so they are training cases of the same fidelity as the
//! rest; their ids are `10000·k + j` (the recorded designs in (N, T) order), apart from the
//! training plan's. Each round's directory is a snapshot shard directory
//! ([`crate::snapshots::run::run_shard`]): an interrupted refinement resumes where it stopped.
//!
//! A multi-fidelity model (a low-fidelity set corrected by a high-fidelity one,
//! [`crate::rom::fidelity`]) is refined on both of its meshes: every round runs each design on
//! the low-fidelity mesh (`round_k_low/`) and on the high-fidelity one (`round_k/`, the FE the
//! surrogate is compared with), the pair is added to both sets under one id, and the correction
//! and the surrogate are retrained as `surrogate train --high-fidelity` does.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::baseline::BaselineRow;
use super::experiments::bending_error;
use super::fit::{calibrate, Calibration, CalibrationSettings};
use super::objective::{Evaluator, ObservationSet, Recordings, Selection, Weights};
use super::params::{OgdenSet, ParamSpace};
use super::verify::{compare_fe, FeVerification};
use super::CalibrateError;
use crate::fe::mesh::MeshOptions;
use crate::rom::data::{SnapshotRow, SnapshotSet};
use crate::rom::{train, Surrogate, TrainConfig, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::snapshots::merge::merge;
use crate::snapshots::plan::{Plan, PlannedCase};
use crate::snapshots::run::{run_shard, CaseRunner, Progress, RunOptions, RunSummary};
use crate::snapshots::shard::Shard;

/// Settings of [`refine`].
#[derive(Clone, Debug)]
pub struct RefineSettings {
    /// Largest number of FE rounds (each: every recorded design at the current optimum).
    pub max_rounds: usize,
    /// How every retrained surrogate is trained (the shipped models: 5 folds, 3 fold
    /// assignments).
    pub train: TrainConfig,
    /// The calibration of every round.
    pub calibration: CalibrationSettings,
    /// FE cases run in parallel (`None`: one per core).
    pub threads: Option<usize>,
    /// The refit counts as unchanged when no recorded number's prediction moves by more than
    /// this many of its standard deviations from the verified set's (through the retrained
    /// surrogate; see [`data_space_shift`]). 0 switches the test off.
    pub data_tolerance: f64,
}

impl Default for RefineSettings {
    fn default() -> Self {
        RefineSettings {
            max_rounds: 3,
            train: TrainConfig {
                repeats: 3,
                ..TrainConfig::default()
            },
            calibration: CalibrationSettings::default(),
            threads: None,
            data_tolerance: 1.0,
        }
    }
}

/// Why the refinement stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum RefineStop {
    /// Surrogate and FE agree at the last calibrated set (within 2σ of the surrogate).
    Agree,
    /// The retrained surrogate's optimum is the set the last round verified.
    OptimumUnchanged,
    /// The retrained surrogate's optimum moved, but not in anything the recordings see: its
    /// predictions there are within `data_tolerance` σ of those at the verified set on every
    /// recorded number.
    PredictionsUnchanged,
    /// `max_rounds` FE rounds were run and the two still disagree somewhere.
    MaxRounds,
}

impl RefineStop {
    /// In words.
    pub fn describe(self) -> &'static str {
        match self {
            RefineStop::Agree => "surrogate and FE agree at the calibrated set",
            RefineStop::OptimumUnchanged => {
                "the retrained surrogate's optimum is the set already verified by FE"
            }
            RefineStop::PredictionsUnchanged => {
                "the retrained surrogate's optimum predicts every recorded number within its \
                 noise of the set already verified by FE"
            }
            RefineStop::MaxRounds => "the largest number of rounds was reached",
        }
    }
}

/// One round: the FE at the set calibrated through the round's surrogate.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RefineRound {
    /// Round (1-based).
    pub round: usize,
    /// Training cases of the surrogate that calibrated this round's set.
    pub model_cases: usize,
    /// Its checksum and provenance.
    pub model: String,
    /// The set, as reported and run (4 significant digits).
    pub set: OgdenSet,
    /// `χ²` of the calibration through the surrogate.
    pub chi2: f64,
    /// Bounds of the training domain active at the set.
    pub active_bounds: Vec<String>,
    /// Mean BE (mm) through the surrogate.
    pub surrogate_mean_be_mm: f64,
    /// The FE at the set against the experiments and the surrogate.
    pub verification: FeVerification,
    /// FE cases run now (the rest were read from the round's directory).
    pub fe_cases_run: usize,
    /// FE wall time of the round (s).
    pub fe_wall_time_s: f64,
    /// The round's FE directory.
    pub fe_dir: PathBuf,
}

/// The whole refinement.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Refinement {
    /// Every round, in order.
    pub rounds: Vec<RefineRound>,
    /// Why it stopped.
    pub stop: RefineStop,
    /// The calibration through the last surrogate (the one retrained on every round's cases
    /// when the stop is [`RefineStop::OptimumUnchanged`]).
    pub last: Calibration,
    /// Training cases of the last surrogate.
    pub last_model_cases: usize,
    /// With [`RefineStop::OptimumUnchanged`] or [`RefineStop::PredictionsUnchanged`]: the
    /// last round's FE against the last surrogate (retrained on it), at the same set.
    pub final_check: Option<FeVerification>,
    /// After each retraining: how far the refit moved from the verified set in what the
    /// recordings see (through the retrained surrogate).
    #[serde(default)]
    pub shifts: Vec<DataSpaceShift>,
    /// Where the retrained surrogates are (`model_round_k.json`, trained after round k).
    pub models: Vec<PathBuf>,
}

impl Refinement {
    /// The round whose FE verifies the final set: the last one.
    pub fn final_round(&self) -> &RefineRound {
        self.rounds
            .last()
            .expect("a refinement has at least one round")
    }
}

/// How far a refit moved from a verified set in what the recordings see
/// ([`data_space_shift`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DataSpaceShift {
    /// After which round's retraining.
    pub round: usize,
    /// The verified set.
    pub from: OgdenSet,
    /// The refit.
    pub to: OgdenSet,
    /// Recorded numbers compared (every output the recordings hold, at the calibration's
    /// configurations).
    pub observations: usize,
    /// Largest `|ŷ(to) − ŷ(from)| / σ` over them.
    pub max_abs_z: f64,
    /// Root mean square of the same.
    pub rms_z: f64,
    /// The recorded number that moves most, in words.
    pub worst: String,
    /// `χ²` of every recorded number (weight 1) at `from` and at `to`.
    pub chi2_from: f64,
    /// See `chi2_from`.
    pub chi2_to: f64,
}

impl DataSpaceShift {
    /// In words.
    pub fn describe(&self) -> String {
        format!(
            "through the surrogate retrained after round {}, the refit {} moves the {} recorded \
             numbers by {:.2} σ rms from the verified set {} (at most {:.2} σ: {}); χ² of all \
             of them {:.1} → {:.1}",
            self.round,
            self.to.spec(),
            self.observations,
            self.rms_z,
            self.from.spec(),
            self.max_abs_z,
            self.worst,
            self.chi2_from,
            self.chi2_to
        )
    }
}

/// The unit-box point of `p` in the model's training domain, allowing the 4-digit rounding of
/// a reported set to sit a hair outside it.
fn unit_of(space: &ParamSpace, p: &OgdenSet) -> Result<[f64; 4], CalibrateError> {
    let u = space.unit(p);
    if u.iter().any(|v| !(-1e-3..=1.0 + 1e-3).contains(v)) {
        return Err(CalibrateError::input(
            "material set",
            p.spec(),
            "a set inside the surrogate's training domain",
        ));
    }
    Ok(u.map(|v| v.clamp(0.0, 1.0)))
}

/// How far `to` lies from `from` in what the recordings `rec` see, through `model`: every
/// recorded number (tip Uz and Uy, angle, force, marker components: the outputs `rec` holds)
/// at the configurations `selection` keeps is predicted at both sets, and the difference is
/// measured in its standard deviation (the calibrator's noise model: measurement and the
/// surrogate's own error in quadrature).
///
/// # Errors
/// A set outside the model's training domain (beyond the rounding of a reported set), or
/// observations that cannot be built (see [`ObservationSet::build`]).
pub fn data_space_shift(
    model: &Surrogate,
    rec: &Recordings,
    selection: &Selection,
    from: &OgdenSet,
    to: &OgdenSet,
    round: usize,
) -> Result<DataSpaceShift, CalibrateError> {
    let has_bending = !rec.bending.is_empty();
    let weights = Weights {
        tip: f64::from(u8::from(has_bending)),
        angle: f64::from(u8::from(has_bending)),
        force: f64::from(u8::from(!rec.force.is_empty())),
        markers: f64::from(u8::from(!rec.markers.is_empty())),
    };
    let set = ObservationSet::build(model, rec, &weights, selection)?;
    let space = ParamSpace::training_domain(model)?;
    let mut ev = Evaluator::new(model, &set, space);
    let (ua, ub) = (unit_of(ev.space(), from)?, unit_of(ev.space(), to)?);
    let a = ev.predictions(&ua)?;
    let b = ev.predictions(&ub)?;
    let (mut max, mut sum2, mut worst) = (0.0_f64, 0.0, 0);
    let (mut chi_a, mut chi_b) = (0.0, 0.0);
    for (i, o) in set.obs.iter().enumerate() {
        let sigma = o.sigma();
        let z = (b[i] - a[i]) / sigma;
        chi_a += ((a[i] - o.value) / sigma).powi(2);
        chi_b += ((b[i] - o.value) / sigma).powi(2);
        sum2 += z * z;
        if z.abs() > max {
            max = z.abs();
            worst = i;
        }
    }
    let n = set.obs.len();
    let w = &set.obs[worst];
    Ok(DataSpaceShift {
        round,
        from: *from,
        to: *to,
        observations: n,
        max_abs_z: max,
        rms_z: (sum2 / n.max(1) as f64).sqrt(),
        worst: format!(
            "{} at {}, {:+.3} (σ {:.3})",
            w.output.name(),
            w.config.label(),
            b[worst] - a[worst],
            w.sigma()
        ),
        chi2_from: chi_a,
        chi2_to: chi_b,
    })
}

/// The high-fidelity part of a multi-fidelity training set.
#[derive(Clone, Debug)]
pub struct HighFidelity {
    /// The high-fidelity snapshots (their cases pair with low-fidelity ones by id).
    pub snapshots: SnapshotSet,
    /// Their plan (the high-fidelity FE settings of the refinement).
    pub plan: Plan,
    /// Whether the low fidelity is warped in pressure before the correction.
    pub pressure_warp: bool,
}

/// The training set of a surrogate and the plan it was run with (for the FE settings of the
/// refinement cases).
#[derive(Clone, Debug)]
pub struct TrainingSet {
    /// The snapshots (validated rows); the low fidelity of a multi-fidelity set.
    pub snapshots: SnapshotSet,
    /// The plan of those snapshots (its settings are the refinement's).
    pub plan: Plan,
    /// The high-fidelity set that corrects them, if any.
    pub high: Option<HighFidelity>,
}

impl TrainingSet {
    /// Reads a snapshot CSV and its plan.
    ///
    /// # Errors
    /// I/O, format and validation errors of either file.
    pub fn read(snapshots: &Path, plan: &Path) -> Result<Self, CalibrateError> {
        let snapshots = SnapshotSet::read(snapshots)?;
        let plan = Plan::read(plan)
            .map_err(|e| CalibrateError::input("training plan", plan.display(), &e.to_string()))?;
        Ok(TrainingSet {
            snapshots,
            plan,
            high: None,
        })
    }

    /// Adds the high-fidelity set `snapshots` (its plan beside it) that corrects this one.
    ///
    /// # Errors
    /// As [`Self::read`].
    pub fn with_high_fidelity(
        self,
        snapshots: &Path,
        pressure_warp: bool,
    ) -> Result<Self, CalibrateError> {
        let h = Self::read(snapshots, &crate::snapshots::merge::sidecar_path(snapshots))?;
        Ok(TrainingSet {
            high: Some(HighFidelity {
                snapshots: h.snapshots,
                plan: h.plan,
                pressure_warp,
            }),
            ..self
        })
    }

    /// The set a model was trained on: its recorded sources (relative to `root`; for a
    /// multi-fidelity model the low- and the high-fidelity set) and the plans beside them
    /// (`<stem>.plan.json`).
    ///
    /// # Errors
    /// A source that is not a file, or the errors of [`Self::read`].
    pub fn of_model(model: &Surrogate, root: &Path) -> Result<Self, CalibrateError> {
        let file = |name: &str, what: &str| {
            let csv = root.join(name);
            if csv.is_file() {
                Ok(csv)
            } else {
                Err(CalibrateError::input(
                    what,
                    csv.display(),
                    "the snapshot CSV the model was trained on (give it explicitly)",
                ))
            }
        };
        match &model.training.correction {
            None => {
                let csv = file(&model.training.source, "model training source")?;
                Self::read(&csv, &crate::snapshots::merge::sidecar_path(&csv))
            }
            Some(c) => {
                // "<low> warped in pressure corrected by <high>" (`rom::fidelity`)
                let src = &model.training.source;
                let low = src
                    .split(" warped in pressure")
                    .next()
                    .and_then(|l| l.split(" corrected by ").next())
                    .unwrap_or(src);
                let csv = file(low, "model training source (low fidelity)")?;
                let high = file(&c.high_source, "model training source (high fidelity)")?;
                Self::read(&csv, &crate::snapshots::merge::sidecar_path(&csv))?
                    .with_high_fidelity(&high, c.pressure_warp.is_some())
            }
        }
    }
}

/// The planned case `id` of design `(n, t)` at the Ogden set `set`, without effects.
pub fn case_at(id: usize, n: usize, t: f64, set: &OgdenSet) -> PlannedCase {
    PlannedCase {
        id,
        n_bellows: n,
        wall_thickness_mm: t,
        mu1_mpa: set.mu1_mpa,
        alpha1: set.alpha1,
        mu2_mpa: set.mu2_mpa,
        alpha2: set.alpha2,
        effects: Default::default(),
    }
}

/// The FE cases of round `round` (1-based): every design of `designs` at `set`, with the
/// training plan's settings.
///
/// # Errors
/// A set or design the plan's validation refuses.
pub fn round_plan(
    training: &Plan,
    designs: &[(usize, f64)],
    set: &OgdenSet,
    round: usize,
) -> Result<Plan, CalibrateError> {
    let cases = designs
        .iter()
        .enumerate()
        .map(|(j, &(n, t))| case_at(10_000 * round + j, n, t, set))
        .collect();
    let plan = Plan {
        sampler: format!(
            "refinement round {round}: the recorded designs at the set calibrated through the surrogate"
        ),
        cases,
        ..training.clone()
    };
    plan.validate().map_err(|e| {
        CalibrateError::input("refinement plan", format!("round {round}"), &e.to_string())
    })?;
    Ok(plan)
}

/// The recorded designs `(N, T)`, sorted by N then T.
pub fn recorded_designs(rec: &Recordings) -> Vec<(usize, f64)> {
    let mut d: Vec<(usize, f64)> = rec
        .bending
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm))
        .chain(rec.force.iter().map(|r| (r.n_bellows, r.wall_thickness_mm)))
        .collect();
    d.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    d.dedup();
    d
}

/// Baseline rows (FE against the experiments) from snapshot rows of designs at one set: one per
/// bending record; a configuration the FE did not reach gets `NaN` values and a message.
pub fn baseline_rows(fe: &SnapshotSet, rec: &Recordings) -> Vec<BaselineRow> {
    let at = |n: usize, t: f64, p: f64| {
        fe.rows.iter().find(|r| {
            r.inputs.n_bellows as usize == n
                && (r.inputs.wall_thickness_mm - t).abs() < 1e-9
                && (r.pressure_bar - p).abs() < 1e-9
        })
    };
    rec.bending
        .iter()
        .map(|b| {
            let row = at(b.n_bellows, b.wall_thickness_mm, b.pressure_bar);
            let v = |q: usize| row.map_or(f64::NAN, |r| r.values[q]);
            let (uz, uy) = (v(Q_TIP_UZ), v(Q_TIP_UY));
            let f_exp = rec
                .force
                .iter()
                .find(|f| {
                    f.n_bellows == b.n_bellows
                        && f.wall_thickness_mm == b.wall_thickness_mm
                        && f.pressure_bar == b.pressure_bar
                })
                .map_or(f64::NAN, |f| f.force_n);
            BaselineRow {
                n_bellows: b.n_bellows,
                wall_thickness_mm: b.wall_thickness_mm,
                pressure_bar: b.pressure_bar,
                uz_exp_mm: b.tip_uz_mm,
                uz_sim_mm: uz,
                uy_exp_mm: b.tip_uy_mm,
                uy_sim_mm: uy,
                angle_exp_deg: b.angle_deg,
                angle_sim_deg: v(Q_ANGLE),
                be_mm: bending_error(b.tip_uz_mm, b.tip_uy_mm, uz, uy),
                force_exp_n: f_exp,
                force_sim_n: v(Q_FORCE),
                force_error_n: v(Q_FORCE) - f_exp,
                error: if row.is_some() {
                    String::new()
                } else {
                    "the FE case did not converge to this pressure".into()
                },
            }
        })
        .collect()
}

/// The surrogate retrained on the training set and the refinement cases of rounds `1..=k`
/// (`low` and `high`: every row so far), as the original was trained.
fn retrain(
    training: &TrainingSet,
    low: &[SnapshotRow],
    high: &[SnapshotRow],
    skipped: usize,
    k: usize,
    settings: &RefineSettings,
    stage: &dyn Fn(String),
) -> Result<Surrogate, CalibrateError> {
    let low_set = SnapshotSet {
        source: format!("{} + refinement rounds 1..{k}", training.snapshots.source),
        rows: low.to_vec(),
        skipped_unconverged: skipped,
    };
    let (set, correction) = match &training.high {
        Some(h) => {
            let high_set = SnapshotSet {
                source: format!("{} + refinement rounds 1..{k}", h.snapshots.source),
                rows: high.to_vec(),
                skipped_unconverged: h.snapshots.skipped_unconverged,
            };
            let (set, info) = crate::rom::fidelity::correct_low_fidelity(
                &low_set,
                &high_set,
                &settings.train,
                h.pressure_warp,
                false,
                &|line| stage(line.to_string()),
            )?;
            (set, Some(info))
        }
        None => (low_set, None),
    };
    let source = set.source.clone();
    let cases = set.into_cases()?;
    stage(format!(
        "retraining on {} cases (with the refinement rounds 1..{k})",
        cases.cases.len()
    ));
    let mut report = train(&cases, &source, skipped, &settings.train, &|_, _| {})?;
    report.surrogate.training.correction = correction;
    Ok(report.surrogate)
}

/// What [`refine`] reports as it goes.
#[derive(Clone, Debug)]
pub enum RefineEvent<'a> {
    /// A stage, in words.
    Stage(String),
    /// FE progress of a round.
    Fe {
        /// Round.
        round: usize,
        /// Cases done of total in this run.
        progress: Progress,
    },
    /// A round finished.
    Round(&'a RefineRound),
}

/// Runs the refinement (see the [module docs](self)) from `model`, trained on `training`, for
/// `rec`. The FE cases are run by `runner` (the FE: [`crate::snapshots::fe_runner::fe_runner`])
/// into `dir/round_k/`; the retrained surrogates are written to `dir/model_round_k.json`.
///
/// # Errors
/// Bad recordings or settings, a refinement case the plan refuses, FE directory errors
/// (another plan in a round directory), training errors.
pub fn refine(
    model: &Surrogate,
    training: &TrainingSet,
    rec: &Recordings,
    settings: &RefineSettings,
    runner: &dyn CaseRunner,
    dir: &Path,
    progress: &(dyn Fn(RefineEvent) + Sync),
) -> Result<Refinement, CalibrateError> {
    settings.validate()?;
    let fe = RoundFe {
        training,
        designs: recorded_designs(rec),
        runner,
        dir,
        threads: settings.threads,
        progress,
    };
    let mut r = Refining::start(model, &fe, rec, settings)?;
    let stop = loop {
        let k = r.rounds.len() + 1;
        let (last_rows, agree) = r.verify(&fe, k)?;
        if agree {
            break RefineStop::Agree;
        }
        if k == settings.max_rounds {
            break RefineStop::MaxRounds;
        }
        r.retrain(&fe, k)?;
        if let Some(stop) = r.settled(&fe, k, last_rows)? {
            break stop;
        }
    };
    Ok(r.finish(stop))
}

impl RefineSettings {
    /// At least one round; a finite, non-negative data tolerance.
    fn validate(&self) -> Result<(), CalibrateError> {
        if self.max_rounds == 0 {
            return Err(CalibrateError::input(
                "max_rounds",
                0,
                "at least 1 FE round",
            ));
        }
        if !(self.data_tolerance.is_finite() && self.data_tolerance >= 0.0) {
            return Err(CalibrateError::input(
                "data_tolerance",
                self.data_tolerance,
                "a finite number of standard deviations ≥ 0 (0: the test is off)",
            ));
        }
        Ok(())
    }
}

/// How the FE cases of a round are run: every recorded design, with the training plans'
/// settings, by `runner` into `dir`.
struct RoundFe<'a> {
    training: &'a TrainingSet,
    designs: Vec<(usize, f64)>,
    runner: &'a dyn CaseRunner,
    dir: &'a Path,
    threads: Option<usize>,
    progress: &'a (dyn Fn(RefineEvent<'_>) + Sync),
}

impl RoundFe<'_> {
    /// A stage, in words, to `progress`.
    fn stage(&self, s: String) {
        (self.progress)(RefineEvent::Stage(s));
    }

    /// The plan the surrogate is compared with: the high fidelity's of a multi-fidelity set.
    fn verify_plan(&self) -> &Plan {
        match &self.training.high {
            Some(h) => &h.plan,
            None => &self.training.plan,
        }
    }

    /// Runs `plan` (round `k`) into `fe_dir` (resuming what is there) and merges it into `csv`;
    /// the run's summary and the merged snapshots.
    fn run(
        &self,
        plan: &Plan,
        fe_dir: &Path,
        csv: &Path,
        k: usize,
    ) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
        let opts = RunOptions {
            shard: Shard::ALL,
            threads: self.threads,
            retry_failed: false,
        };
        let summary = run_shard(plan, fe_dir, &opts, self.runner, &|p| {
            (self.progress)(RefineEvent::Fe {
                round: k,
                progress: p,
            })
        })
        .map_err(|e| CalibrateError::input("refinement FE", fe_dir.display(), &e.to_string()))?;
        merge(&[fe_dir.to_path_buf()], csv)
            .map_err(|e| CalibrateError::input("refinement FE", csv.display(), &e.to_string()))?;
        Ok((summary, SnapshotSet::read(csv)?))
    }

    /// Round `k`'s low-fidelity FE of every design at `set` (in `round_k_low/`).
    fn low(&self, set: &OgdenSet, k: usize) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
        let low_dir = self.dir.join(format!("round_{k}_low"));
        self.stage(format!(
            "round {k}: low-fidelity FE of {} designs at {} in {}",
            self.designs.len(),
            set.spec(),
            low_dir.display()
        ));
        let plan = round_plan(&self.training.plan, &self.designs, set, k)?;
        let csv = self.dir.join(format!("round_{k}_low.csv"));
        self.run(&plan, &low_dir, &csv, k)
    }

    /// Round `k`'s FE of every design at `set` that the surrogate is compared with (in
    /// `round_k/`).
    fn verified(
        &self,
        set: &OgdenSet,
        k: usize,
    ) -> Result<(RunSummary, SnapshotSet), CalibrateError> {
        let fe_dir = self.dir.join(format!("round_{k}"));
        self.stage(format!(
            "round {k}: FE of {} designs at {} in {}",
            self.designs.len(),
            set.spec(),
            fe_dir.display()
        ));
        let plan = round_plan(self.verify_plan(), &self.designs, set, k)?;
        let csv = self.dir.join(format!("round_{k}.csv"));
        self.run(&plan, &fe_dir, &csv, k)
    }
}

/// A refinement under way: the current surrogate and its calibration, the training rows so
/// far, and what the rounds found.
struct Refining<'a> {
    rec: &'a Recordings,
    settings: &'a RefineSettings,
    current: Surrogate,
    cal: Calibration,
    /// Every training row so far (the low fidelity of a multi-fidelity set).
    low_rows: Vec<SnapshotRow>,
    /// Every high-fidelity row so far (empty without a high fidelity).
    high_rows: Vec<SnapshotRow>,
    skipped: usize,
    rounds: Vec<RefineRound>,
    models: Vec<PathBuf>,
    final_check: Option<FeVerification>,
    shifts: Vec<DataSpaceShift>,
}

impl<'a> Refining<'a> {
    /// The training set's rows and the calibration through `model`.
    fn start(
        model: &Surrogate,
        fe: &RoundFe<'_>,
        rec: &'a Recordings,
        settings: &'a RefineSettings,
    ) -> Result<Self, CalibrateError> {
        let cal = calibrate(model, rec, &settings.calibration, &|s| fe.stage(s.into()))?;
        let training = fe.training;
        Ok(Refining {
            rec,
            settings,
            current: model.clone(),
            cal,
            low_rows: training.snapshots.rows.clone(),
            high_rows: training
                .high
                .as_ref()
                .map(|h| h.snapshots.rows.clone())
                .unwrap_or_default(),
            skipped: training.snapshots.skipped_unconverged,
            rounds: Vec::new(),
            models: Vec::new(),
            final_check: None,
            shifts: Vec::new(),
        })
    }

    /// Round `k`: the FE of every design at the calibrated set (as reported), compared with
    /// the current surrogate and recorded; its cases join the training rows. Returns the FE
    /// rows of the comparison, and whether the two agree everywhere.
    fn verify(
        &mut self,
        fe: &RoundFe<'_>,
        k: usize,
    ) -> Result<(Vec<BaselineRow>, bool), CalibrateError> {
        let set = self.cal.best.rounded(4);
        let (mut cases_run, mut wall) = (0, 0.0);
        let high = fe.training.high.is_some();
        if high {
            let (summary, low) = fe.low(&set, k)?;
            cases_run += summary.done;
            wall += summary.wall_time_s;
            self.skipped += low.skipped_unconverged;
            self.low_rows.extend(low.rows);
        }
        let (summary, verified) = fe.verified(&set, k)?;
        let mesh: MeshOptions = fe.verify_plan().settings.mesh;
        let verification = compare_fe(
            &self.current,
            &set,
            mesh,
            baseline_rows(&verified, self.rec),
        )?;
        let round = RefineRound {
            round: k,
            model_cases: self.current.training.n_cases,
            model: self.cal.model.clone(),
            set,
            chi2: self.cal.chi2,
            active_bounds: self.cal.active_bounds.clone(),
            surrogate_mean_be_mm: self.cal.calibrated.mean_be_mm,
            verification,
            fe_cases_run: cases_run + summary.done,
            fe_wall_time_s: wall + summary.wall_time_s,
            fe_dir: fe.dir.join(format!("round_{k}")),
        };
        (fe.progress)(RefineEvent::Round(&round));
        let agree = round.verification.disagreements == 0;
        let rows = round
            .verification
            .rows
            .iter()
            .map(|r| r.fe.clone())
            .collect();
        self.rounds.push(round);
        if high {
            self.high_rows.extend(verified.rows);
        } else {
            self.skipped += verified.skipped_unconverged;
            self.low_rows.extend(verified.rows);
        }
        Ok((rows, agree))
    }

    /// After round `k`: the surrogate retrained on every row so far (written to
    /// `model_round_k.json`) and the material refitted through it.
    fn retrain(&mut self, fe: &RoundFe<'_>, k: usize) -> Result<(), CalibrateError> {
        let stage = |s: String| fe.stage(s);
        self.current = retrain(
            fe.training,
            &self.low_rows,
            &self.high_rows,
            self.skipped,
            k,
            self.settings,
            &stage,
        )?;
        let path = fe.dir.join(format!("model_round_{k}.json"));
        self.current.save(&path)?;
        self.models.push(path);
        self.cal = calibrate(&self.current, self.rec, &self.settings.calibration, &|s| {
            stage(s.into())
        })?;
        Ok(())
    }

    /// Whether the refit after round `k` ends the refinement: the same set as the round
    /// verified, or predictions within `data_tolerance` of it (then the round's FE rows
    /// `last_rows` are compared with the retrained surrogate).
    fn settled(
        &mut self,
        fe: &RoundFe<'_>,
        k: usize,
        last_rows: Vec<BaselineRow>,
    ) -> Result<Option<RefineStop>, CalibrateError> {
        let mesh: MeshOptions = fe.verify_plan().settings.mesh;
        let last = self.rounds.last().expect("a round was pushed");
        if self.cal.best.rounded(4) == last.set {
            self.final_check = Some(compare_fe(&self.current, &last.set, mesh, last_rows)?);
            return Ok(Some(RefineStop::OptimumUnchanged));
        }
        let selection = Selection {
            exclude: self.cal.excluded.clone(),
            ..self.settings.calibration.selection.clone()
        };
        let shift = data_space_shift(
            &self.current,
            self.rec,
            &selection,
            &last.set,
            &self.cal.best.rounded(4),
            k,
        )?;
        fe.stage(shift.describe());
        let unchanged = shift.max_abs_z <= self.settings.data_tolerance;
        self.shifts.push(shift);
        if unchanged {
            self.final_check = Some(compare_fe(&self.current, &last.set, mesh, last_rows)?);
            return Ok(Some(RefineStop::PredictionsUnchanged));
        }
        Ok(None)
    }

    fn finish(self, stop: RefineStop) -> Refinement {
        Refinement {
            rounds: self.rounds,
            stop,
            last_model_cases: self.current.training.n_cases,
            last: self.cal,
            final_check: self.final_check,
            shifts: self.shifts,
            models: self.models,
        }
    }
}

impl Refinement {
    /// The FE check of the final set: [`Self::final_check`] when the optimum stopped moving
    /// (the last round's FE against the surrogate retrained on it), else the last round's.
    pub fn final_verification(&self) -> &FeVerification {
        self.final_check
            .as_ref()
            .unwrap_or(&self.final_round().verification)
    }

    /// A Markdown account of the rounds.
    pub fn summary_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "## Adaptive refinement\n");
        let _ = writeln!(
            s,
            "Each round runs the FE model for every recorded design at the set calibrated through \
             the round's surrogate, compares the two (a disagreement: |FE − surrogate| > 2σ of \
             the surrogate in tip Uz, tip Uy or force), and where they disagree adds the FE cases \
             to the training set, retrains and refits.\n"
        );
        let _ = writeln!(
            s,
            "| round | training cases | μ1 (MPa) | α1 | μ2 (MPa) | α2 | χ² | mean BE surrogate (mm) | mean BE FE (mm) | mean F error FE (N) | mean \\|Δ\\| Uz, Uy (mm), F (N) | max \\|Δ\\| Uz, Uy (mm), F (N) | configurations in disagreement | FE cases run, wall time |"
        );
        let _ = writeln!(
            s,
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.rounds {
            let v = &r.verification;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {:.1} | {:.2} | {:.2} | {:+.3} | {:.2}, {:.2}, {:.3} | {:.2}, {:.2}, {:.3} | {} of {} | {} |",
                r.round,
                r.model_cases,
                r.set.mu1_mpa,
                r.set.alpha1,
                r.set.mu2_mpa,
                r.set.alpha2,
                r.chi2,
                r.surrogate_mean_be_mm,
                v.summary.mean_be_mm,
                v.summary.mean_force_error_n,
                v.mean_abs_sur_fe[0],
                v.mean_abs_sur_fe[1],
                v.mean_abs_sur_fe[2],
                v.max_abs_sur_fe[0],
                v.max_abs_sur_fe[1],
                v.max_abs_sur_fe[2],
                v.disagreements,
                v.rows.len(),
                if r.fe_cases_run == 0 {
                    "none (read back)".to_string()
                } else {
                    format!("{}, {:.0} s", r.fe_cases_run, r.fe_wall_time_s)
                }
            );
        }
        for sh in &self.shifts {
            let _ = writeln!(s, "\nAfter round {}: {}.", sh.round, sh.describe());
        }
        let _ = writeln!(s, "\nStopped: {}.", self.stop.describe());
        if let Some(c) = &self.final_check {
            let _ = writeln!(
                s,
                "\nThe surrogate retrained on every round ({} cases) against the last round's FE at \
                 the same set: mean |Δ| {:.2}, {:.2} mm, {:.3} N; max {:.2}, {:.2} mm, {:.3} N; {} of \
                 {} configurations beyond 2σ.",
                self.last_model_cases,
                c.mean_abs_sur_fe[0],
                c.mean_abs_sur_fe[1],
                c.mean_abs_sur_fe[2],
                c.max_abs_sur_fe[0],
                c.max_abs_sur_fe[1],
                c.max_abs_sur_fe[2],
                c.disagreements,
                c.rows.len()
            );
        }
        let f = self.final_verification();
        let _ = writeln!(
            s,
            "\nFinal set {}: FE mean BE {:.2} mm (median {:.2}), mean force error {:+.3} N over {} configurations.",
            self.final_round().set.spec(),
            f.summary.mean_be_mm,
            f.summary.median_be_mm,
            f.summary.mean_force_error_n,
            f.rows.len()
        );
        s
    }
}
