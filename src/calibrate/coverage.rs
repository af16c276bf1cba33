//! How often the reported interval of μ0 covers the truth.
//!
//! The recovery of `tests/calibrate/calibrate.rs` repeated over many noise seeds: recordings
//! made by a reference (FE outputs at a known material, [`TrueOutputs`]) with noise at the
//! experiments' standard deviations ([`noisy_recordings`]), each fitted through a surrogate,
//! and the profile interval of `μ0` of every seed checked against the true `μ0` at the same
//! level twice:
//!
//! ```text
//!   projection of the joint region   Δχ²(μ0) ≤ χ²₄(level) ŝ²   (what the reports give)
//!   pointwise profile interval       Δχ²(μ0) ≤ χ²₁(level) ŝ²   (IdentifySettings::simultaneous = false)
//! ```
//!
//! A valid interval at level `1 − a` covers the truth in about `1 − a` of the seeds. The
//! projection covers all four coordinates at once, so it is wider than a pointwise interval
//! needs to be for one of them; the pointwise interval is the narrower claim. Neither knows of
//! the surrogate's error against the reference that made the data.

use serde::{Deserialize, Serialize};

use super::fit::{calibrate, CalibrationSettings};
use super::objective::{Recordings, Weights};
use super::optimise::MultistartSettings;
use super::synthetic::{noisy_recordings, TrueOutputs};
use super::CalibrateError;
use crate::rom::Surrogate;

/// Settings of [`interval_coverage`].
#[derive(Clone, Debug)]
pub struct CoverageSettings {
    /// The noise seeds, one calibration (and one check of each interval) per seed.
    pub seeds: Vec<u64>,
    /// Confidence level of both intervals.
    pub level: f64,
    /// Objective (`tip,force`), as `calibrate --objective` takes it.
    pub objective: String,
    /// Multistart starts per calibration.
    pub starts: usize,
}

impl Default for CoverageSettings {
    /// Seeds 1 … 30 at 95 %, objective `tip,force`, 12 starts (the recovery test's settings).
    fn default() -> Self {
        CoverageSettings {
            seeds: (1..=30).collect(),
            level: 0.95,
            objective: "tip,force".into(),
            starts: 12,
        }
    }
}

/// One seed: the fitted `μ0`, its two intervals and whether each covers the truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeedCoverage {
    /// Noise seed.
    pub seed: u64,
    /// Fitted `μ0` (MPa).
    pub mu0_mpa: f64,
    /// `χ²/dof` at the optimum.
    pub chi2_per_dof: f64,
    /// Projection of the joint region onto `μ0` (MPa).
    pub projection: [f64; 2],
    /// Pointwise profile interval of `μ0` (MPa).
    pub pointwise: [f64; 2],
    /// Whether the projection holds the true `μ0`.
    pub projection_covers: bool,
    /// Whether the pointwise interval holds the true `μ0`.
    pub pointwise_covers: bool,
}

/// The coverage over all seeds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IntervalCoverage {
    /// The true `μ0` (MPa).
    pub true_mu0_mpa: f64,
    /// Confidence level of both intervals.
    pub level: f64,
    /// Objective.
    pub objective: String,
    /// Multistart starts per calibration.
    pub starts: usize,
    /// Every seed, in the order given.
    pub seeds: Vec<SeedCoverage>,
    /// Seeds whose projection covers the true `μ0`.
    pub projection_covered: usize,
    /// Seeds whose pointwise interval covers the true `μ0`.
    pub pointwise_covered: usize,
}

/// Calibrates `model` on noisy recordings of `truth` (noise at the scatter of `noise_from`)
/// for every seed of `settings`, once with each kind of interval, and counts the seeds whose
/// interval of `μ0` holds `true_mu0_mpa`. `progress` sees each seed as it is done.
///
/// # Errors
/// A bad objective or level, a configuration of `truth` without a row in `noise_from`, or a
/// calibration error.
pub fn interval_coverage(
    model: &Surrogate,
    truth: &[TrueOutputs],
    true_mu0_mpa: f64,
    noise_from: &Recordings,
    settings: &CoverageSettings,
    progress: &dyn Fn(&SeedCoverage),
) -> Result<IntervalCoverage, CalibrateError> {
    let mut base = CalibrationSettings {
        weights: Weights::parse(&settings.objective)?,
        multistart: MultistartSettings {
            starts: settings.starts,
            ..MultistartSettings::default()
        },
        ..CalibrationSettings::default()
    };
    base.identify.level = settings.level;
    let mut seeds = Vec::with_capacity(settings.seeds.len());
    for &seed in &settings.seeds {
        let rec = noisy_recordings(truth, noise_from, seed, "synthetic")?;
        let interval = |simultaneous: bool| {
            let mut s = base.clone();
            s.identify.simultaneous = simultaneous;
            calibrate(model, &rec, &s, &|_| {})
        };
        let joint = interval(true)?;
        let pointwise = interval(false)?.identifiability.profiles[0].interval;
        let projection = joint.identifiability.profiles[0].interval;
        let covers = |i: [f64; 2]| i[0] <= true_mu0_mpa && true_mu0_mpa <= i[1];
        let one = SeedCoverage {
            seed,
            mu0_mpa: joint.best.mu0_mpa(),
            chi2_per_dof: joint.chi2 / joint.identifiability.dof as f64,
            projection,
            pointwise,
            projection_covers: covers(projection),
            pointwise_covers: covers(pointwise),
        };
        progress(&one);
        seeds.push(one);
    }
    Ok(IntervalCoverage {
        true_mu0_mpa,
        level: settings.level,
        objective: settings.objective.clone(),
        starts: settings.starts,
        projection_covered: seeds.iter().filter(|s| s.projection_covers).count(),
        pointwise_covered: seeds.iter().filter(|s| s.pointwise_covers).count(),
        seeds,
    })
}
