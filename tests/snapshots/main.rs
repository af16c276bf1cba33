//! The snapshot machinery (`surrogate::snapshots`) with the real FE runner. The tests that run
//! the command line are in `tests/cli/`.

mod snapshots_fe;
