//! What a refinement found: its rounds, why it stopped, and their account in Markdown.

use std::path::PathBuf;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};

use super::shift::DataSpaceShift;
use crate::calibrate::fit::Calibration;
use crate::calibrate::verify::FeVerification;
use crate::case::OgdenSet;

/// Why the refinement stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum RefineStop {
    /// Surrogate and FE agree at the last calibrated set (within 2σ of the surrogate).
    Agree,
    /// The retrained surrogate's optimum is the set the last round verified.
    OptimumUnchanged,
    /// The retrained surrogate's optimum moved, but not in anything the recordings see: its
    /// predictions there are within `data_tolerance` σ of those at the verified set on every
    /// recorded number.
    PredictionsUnchanged,
    /// `max_rounds` FE rounds were run and the two still disagree somewhere.
    MaxRounds,
}

impl RefineStop {
    /// In words.
    pub fn describe(self) -> &'static str {
        match self {
            RefineStop::Agree => "surrogate and FE agree at the calibrated set",
            RefineStop::OptimumUnchanged => {
                "the retrained surrogate's optimum is the set already verified by FE"
            }
            RefineStop::PredictionsUnchanged => {
                "the retrained surrogate's optimum predicts every recorded number within its \
                 noise of the set already verified by FE"
            }
            RefineStop::MaxRounds => "the largest number of rounds was reached",
        }
    }
}

/// One round: the FE at the set calibrated through the round's surrogate.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RefineRound {
    /// Round (1-based).
    pub round: usize,
    /// Training cases of the surrogate that calibrated this round's set.
    pub model_cases: usize,
    /// Its checksum and provenance.
    pub model: String,
    /// The set, as reported and run (4 significant digits).
    pub set: OgdenSet,
    /// `χ²` of the calibration through the surrogate.
    pub chi2: f64,
    /// Bounds of the training domain active at the set.
    pub active_bounds: Vec<String>,
    /// Mean BE (mm) through the surrogate.
    pub surrogate_mean_be_mm: f64,
    /// The FE at the set against the experiments and the surrogate.
    pub verification: FeVerification,
    /// FE cases run now (the rest were read from the round's directory).
    pub fe_cases_run: usize,
    /// FE wall time of the round (s).
    pub fe_wall_time_s: f64,
    /// The round's FE directory.
    pub fe_dir: PathBuf,
}

/// The whole refinement.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Refinement {
    /// Every round, in order (at least one; a file without is refused).
    #[serde(deserialize_with = "at_least_one_round")]
    pub rounds: Vec<RefineRound>,
    /// Why it stopped.
    pub stop: RefineStop,
    /// The calibration through the last surrogate (the one retrained on every round's cases
    /// when the stop is [`RefineStop::OptimumUnchanged`]).
    pub last: Calibration,
    /// Training cases of the last surrogate.
    pub last_model_cases: usize,
    /// With [`RefineStop::OptimumUnchanged`] or [`RefineStop::PredictionsUnchanged`]: the
    /// last round's FE against the last surrogate (retrained on it), at the same set.
    pub final_check: Option<FeVerification>,
    /// After each retraining: how far the refit moved from the verified set in what the
    /// recordings see (through the retrained surrogate).
    #[serde(default)]
    pub shifts: Vec<DataSpaceShift>,
    /// Where the retrained surrogates are (`model_round_k.json`, trained after round k).
    pub models: Vec<PathBuf>,
}

/// The rounds of a refinement read from a file: at least one.
fn at_least_one_round<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<RefineRound>, D::Error> {
    let rounds = Vec::<RefineRound>::deserialize(d)?;
    if rounds.is_empty() {
        return Err(D::Error::custom(
            "refinement rounds = []: expected at least one round",
        ));
    }
    Ok(rounds)
}

impl Refinement {
    /// The round whose FE verifies the final set: the last one.
    ///
    /// # Panics
    /// A refinement built without rounds (one read from a file has at least one).
    pub fn final_round(&self) -> &RefineRound {
        self.rounds
            .last()
            .expect("a refinement has at least one round")
    }
}

impl Refinement {
    /// The FE check of the final set: [`Self::final_check`] when the optimum stopped moving
    /// (the last round's FE against the surrogate retrained on it), else the last round's.
    pub fn final_verification(&self) -> &FeVerification {
        self.final_check
            .as_ref()
            .unwrap_or(&self.final_round().verification)
    }

    /// A Markdown account of the rounds.
    pub fn summary_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "## Adaptive refinement\n");
        let _ = writeln!(
            s,
            "Each round runs the FE model for every recorded design at the set calibrated through \
             the round's surrogate, compares the two (a disagreement: |FE − surrogate| > 2σ of \
             the surrogate in tip Uz, tip Uy or force), and where they disagree adds the FE cases \
             to the training set, retrains and refits.\n"
        );
        let _ = writeln!(
            s,
            "| round | training cases | μ1 (MPa) | α1 | μ2 (MPa) | α2 | χ² | mean BE surrogate (mm) | mean BE FE (mm) | mean F error FE (N) | mean \\|Δ\\| Uz, Uy (mm), F (N) | max \\|Δ\\| Uz, Uy (mm), F (N) | configurations in disagreement | FE cases run, wall time |"
        );
        let _ = writeln!(
            s,
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.rounds {
            let v = &r.verification;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {:.1} | {:.2} | {:.2} | {:+.3} | {:.2}, {:.2}, {:.3} | {:.2}, {:.2}, {:.3} | {} of {} | {} |",
                r.round,
                r.model_cases,
                r.set.mu1_mpa,
                r.set.alpha1,
                r.set.mu2_mpa,
                r.set.alpha2,
                r.chi2,
                r.surrogate_mean_be_mm,
                v.summary.mean_be_mm,
                v.summary.mean_force_error_n,
                v.mean_abs_sur_fe[0],
                v.mean_abs_sur_fe[1],
                v.mean_abs_sur_fe[2],
                v.max_abs_sur_fe[0],
                v.max_abs_sur_fe[1],
                v.max_abs_sur_fe[2],
                v.disagreements,
                v.rows.len(),
                if r.fe_cases_run == 0 {
                    "none (read back)".to_string()
                } else {
                    format!("{}, {:.0} s", r.fe_cases_run, r.fe_wall_time_s)
                }
            );
        }
        for sh in &self.shifts {
            let _ = writeln!(s, "\nAfter round {}: {}.", sh.round, sh.describe());
        }
        let _ = writeln!(s, "\nStopped: {}.", self.stop.describe());
        if let Some(c) = &self.final_check {
            let _ = writeln!(
                s,
                "\nThe surrogate retrained on every round ({} cases) against the last round's FE at \
                 the same set: mean |Δ| {:.2}, {:.2} mm, {:.3} N; max {:.2}, {:.2} mm, {:.3} N; {} of \
                 {} configurations beyond 2σ.",
                self.last_model_cases,
                c.mean_abs_sur_fe[0],
                c.mean_abs_sur_fe[1],
                c.mean_abs_sur_fe[2],
                c.max_abs_sur_fe[0],
                c.max_abs_sur_fe[1],
                c.max_abs_sur_fe[2],
                c.disagreements,
                c.rows.len()
            );
        }
        let f = self.final_verification();
        let _ = writeln!(
            s,
            "\nFinal set {}: FE mean BE {:.2} mm (median {:.2}), mean force error {:+.3} N over {} configurations.",
            self.final_round().set.spec(),
            f.summary.mean_be_mm,
            f.summary.median_be_mm,
            f.summary.mean_force_error_n,
            f.rows.len()
        );
        s
    }
}
