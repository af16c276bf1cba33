//! The calibrator (`surrogate::calibrate`) on recordings made by the FE model, and the
//! diagnoser's Locate stage (`surrogate::diagnose`) on recordings with a planted residual. The
//! command-line tests are in `tests/cli/`.

mod calibrate;
mod diagnose;
mod mesh_error;
mod refit;
mod twin;
