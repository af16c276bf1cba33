//! The settings of a box extension, validated before any FE runs.

use super::limits::PhysicalLimits;
use crate::calibrate::fit::CalibrationSettings;
use crate::calibrate::CalibrateError;
use crate::rom::TrainConfig;

/// The most cases a round may add: its ids are `10000·k + 5000 + j`, `j < 5000`
/// ([module docs](super)).
pub const MAX_CASES_PER_ROUND: usize = 5000;

/// Settings of [`extend_box`](super::extend_box).
#[derive(Clone, Debug)]
pub struct ExtendSettings {
    /// Largest number of extension rounds (each: new cases, retraining, refit).
    pub max_rounds: usize,
    /// How far a pressed bound moves, as a fraction of its coordinate's current range (in
    /// `ln μ0` for `μ0`).
    pub step: f64,
    /// New cases per round, shared among the slabs by volume and stratified over the model's
    /// values of `N` (at least 2 per value).
    pub cases_per_round: usize,
    /// Seed of the rounds' Latin hypercubes (slab `t` of round `k`: `seed + 100·k + t`).
    pub seed: u64,
    /// How far the box may ever reach.
    pub limits: PhysicalLimits,
    /// How every retrained surrogate is trained (as the original was: the shipped models use
    /// 5 folds and 3 fold assignments).
    pub train: TrainConfig,
    /// The calibration of every round.
    pub calibration: CalibrationSettings,
    /// FE cases run in parallel (`None`: one per core).
    pub threads: Option<usize>,
}

impl Default for ExtendSettings {
    fn default() -> Self {
        ExtendSettings {
            max_rounds: 3,
            step: 0.5,
            cases_per_round: 36,
            seed: 2024,
            limits: PhysicalLimits::default(),
            train: TrainConfig {
                repeats: 3,
                ..TrainConfig::default()
            },
            calibration: CalibrationSettings::default(),
            threads: None,
        }
    }
}

impl ExtendSettings {
    /// At least one round, a finite step > 0, at least 2 cases per value of `N`
    /// (`n_values` of them) and at most [`MAX_CASES_PER_ROUND`], a usable thread count,
    /// valid limits.
    ///
    /// # Errors
    /// [`CalibrateError::Input`] naming the setting (`max_rounds`, `step`,
    /// `cases_per_round`, `threads`, a limit).
    pub fn validate(&self, n_values: usize) -> Result<(), CalibrateError> {
        if self.max_rounds == 0 {
            return Err(CalibrateError::input(
                "max_rounds",
                0,
                "at least 1 extension round",
            ));
        }
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(CalibrateError::input(
                "step",
                self.step,
                "a finite fraction > 0 of the pressed coordinate's range",
            ));
        }
        let least = 2 * n_values.max(1);
        if !(least..=MAX_CASES_PER_ROUND).contains(&self.cases_per_round) {
            return Err(CalibrateError::input(
                "cases_per_round",
                self.cases_per_round,
                &format!(
                    "{least} ..= {MAX_CASES_PER_ROUND} (at least 2 per trained value of N: \
                     {n_values} of them)"
                ),
            ));
        }
        if self.threads == Some(0) {
            return Err(CalibrateError::input(
                "threads",
                0,
                "at least 1 FE case at a time",
            ));
        }
        self.limits.validate()
    }
}
