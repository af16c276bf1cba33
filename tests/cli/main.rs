//! The `surrogate` program: every test that runs the binary (`simulate`, `snapshots`, `train`,
//! `predict`, `export`, `calibrate`, `diagnose`, the README recipes) and the figures it draws.
//! Built with the `cli` feature only.
//!
//! One test binary; each module is one subject.

mod common;
#[path = "../rom_common/mod.rs"]
mod rom_common;
mod snapshots_common;

mod calibrate_cli;
mod calibrate_extend_cli;
mod defaults_cli;
mod design_cli;
mod diagnose_cli;
mod fe_cli;
mod figures;
mod material_cli;
mod model_form_cli;
mod readme_recipe;
mod rom_cli;
mod rom_fidelity;
mod snapshots;
mod snapshots_plan;
mod twin_cli;
