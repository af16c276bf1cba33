//! The settings of a refinement, validated before any FE runs.

use crate::calibrate::fit::CalibrationSettings;
use crate::calibrate::CalibrateError;
use crate::rom::TrainConfig;

/// Settings of [`refine`](crate::calibrate::refine::refine).
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
    /// surrogate; see [`data_space_shift`](crate::calibrate::refine::data_space_shift)). 0
    /// switches the test off.
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

impl RefineSettings {
    /// At least one round; a finite, non-negative data tolerance.
    pub(super) fn validate(&self) -> Result<(), CalibrateError> {
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
