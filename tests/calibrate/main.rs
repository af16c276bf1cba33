//! The calibrator (`surrogate::calibrate`) on recordings made by the FE model. The command-line
//! tests are in `tests/cli/`.

mod calibrate;
mod twin;
