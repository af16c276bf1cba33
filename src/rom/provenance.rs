//! What a trained model records about its making: the snapshot source and the cases used, the
//! code version, and how a multi-fidelity training set was corrected ([`super::fidelity`]).

use serde::{Deserialize, Serialize};

use super::metrics::{ErrorStats, Validation};
use super::warp::WarpInfo;
use crate::case::PlanDomain;
use crate::fe::effects::Effects;
use crate::fe::preset::Geometry;

/// Provenance of a trained model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainingInfo {
    /// Snapshot source.
    pub source: String,
    /// Number of training cases.
    pub n_cases: usize,
    /// Cases dropped from the complete set (truncated ramps).
    pub dropped_cases: usize,
    /// Truncated cases used for the regression through gappy POD.
    pub filled_cases: usize,
    /// Unconverged rows skipped.
    pub skipped_unconverged: usize,
    /// Version of the crate that trained the model.
    pub code_version: String,
    /// How N is treated.
    pub n_treatment: String,
    /// Inducing points of a sparse GP fit
    /// ([`GpParams::inducing`](super::regression::gp::GpParams::inducing)), as asked: a fit of
    /// no more points than this (a small fold, the final fit of a small set) was exact.
    /// Absent: exact GP fits (and models written before this field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gp_inducing: Option<usize>,
    /// Multi-fidelity correction of the training set, if any ([`super::fidelity`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correction: Option<CorrectionInfo>,
    /// The training domain as the snapshot plan states it: the plan's nominal ranges where
    /// its cases cover them ([`crate::case::domain`]). Absent (a model trained without its
    /// plan, or written before this field): the domain is the box of the training cases.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plan_domain: Option<PlanDomain>,
    /// How the training cases' actuators were built, where their plan says it: its geometry
    /// preset and its fixed effects (the force rig's plate, ...). Absent: the geometry as
    /// modelled, no fixed effect (or a model trained without its plan).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub built_with: Option<BuiltWith>,
}

/// [`TrainingInfo::n_treatment`] of a model trained with
/// [`TrainConfig::ordinal_n`](super::TrainConfig::ordinal_n).
pub const N_ORDINAL: &str =
    "ordinal regression input; predictions at every integer N between the trained ends";

impl TrainingInfo {
    /// Whether the model was trained with `N` as an ordinal input
    /// ([`super::TrainConfig::ordinal_n`]).
    pub fn ordinal_n(&self) -> bool {
        self.n_treatment == N_ORDINAL
    }
}

/// The geometry and the fixed effects every training case was built with (from its plan's
/// settings): what an FE run must use to be compared with the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuiltWith {
    /// The geometry preset ([`Geometry::as_modelled`] when the plan names none).
    pub geometry: Geometry,
    /// The effects fixed for every case.
    #[serde(default)]
    pub effects: Effects,
}

/// How a training set was corrected (stored in the model's training information).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorrectionInfo {
    /// High-fidelity snapshot source.
    pub high_source: String,
    /// Cases run at both fidelities.
    pub matched_cases: usize,
    /// Low-fidelity rows replaced by their high-fidelity values.
    pub replaced_rows: usize,
    /// Low-fidelity rows corrected by the discrepancy surrogate.
    pub corrected_rows: usize,
    /// Held-out errors of the discrepancy surrogate (k-fold over the matched cases): the
    /// error the correction adds to the surrogate's.
    pub validation: Validation,
    /// The pressure warp applied to the low fidelity before the discrepancy
    /// ([`super::warp`]), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure_warp: Option<WarpInfo>,
    /// The whole pipeline against the high fidelity ([`super::fidelity::end_to_end`]), when it
    /// was run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_to_end: Option<EndToEnd>,
}

/// Error of the whole multi-fidelity pipeline against high-fidelity cases it never saw:
/// for each fold of the high-fidelity cases, the discrepancy surrogate is fitted without
/// them, the low-fidelity set corrected, the surrogate trained on it, and its predictions at
/// the held-out cases compared with their high-fidelity values. Beside it, the raw
/// discrepancy `H − L` of the same rows: what training on the low fidelity alone would miss.
///
/// The held-out cases are left out of the surrogate's training set too (their corrected
/// low-fidelity rows are dropped), so each is predicted as a design the model never saw: the
/// figure is what a user gets against the high fidelity at a new design, the correction's
/// error and the surrogate's regression error together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EndToEnd {
    /// Scheme, e.g. `5-fold over the 30 high-fidelity cases`.
    pub scheme: String,
    /// Per output (`markers_mm`, `tip_uz_mm`, `tip_uy_mm`, `angle_deg`, `force_n`): errors of
    /// the surrogate against the held-out high-fidelity values.
    pub surrogate: Vec<(String, ErrorStats)>,
    /// The same rows: the corrected low-fidelity values (what the surrogate would have been
    /// trained on had the case been in the plan) against the high fidelity: the correction's
    /// own error.
    #[serde(default)]
    pub corrected: Vec<(String, ErrorStats)>,
    /// The same rows: low- against high-fidelity values (no surrogate, no correction).
    pub low_fidelity: Vec<(String, ErrorStats)>,
}

impl EndToEnd {
    /// Human-readable table.
    pub fn table(&self) -> String {
        let mut s = format!(
            "surrogate against held-out high fidelity ({}): RMSE / max of the surrogate at the \
             unseen design, of the corrected low fidelity, of the raw low fidelity\n\
             {:<12} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}\n",
            self.scheme, "output", "surrogate", "max", "corrected", "max", "low", "max"
        );
        for (i, ((name, e), (_, l))) in self.surrogate.iter().zip(&self.low_fidelity).enumerate() {
            let c = self.corrected.get(i).map(|(_, c)| *c);
            s.push_str(&format!(
                "{name:<12} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>9.4}\n",
                e.rmse,
                e.max_abs,
                c.map_or(f64::NAN, |c| c.rmse),
                c.map_or(f64::NAN, |c| c.max_abs),
                l.rmse,
                l.max_abs
            ));
        }
        s
    }
}
