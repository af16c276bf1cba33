//! The calibration summary's words: the verdict on the fit and the reference study's line.
//!
//! The verdict compares the whitened residuals with the measurement scatter of the noise model
//! (`objective`): with `d` degrees of freedom (observations − fitted parameters), noise alone
//! gives χ² ~ χ²_d, so `√(χ²/d)` is the residuals' size in units of the scatter. The fit
//! misses the data when χ² lies above the 99 % quantile of χ²_d, and the stated scatter looks
//! too large when it lies below the 1 % quantile; in between the model fits within the scatter.
//!
//! The reference study's mean BE (Ansys, its nine configurations) is a statement about the
//! shipped experiments; it is quoted only when the recordings read are those files (by
//! checksum, wherever they were read from).
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::experiments::is_shipped;
use super::inputs::InputFile;

/// Tail probability beyond which the verdict says the residuals are not noise.
const TAIL: f64 = 0.01;

/// The reference study's line, for recordings that are the shipped experiments.
pub const REFERENCE_STUDY: &str = "The reference study (Ansys, 9 configurations): mean BE \
     2.51 mm with Ogden 002, 1.58 mm with a set per configuration.";

/// The verdict, one sentence: the residuals' size against the measurement scatter and what it
/// means, with χ²/dof and the quantile it was tested against.
pub fn fit_verdict(chi2: f64, dof: usize) -> String {
    let dist = match ChiSquared::new(dof as f64) {
        Ok(d) if chi2.is_finite() => d,
        _ => {
            return "**Verdict: none.** No degree of freedom is left beyond the fitted \
                    parameters (or χ² is not finite): more recordings are needed to judge the \
                    fit."
                .to_string()
        }
    };
    let reduced = chi2 / dof as f64;
    let ratio = reduced.sqrt();
    let (lo, hi) = (
        dist.inverse_cdf(TAIL) / dof as f64,
        dist.inverse_cdf(1.0 - TAIL) / dof as f64,
    );
    if reduced > hi {
        format!(
            "**Verdict: residuals {ratio:.1}× the measurement scatter: the model misses these \
             data.** χ²/dof = {reduced:.2} over {dof} degrees of freedom; noise alone exceeds \
             {hi:.2} one time in 100."
        )
    } else if reduced < lo {
        format!(
            "**Verdict: residuals {ratio:.1}× the measurement scatter, smaller than noise \
             alone makes: the recordings' standard deviations look too large.** χ²/dof = \
             {reduced:.2} over {dof} degrees of freedom; noise alone falls below {lo:.2} one \
             time in 100."
        )
    } else {
        format!(
            "**Verdict: residuals {ratio:.1}× the measurement scatter: the model fits these \
             data within their scatter.** χ²/dof = {reduced:.2} over {dof} degrees of \
             freedom, between {lo:.2} and {hi:.2} (noise alone lies outside one time in 50)."
        )
    }
}

/// [`REFERENCE_STUDY`] when the recordings read are the shipped experiments: the bending file
/// is the shipped one and so is the force file, if one was read. A marker file does not
/// change the bending configurations the study's BE is about.
pub fn reference_study_line(inputs: &[InputFile]) -> Option<&'static str> {
    let bending: Vec<_> = inputs.iter().filter(|f| f.role == "bending").collect();
    let shipped = !bending.is_empty()
        && bending.iter().all(|f| is_shipped(f))
        && inputs.iter().filter(|f| f.role == "force").all(is_shipped);
    shipped.then_some(REFERENCE_STUDY)
}
