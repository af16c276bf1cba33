//! Hyperelastic material laws with the isochoric / volumetric split.
//!
//! Every law stores its isochoric strain energy `W_iso(F) = Ŵ(F̄)`, `F̄ = J^{-1/3} F`,
//! and shares the volumetric energy `U(J) = κ/2 (J − 1)²` (ANSYS: `d = 2/κ`).
//!
//! Index convention for fourth-order tangents stored as 9×9 matrices:
//! `A[(3*i + J, 3*k + L)] = ∂P_iJ / ∂F_kL`, with `P` the first Piola–Kirchhoff stress
//! and `F` the deformation gradient (`nalgebra::Matrix3`, row `i`, column `J`).

use thiserror::Error;

/// Errors of material parameters.
#[derive(Debug, Error)]
pub enum MaterialError {
    /// A parameter outside its admissible range.
    #[error("inadmissible material parameter {field} = {value}: expected {expected}")]
    Inadmissible {
        /// Parameter name.
        field: String,
        /// Offending value.
        value: f64,
        /// What was expected.
        expected: String,
    },
}
