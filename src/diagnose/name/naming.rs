//! What the Name stage reports: its settings, every candidate tested with its statistics,
//! the pairs the recordings cannot tell apart, the effects not testable, and the verdict.

use serde::{Deserialize, Serialize};

#[cfg(doc)]
use crate::calibrate::baseline::SweepSensitivities;
use crate::diagnose::approx_error::ErrorSpread;
use crate::diagnose::mesh_error::ErrorDirection;
use crate::fe::effects::Effect;

/// Settings of [`name`](super::name).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NameSettings {
    /// Family-wise significance level of the candidates' tests (Holm).
    pub alpha: f64,
    /// `|cos|` between two projected signatures above which the two are indistinguishable.
    pub collinear: f64,
    /// Errors of the diagnosing model itself (its mesh error, [`crate::diagnose::mesh_error`]),
    /// tested beside the effects: when one explains the residual best, the verdict says so
    /// and names no physics.
    #[serde(default)]
    pub model_errors: Vec<ErrorDirection>,
    /// The covariance of the diagnosing model's own error over the cells
    /// ([`crate::diagnose::approx_error`]): the residual and every signature are weighed by
    /// `(I + Γ̃)^(−1/2)` (a Cholesky factor) before the tests. None: the recordings' σ alone.
    #[serde(default)]
    pub error_spread: Option<ErrorSpread>,
}

impl Default for NameSettings {
    fn default() -> Self {
        Self {
            alpha: 0.05,
            collinear: 0.95,
            model_errors: Vec::new(),
            error_spread: None,
        }
    }
}

/// One candidate effect, tested.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// The effect's name.
    pub effect: String,
    /// Its unit.
    pub unit: String,
    /// Whether it is an error of the diagnosing model itself (its mesh), not physics.
    #[serde(default)]
    pub model_error: bool,
    /// `|s|`: how strongly the recordings see it (σ per unit).
    pub signature_norm: f64,
    /// Share of `|s|²` the material absorbs.
    pub absorbed_by_material: f64,
    /// Its estimated size `θ̂` (unit of the effect, from [`Self::base`]).
    pub estimate: f64,
    /// The sweep's value of the effect, which `θ̂` is measured from, when it is not the
    /// effect's neutral value (a sweep of a model built with the effect fixed, such as the
    /// force rig's plate: [`SweepSensitivities::base`]); none: the neutral value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<f64>,
    /// Standard error of `θ̂`.
    pub std_error: f64,
    /// Whether its size ([`Self::size`]) lies in the library's plausible range.
    pub plausible: bool,
    /// `Δχ²` of adding it to the material re-fit.
    pub delta_chi2: f64,
    /// `Δχ²` over the material-only `χ²`.
    pub explained: f64,
    /// The F statistic.
    pub f: f64,
    /// Its p-value.
    pub p_value: f64,
    /// Whether it is significant after Holm's correction.
    pub significant: bool,
    /// `ΔAIC` against the material-only re-fit (negative: better).
    pub delta_aic: f64,
    /// `ΔBIC` against the material-only re-fit.
    pub delta_bic: f64,
    /// `|θ̂| maxᵢ |s̃ᵢ|`: the largest change its estimated size makes to one recorded number
    /// past what the material can mimic, in that number's σ.
    #[serde(default)]
    pub max_move_sigma: f64,
}

impl Candidate {
    /// Its size: [`Self::base`] (the effect's neutral value when none, zero for an error of
    /// the model) plus the estimate; what `--effect NAME=VALUE` takes and what its
    /// plausibility is judged on.
    pub fn size(&self) -> f64 {
        let neutral = || {
            Effect::from_name(&self.effect)
                .ok()
                .filter(|_| !self.model_error)
                .map_or(0.0, |e| e.info().neutral)
        };
        self.base.unwrap_or_else(neutral) + self.estimate
    }

    /// Its estimate in words with `decimals` decimals: `+0.120`, or from a sweep that fixed
    /// the effect, its size with the sweep's value and the estimate, `-4.200 (-4.5 +0.300)`.
    pub fn size_text(&self, decimals: usize) -> String {
        match self.base {
            None => format!("{:+.decimals$}", self.estimate),
            Some(b) => format!(
                "{:.decimals$} ({b} {:+.decimals$})",
                self.size(),
                self.estimate
            ),
        }
    }
}

/// Two candidates the recordings cannot tell apart.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Indistinguishable {
    /// First effect.
    pub a: String,
    /// Second effect.
    pub b: String,
    /// `cos` between their projected signatures.
    pub cosine: f64,
    /// For a pair with the first or the named candidate: the p-value of the better one's
    /// `Δχ²` beyond the other's (F test of the fit with both against the fit with the other
    /// alone). Above the level: the recordings do not prefer it, so the two cannot be told
    /// apart even when their signatures are not collinear.
    #[serde(default)]
    pub p_separation: Option<f64>,
    /// For the same pairs: the z of the likelihood ratio of the two non-nested one-effect
    /// fits (positive: `a` fits better; see the module docs). Within the two-sided normal
    /// quantile of the level: neither fits significantly better.
    #[serde(default)]
    pub vuong_z: Option<f64>,
    /// Where their two explanations differ most among outputs the recordings lack.
    pub separated_by: Option<String>,
}

impl Indistinguishable {
    /// Why the two cannot be told apart, in words.
    pub fn why(&self) -> String {
        match (self.p_separation, self.vuong_z) {
            (Some(p), Some(z)) => format!(
                "cos {:.3}; the better one beyond the other: p = {p:.2}; likelihood-ratio z = {z:+.2}",
                self.cosine
            ),
            _ => format!("cos {:.3}", self.cosine),
        }
    }
}

/// An effect that could not be tested, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Untestable {
    /// The effect.
    pub effect: String,
    /// Why.
    pub reason: String,
}

/// What the Name stage found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Naming {
    /// The material of the nonlinear re-fit on every used cell ([`name_refitted`](super::name_refitted); none:
    /// the re-fit was linearised with the sweep's material sensitivities).
    #[serde(default)]
    pub refitted_material: Option<crate::case::OgdenSet>,
    /// Cells used (those with sensitivities).
    pub n_cells: usize,
    /// Cells without sensitivities in the sweep, in words.
    pub unmatched: Vec<String>,
    /// Used cells whose FE sensitivities hold a derivative spike (more than 10 times the
    /// same derivative at the ramp's other pressures, as at a contact switch): their
    /// linearisation is doubtful, in words.
    #[serde(default)]
    pub spikes: Vec<String>,
    /// `χ²` of the used cells at the calibrated set.
    pub chi2: f64,
    /// `χ²` after the material re-fit on every used cell.
    pub chi2_material: f64,
    /// The candidates, largest `Δχ²` first.
    pub candidates: Vec<Candidate>,
    /// Pairs the recordings cannot separate.
    pub indistinguishable: Vec<Indistinguishable>,
    /// Effects not testable on these recordings.
    pub untestable: Vec<Untestable>,
    /// The verdict in words.
    pub verdict: String,
}

impl Naming {
    /// The best significant candidate at a plausible size (an effect or an error of the
    /// model itself).
    pub fn best(&self) -> Option<&Candidate> {
        self.candidates
            .iter()
            .find(|c| c.significant && c.plausible)
    }

    /// The named effect: the best significant candidate at a plausible size, when it is
    /// physics (none when the verdict names nothing or the model's own error explains the
    /// residual best).
    pub fn named(&self) -> Option<&Candidate> {
        self.best().filter(|c| !c.model_error)
    }

    /// The model's own error, when it explains the residual best.
    pub fn model_error(&self) -> Option<&Candidate> {
        self.best().filter(|c| c.model_error)
    }
}
