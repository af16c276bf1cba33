//! Why an embedded evaluation was refused, with the C entry point's status codes.

use crate::outputs::N_INPUTS;

/// Why an embedded evaluation was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmbeddedError {
    /// An input is NaN or infinite (index into `N, T, P, μ₁, α₁, μ₂, α₂`).
    NonFinite(usize),
    /// `N` is not one of the numbers of bellows the model predicts (`n_allowed`).
    UnknownN,
    /// `μ₁α₁ ≤ 0` or `μ₂α₂ ≤ 0`.
    Inadmissible,
    /// The model tables are inconsistent (too many coefficients, bad indices).
    BadModel,
}

impl EmbeddedError {
    /// Status code of the C entry point (`0` is success).
    pub fn code(self) -> i32 {
        match self {
            EmbeddedError::NonFinite(_) => 1,
            EmbeddedError::UnknownN => 2,
            EmbeddedError::Inadmissible => 3,
            EmbeddedError::BadModel => 4,
        }
    }
}

impl core::fmt::Display for EmbeddedError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        const INPUTS: [&str; N_INPUTS] = ["N", "T", "P", "mu1", "alpha1", "mu2", "alpha2"];
        match *self {
            EmbeddedError::NonFinite(i) => match INPUTS.get(i) {
                Some(name) => write!(f, "input {name} is not finite"),
                None => write!(f, "input {i} is not finite"),
            },
            EmbeddedError::UnknownN => {
                f.write_str("N is not a number of bellows the model predicts")
            }
            EmbeddedError::Inadmissible => {
                f.write_str("inadmissible Ogden material (mu1*alpha1 <= 0 or mu2*alpha2 <= 0)")
            }
            EmbeddedError::BadModel => f.write_str("inconsistent model tables"),
        }
    }
}

impl core::error::Error for EmbeddedError {}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;

    #[test]
    fn errors_have_c_codes_and_messages() {
        use std::string::ToString;
        let cases = [
            (EmbeddedError::NonFinite(2), 1, "input P is not finite"),
            (EmbeddedError::NonFinite(9), 1, "input 9 is not finite"),
            (
                EmbeddedError::UnknownN,
                2,
                "N is not a number of bellows the model predicts",
            ),
            (
                EmbeddedError::Inadmissible,
                3,
                "inadmissible Ogden material",
            ),
            (EmbeddedError::BadModel, 4, "inconsistent model tables"),
        ];
        for (e, code, text) in cases {
            assert_eq!(e.code(), code);
            assert!(e.to_string().starts_with(text), "{e}");
        }
    }
}
