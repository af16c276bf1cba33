//! The ground floor's error: a case value outside what it may be.

/// A case value that is not admissible: the field, its value and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CaseError {
    /// A bad value.
    #[error("{field} = {value}: expected {expected}")]
    Input {
        /// The field (`mu1*alpha1`, `material coordinates`, …).
        field: String,
        /// Its value.
        value: String,
        /// What is allowed.
        expected: String,
    },
}

impl CaseError {
    pub(crate) fn input(field: &str, value: impl std::fmt::Display, expected: &str) -> Self {
        CaseError::Input {
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }
}
