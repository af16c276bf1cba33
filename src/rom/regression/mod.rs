//! Regression of POD coefficients on the scaled case features.
//!
//! A regressor is a type implementing [`Regressor`] (linfa's fit / predict-into split): its
//! fit, its allocation-free prediction, its serialisation into the model file (serde, under its
//! [`Regressor::NAME`]) and, if the embedded predictor can evaluate it, its export tables
//! ([`Regressor::embedded`]). The built-ins are listed once, in [`BUILTIN`]: training fits
//! every regressor of a [`Registry`] (the built-ins by default), a model file holds each
//! fitted one under its name, and loading reads the names the registry knows. Adding a
//! regressor is one new file and one line in [`BUILTIN`] (and its `mod` line here); a regressor outside the crate
//! (a test's) is added to a registry with [`Registry::with`].
//!
//! The built-ins: [`gp::Gp`] (Gaussian process, Matérn 5/2, ARD length scales shared by all
//! outputs or per column group, predictive variance) and [`poly::Poly`] (ridge polynomial of
//! total degree ≤ 3, degree and ridge chosen by PRESS). Both are multi-output: one fit predicts
//! all POD coefficients of all blocks. Inputs are the active features scaled to `[−1, 1]` by
//! [`FeatureScaler`](crate::case::FeatureScaler).

pub mod gp;
// public for the tests in tests/rom/
#[doc(hidden)]
pub mod linalg;
pub mod poly;
mod registry;
mod regressor;

pub(crate) use linalg::{cholesky_in_place, solve_lower, solve_lower_t};
pub use registry::{DynRegressor, Entry, Registry, RegressorKind, Regressors, BUILTIN};
pub use regressor::{Data, EmbeddedRegressor, LinearBasis, Regressor, TrainingSettings};
