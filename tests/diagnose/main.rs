//! The diagnoser (`surrogate::diagnose`): the Locate stage on recordings with a planted
//! residual (`diagnose`), Model and show (`refit`), the sensitivities against the model they are
//! used with (`built_with`), the model's mesh error (`mesh_error`) and approximation error
//! (`approx_error`) as candidates, and the blind study's plan, scoring, noise and closed loop
//! (`study`, `study_noise`, `closed_loop`). The command-line tests are in `tests/cli/`.

mod approx_error;
mod built_with;
mod closed_loop;
mod diagnose;
mod mesh_error;
mod refit;
mod study;
mod study_noise;

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
