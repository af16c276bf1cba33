//! The calibrator (`surrogate::calibrate`) on recordings made by the FE model, the recording
//! readers on bad files (`tests/data/bad_recordings/`) and random ones. The diagnoser's tests
//! are in `tests/diagnose/`, the command-line tests in `tests/cli/`.

mod analytic;
mod bad_recordings;
mod calibrate;
mod extend;
mod fuzz_recordings;
mod refine;
mod twin;
