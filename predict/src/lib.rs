//! # surrogate-predict
//!
//! The embedded predictor of the `surrogate` crate: evaluates a soft-actuator surrogate exported
//! by `surrogate export --rust OUT.rs` with **`core` only**: `#![no_std]`, no allocation, no
//! dependencies, no `std` maths, no `unsafe`. A controller adds this crate to its `Cargo.toml`
//! and compiles the exported file as one of its modules; the exported file brings the model's
//! `static` tables, `pub static MODEL` (or `RAMP`) and a C entry point (`README.md` of this
//! crate: the Rust and the C controller side).
//!
//! The evaluation mirrors the library's `surrogate::rom::Surrogate`:
//!
//! 1. features `z = (N, T, ln μ0, α₁, s, α₂)` (μ0 = ½(μ₁α₁ + μ₂α₂), s = μ₁α₁/(2μ0)), scaled `x_d = (z_d − c_d)·s_d`;
//! 2. POD coefficients `a = f(x)` from a Matérn-5/2 Gaussian process (posterior mean
//!    `a_c = Σᵢ k(x, xᵢ) αᵢc`) or a polynomial (`a_c = Σ_p x^{e_p} β_pc`);
//! 3. per output block, the snapshot ramp at the pressure nodes of a cubic Hermite stencil,
//!    `y_{j,q} = m_{j,q} + s_{j,q} Σ_k a_k Φ_{(j,q),k}`, interpolated in pressure:
//!    `y_q(P) = Σ_j w_j(P) y_{j,q}`.
//!
//! Transcendentals (`exp`, `ln`, `sqrt`) are evaluated in `f64` by the crate's portable routines
//! (accurate to a few ulp); the Gaussian-process sum is always `f64` (see [`GpTables`]); the
//! polynomial and the POD reconstruction run in the model's precision `F` (`f32` or `f64`).
//!
//! An exported ramp (`surrogate export --ramp`: one design and one material) is evaluated by
//! [`evaluate_ramp`]; only the pressure stencil is left:
//!
//! ```
//! use surrogate_predict::{evaluate_ramp, EmbeddedError, RampTables, FORCE, N_QUANTITIES};
//!
//! // the shape of an exported ramp: a pressure grid (bar) and the 22 quantities at each node
//! static PRESSURES: [f64; 2] = [0.0, 2.0];
//! static VALUES: [f32; 2 * N_QUANTITIES] = {
//!     let mut v = [0.0f32; 2 * N_QUANTITIES];
//!     v[N_QUANTITIES + FORCE] = 1.2; // blocked force 1.2 N at 2 bar
//!     v
//! };
//! static RAMP: RampTables<'static, f32> = RampTables { pressures: &PRESSURES, values: &VALUES };
//!
//! let mut out = [0.0f32; N_QUANTITIES];
//! evaluate_ramp(&RAMP, 1.0, &mut out)?;
//! assert!((out[FORCE] - 0.6).abs() < 1e-6);
//! // outside the grid the pressure is clamped to its ends
//! evaluate_ramp(&RAMP, 5.0, &mut out)?;
//! assert_eq!(out[FORCE], 1.2);
//! assert_eq!(evaluate_ramp(&RAMP, f32::NAN, &mut out), Err(EmbeddedError::NonFinite(2)));
//! # Ok::<(), EmbeddedError>(())
//! ```
//!
//! Beside the tables, an exported file carries the model-form error learned from a calibration
//! (`pub static MODEL_FORM: Option<ModelFormTables>`, [`ModelFormTables::error`]): how far the
//! calibrated model misses the recorded actuators, per output and pressure. The surrogate's
//! own error against the FE model is much smaller; the model-form error is the one a designer
//! should read as the prediction's accuracy.
//!
//! By concern:
//! - `outputs`: the query's inputs and the 22 quantities, their names and indices;
//! - `maths`: the model's precision ([`Real`]) and the transcendentals with `core` only;
//! - `stencil`: interpolation in pressure ([`stencil()`]);
//! - `model`: an exported model's tables and their evaluation ([`EmbeddedModel`], [`evaluate`]);
//! - `ramp`: an exported ramp ([`RampTables`], [`evaluate_ramp`]);
//! - `model_form`: the model-form error ([`ModelFormTables`]);
//! - `error`: why an evaluation was refused ([`EmbeddedError`]).
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// index loops mirror the equations and the table layouts
#![allow(clippy::needless_range_loop)]

mod error;
mod maths;
mod model;
mod model_form;
mod outputs;
mod ramp;
mod stencil;

pub use error::EmbeddedError;
pub use maths::{exp, exp_nonpos, ln, matern52, sqrt, Real};
pub use model::{
    evaluate, raw_features, BlockTables, EmbeddedModel, GpTables, PolyTables, MAX_COEFS,
};
pub use model_form::{model_form_at, ModelFormTables};
pub use outputs::{
    marker_uy, marker_uz, ANGLE, FORCE, M1_UY, M1_UZ, M2_UY, M2_UZ, M3_UY, M3_UZ, M4_UY, M4_UZ,
    M5_UY, M5_UZ, M6_UY, M6_UZ, M7_UY, M7_UZ, M8_UY, M8_UZ, M9_UY, M9_UZ, N_FEATURES, N_INPUTS,
    N_QUANTITIES, OUTPUT_NAMES, TIP_UY, TIP_UZ,
};
pub use ramp::{evaluate_ramp, RampTables};
pub use stencil::{stencil, Stencil};
