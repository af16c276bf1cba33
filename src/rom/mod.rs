//! Reduced-order surrogate: POD of the pressure ramps + regression on the case parameters.
//!
//! ## The snapshot of a case
//!
//! A *case* is one design and material `(N, T, μ₁, α₁, μ₂, α₂)` simulated along a pressure ramp
//! `P₀ < … < P_{n_p−1}` (the grid shared by the snapshot set). Its snapshot stacks, for every
//! grid pressure `j`, the 22 quantities `q` (18 marker components `m1_uz … m9_uy`, `tip_uz`,
//! `tip_uy`, `angle`, `force`): `y ∈ ℝ^{22·n_p}`. Pressure is therefore *not* a regression input:
//! the regression sees one point per case (a held-out case never shares a ramp with training),
//! and a query at pressure `P` interpolates the reconstructed ramp with a cubic Hermite stencil
//! ([`surrogate_predict::stencil`]).
//!
//! ## POD ([`pod`])
//!
//! Snapshots are grouped in *blocks*: the **field** block (all 22 quantities) and one **direct**
//! block per scalar (tip Uz, tip Uy, angle, force). Per block, entries are centred by the mean
//! snapshot `ȳ` and scaled by one scale per quantity `s_q` (its RMS deviation over cases and
//! pressures): `ỹ = (y − ȳ)/s`. The thin SVD `Ỹ = U Σ Vᵀ` (faer) of the `dim × n_cases`
//! matrix gives modes `Φ = U[:, :r]`, with `r` the smallest count whose discarded energy
//! `Σ_{k>r} σ_k² / Σ σ_k²` is below the tolerance. A snapshot is represented by its coefficients
//! `a = Φᵀỹ`; the **projection error** is `y − (ȳ + s ⊙ Φa)`.
//!
//! ## Regression ([`regression`])
//!
//! The coefficients of all blocks are regressed on the scaled features
//! `z = (N, T, ln μ0, α₁, s, α₂)` (μ0 = ½(μ₁α₁ + μ₂α₂), s = μ₁α₁/(2μ0)) by a Gaussian process (Matérn 5/2, shared ARD
//! length scales, profiled variance) and by a polynomial (total degree and ridge chosen by
//! PRESS). `N` is discrete: it enters as a numeric input, and only the trained values of `N`
//! are accepted at prediction. The **regression error** is `s ⊙ Φ(a − â)`.
//!
//! ## Choice and validation ([`mod@train`], [`metrics`])
//!
//! K-fold cross-validation by case runs the whole pipeline per fold. For the markers, the field
//! block's regressor (GP or polynomial) with the smaller held-out marker RMSE is kept; for each
//! scalar, the best of {field, direct} × {GP, polynomial}. The held-out errors (RMSE, max, R²,
//! projection and regression parts) are stored in the model file ([`model`]).
//!
//! ## Example
//!
//! ```
//! use surrogate::rom::data::SnapshotSet;
//! use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
//! use surrogate::case::{OgdenSet, Query};
//! use surrogate::rom::{train, Jacobian, Surrogate, TrainConfig};
//!
//! // a small synthetic snapshot set in the snapshot CSV contract
//! let mut csv = Vec::new();
//! write_csv(&SyntheticConfig { n_cases: 24, ..Default::default() }, &mut csv)?;
//! let cases = SnapshotSet::from_reader(csv.as_slice(), "demo")?.into_cases()?;
//! let cfg = TrainConfig { folds: 3, ..Default::default() };
//! let model: Surrogate = train(&cases, "demo", 0, &cfg, &|_, _| {})?.surrogate;
//!
//! // optimisation loops: reuse one Prediction, no allocation per call
//! let ogden_002 = OgdenSet::new(1.13, 3.11, -13.17, -0.6)?;
//! let q = Query::new(11, 2.0, 2.0, ogden_002);
//! let mut pred = model.new_prediction();
//! let mut jac = Jacobian::default();
//! model.gradient_into(&q, &mut pred, &mut jac)?;
//! assert!(pred.tip_uy_mm() < 0.0 && jac.d[surrogate::rom::Q_TIP_UY][1] < 0.0); // bends down with P
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// index loops mirror the equations and the table layouts
#![allow(clippy::needless_range_loop)]

/// A method of `$self_ty` that runs its `#[inline(always)]` body compiled for AVX-512, or for AVX2 + FMA,
/// when the CPU has it (detected at run time), else as compiled for the baseline target. No
/// fused multiply-adds are formed by the compiler, so every path gives the same bits.
macro_rules! simd_method {
    (
        $self_ty:ty;
        $(#[$meta:meta])*
        $vis:vis fn $name:ident(&self $(, $arg:ident: $ty:ty)* $(,)?) => $body:ident
    ) => {
        $(#[$meta])*
        $vis fn $name(&self $(, $arg: $ty)*) {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx512f")]
                unsafe fn avx512(this: &$self_ty $(, $arg: $ty)*) {
                    this.$body($($arg),*)
                }
                #[target_feature(enable = "avx2,fma")]
                unsafe fn avx2(this: &$self_ty $(, $arg: $ty)*) {
                    this.$body($($arg),*)
                }
                if std::is_x86_feature_detected!("avx512f") {
                    // SAFETY: the CPU supports the features the function is compiled for.
                    return unsafe { avx512(self $(, $arg)*) };
                }
                if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                    // SAFETY: as above.
                    return unsafe { avx2(self $(, $arg)*) };
                }
            }
            self.$body($($arg),*)
        }
    };
}

pub mod batch;
mod consistency;
pub mod data;
pub mod export;
pub mod fast;
pub mod fidelity;
pub mod held_out_n;
pub mod material_spec;
pub mod metrics;
pub mod model;
pub mod model_form;
pub mod model_form_report;
mod plan_domain;
pub mod pod;
pub mod provenance;
pub mod ramp;
pub mod regression;
pub mod surrogate;
pub(crate) mod svd;
pub mod synthetic;
pub mod train;
pub mod unseen;
pub mod warp;

pub use data::SnapshotSet;
pub use model::FORMAT_VERSION;
pub use model_form::{ModelFormError, ModelFormEstimate};
pub use ramp::Ramp;
pub use surrogate::{Gradient, Jacobian, Prediction, Surrogate};
pub use train::{train, TrainConfig, TrainReport};

use thiserror::Error;

use crate::schema;

/// Names of the 22 predicted quantities, in storage order ([`schema::OUTPUTS`]).
pub const QUANTITY_NAMES: [&str; 22] = schema::names(&schema::OUTPUTS);
/// Index of `tip_uz_mm` among the quantities ([`surrogate_predict::TIP_UZ`]; every output's
/// index is named there: `M1_UZ` … `M9_UY`, `marker_uz(k)` for marker `k = 1 … 9`).
pub const Q_TIP_UZ: usize = surrogate_predict::TIP_UZ;
/// Index of `tip_uy_mm`.
pub const Q_TIP_UY: usize = surrogate_predict::TIP_UY;
/// Index of `angle_deg`.
pub const Q_ANGLE: usize = surrogate_predict::ANGLE;
/// Index of `force_n`.
pub const Q_FORCE: usize = surrogate_predict::FORCE;
/// Number of marker components (9 markers × (Uz, Uy)).
pub const N_MARKER_COMPONENTS: usize = 18;

/// Errors of the reduced-order model: data, training, model files and queries.
#[derive(Debug, Error)]
pub enum RomError {
    /// The snapshot CSV header does not match the contract.
    #[error("{source_name}: header: {message}")]
    Header {
        /// File the header comes from.
        source_name: String,
        /// What is wrong.
        message: String,
    },
    /// A CSV cell is invalid.
    #[error("{source_name}: line {line}, column `{column}`: value {value:?}: expected {expected}")]
    Cell {
        /// File the row comes from.
        source_name: String,
        /// 1-based line number (the header is line 1).
        line: usize,
        /// Column name.
        column: String,
        /// Offending text.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// The CSV could not be read.
    #[error("{source_name}: {message}")]
    Csv {
        /// File involved.
        source_name: String,
        /// Underlying message.
        message: String,
    },
    /// Not enough usable data to train.
    #[error("not enough data: {0}")]
    InsufficientData(String),
    /// An invalid training or query setting.
    #[error("invalid {field} = {value}: expected {expected}")]
    InvalidInput {
        /// Field name.
        field: String,
        /// Offending value.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// A numerical failure during training.
    #[error("numerical failure in {stage}: {message}")]
    Numerical {
        /// Training stage.
        stage: String,
        /// What happened.
        message: String,
    },
    /// A model file is unreadable, corrupt, of another version or fails its checksum.
    #[error("model file {path}: {message}")]
    ModelFile {
        /// File involved.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// A calibration report that cannot give a model-form error ([`model_form`]).
    #[error("calibration report {path}: {field} = {value}: expected {expected}")]
    CalibrationReport {
        /// File involved.
        path: String,
        /// The field of the report.
        field: String,
        /// Its value.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// Inputs outside the training domain where extrapolation was not allowed (the message
    /// names the inputs, their values and the training ranges; a batch: how many rows, the
    /// first few).
    #[error("{0}")]
    OutsideDomain(String),
    /// A model whose regressor the embedded predictor cannot evaluate, asked for by
    /// `surrogate export` ([`export`]).
    #[error("regressor `{regressor}` cannot be exported: {reason}")]
    NotExportable {
        /// The regressor's name.
        regressor: String,
        /// Why.
        reason: String,
    },
    /// Input/output failure.
    #[error("{path}: {source}")]
    Io {
        /// File involved.
        path: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
}

impl RomError {
    pub(crate) fn invalid(field: &str, value: impl ToString, expected: &str) -> Self {
        RomError::InvalidInput {
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }
}
