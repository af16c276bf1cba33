//! The calibrator (`surrogate::calibrate`) on recordings made by the FE model, the recording
//! readers on bad files (`tests/data/bad_recordings/`) and random ones, and the diagnoser's
//! Locate stage (`surrogate::diagnose`) on recordings with a planted residual, and the blind
//! study's noise (`study_noise`). The command-line tests are in `tests/cli/`.

mod approx_error;
mod bad_recordings;
mod calibrate;
mod diagnose;
mod fuzz_recordings;
mod mesh_error;
mod refine;
mod refit;
mod study_noise;
mod twin;

/// The diagnoser's settings of the Model-and-show and mesh-error tests: the `tip` objective,
/// 6 starts, 4 profile points.
pub fn quick_diagnose_settings() -> surrogate::diagnose::DiagnoseSettings {
    let mut c = surrogate::calibrate::CalibrationSettings {
        weights: surrogate::calibrate::Weights::parse("tip").unwrap(),
        multistart: surrogate::calibrate::optimise::MultistartSettings {
            starts: 6,
            ..surrogate::calibrate::optimise::MultistartSettings::default()
        },
        ..surrogate::calibrate::CalibrationSettings::default()
    };
    c.identify.profile_points = 4;
    surrogate::diagnose::DiagnoseSettings {
        calibration: c,
        ..surrogate::diagnose::DiagnoseSettings::default()
    }
}
