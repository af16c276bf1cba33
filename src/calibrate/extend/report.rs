//! What a box extension found: its rounds, why it stopped, and their account in Markdown; a
//! versioned JSON document.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::limits::PhysicalLimits;
use super::material_box::{sig, MaterialBox, PressedBound};
use crate::calibrate::fit::Calibration;
use crate::calibrate::CalibrateError;
use crate::case::{MaterialCoords, OgdenSet};

/// The `format` field of a box-extension report.
pub const FORMAT: &str = "surrogate.box_extension";
/// The `version` field this code writes and reads.
pub const VERSION: u32 = 1;

/// Why the extension stopped.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExtendStop {
    /// The optimum lies inside the box: no bound is active.
    Inside,
    /// Every bound the optimum presses is at its physical limit (named, with its value).
    PhysicalLimit {
        /// The bounds, in words.
        bounds: Vec<String>,
        /// Bounds also pressed, of coordinates the recordings do not determine (their
        /// profiles open on both sides), in words: the box truncates them, and moving them
        /// would change nothing the recordings see.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        undetermined: Vec<String>,
    },
    /// The optimum presses only bounds of coordinates the recordings do not determine (their
    /// profiles open on both sides): moving them would change nothing the recordings see.
    Undetermined {
        /// The bounds, in words.
        bounds: Vec<String>,
    },
    /// `max_rounds` rounds were run and the optimum still presses a bound that could move.
    MaxRounds,
}

impl ExtendStop {
    /// In words.
    pub fn describe(&self) -> String {
        match self {
            ExtendStop::Inside => "the optimum lies inside the box (no bound is active)".into(),
            ExtendStop::PhysicalLimit {
                bounds,
                undetermined,
            } => {
                let mut s = format!(
                    "every bound the optimum presses that the recordings determine is at its \
                     physical limit: {}",
                    bounds.join("; ")
                );
                if !undetermined.is_empty() {
                    s.push_str(&format!(
                        "; it also presses {}, of coordinates the recordings do not determine \
                         (their profiles are open on both sides): the box truncates them, and \
                         moving them would change nothing the recordings see",
                        undetermined.join("; ")
                    ));
                }
                s
            }
            ExtendStop::Undetermined { bounds } => format!(
                "the optimum presses only bounds of coordinates the recordings do not determine \
                 (their profiles are open on both sides), so moving them changes nothing the \
                 recordings see: {}",
                bounds.join("; ")
            ),
            ExtendStop::MaxRounds => {
                "the largest number of rounds was reached with the optimum still on a bound that \
                 could move"
                    .into()
            }
        }
    }
}

/// An optimum through one surrogate, in brief.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Optimum {
    /// The calibrated set.
    pub set: OgdenSet,
    /// Its sampling coordinates.
    pub coords: MaterialCoords,
    /// `χ²` of the calibration.
    pub chi2: f64,
    /// Bounds of the surrogate's training domain active at the set.
    pub active_bounds: Vec<String>,
    /// The box the fit moved in (the surrogate's training cases span it).
    pub domain: MaterialBox,
    /// Training cases of the surrogate.
    pub model_cases: usize,
    /// Mean BE (mm) through the surrogate.
    pub surrogate_mean_be_mm: f64,
}

impl Optimum {
    /// The brief of a calibration through a surrogate of `model_cases` training cases.
    ///
    /// # Errors
    /// A calibration whose domain is not a training domain.
    pub fn of(cal: &Calibration, model_cases: usize) -> Result<Self, CalibrateError> {
        Ok(Optimum {
            set: cal.best,
            coords: cal.best_coords,
            chi2: cal.chi2,
            active_bounds: cal.active_bounds.clone(),
            domain: MaterialBox::of_domain(&cal.domain)?,
            model_cases,
            surrogate_mean_be_mm: cal.calibrated.mean_be_mm,
        })
    }
}

/// A round's FE cases that failed (left out of the training set).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailedCase {
    /// Case id.
    pub id: usize,
    /// The mesh it failed on (`coarse`, `standard`, …).
    pub mesh: String,
    /// The solver's message.
    pub error: String,
}

/// One round: the box extended where the optimum pressed, the new cases, the refit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtendRound {
    /// Round (1-based).
    pub round: usize,
    /// The box before the round (the training plan's nominal box after the rounds before).
    pub box_before: MaterialBox,
    /// The box after it.
    pub box_after: MaterialBox,
    /// The bounds the optimum pressed, and where each went.
    pub pressed: Vec<PressedBound>,
    /// Hash of the round's plan (`extend_k/plan.json`).
    pub plan_hash: String,
    /// Cases of the round's plan.
    pub cases: usize,
    /// Of which on the high-fidelity mesh too (0 without a high fidelity).
    pub high_fidelity_cases: usize,
    /// FE cases run now, both meshes (the rest were read back from the round's directories).
    pub cases_run: usize,
    /// FE cases read back.
    pub cases_read_back: usize,
    /// Cases that failed, left out of the training set.
    pub failed: Vec<FailedCase>,
    /// FE wall time of the round (s).
    pub fe_wall_time_s: f64,
    /// The round's FE directory.
    pub fe_dir: PathBuf,
    /// The surrogate retrained with the round's cases.
    pub model: PathBuf,
    /// The refit through it.
    pub refit: Optimum,
}

/// The whole extension.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BoxExtension {
    /// [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The step (fraction of a coordinate's range).
    pub step: f64,
    /// Cases per round.
    pub cases_per_round: usize,
    /// Seed of the rounds' Latin hypercubes.
    pub seed: u64,
    /// The physical limits.
    pub limits: PhysicalLimits,
    /// The optimum through the surrogate given, before any round.
    pub start: Optimum,
    /// Every round, in order (none when the first optimum was inside or at the limits).
    pub rounds: Vec<ExtendRound>,
    /// Why it stopped.
    pub stop: ExtendStop,
    /// The nominal box at the end.
    pub final_box: MaterialBox,
    /// The calibration through the last surrogate: always there in what
    /// [`extend_box`](super::extend_box) returns, not written to the report's file (a
    /// calibration's report may hold undefined numbers, which JSON cannot; `surrogate
    /// calibrate` writes it to `report.json` beside it, and its brief is
    /// [`Self::final_optimum`]).
    #[serde(skip)]
    pub last: Option<Calibration>,
}

impl BoxExtension {
    /// The optimum the extension ends with: the last round's refit, else the start.
    pub fn final_optimum(&self) -> &Optimum {
        self.rounds.last().map_or(&self.start, |r| &r.refit)
    }

    /// The retrained surrogates, in order (`model_extend_k.json`).
    pub fn models(&self) -> Vec<&PathBuf> {
        self.rounds.iter().map(|r| &r.model).collect()
    }

    /// Reads a report written as JSON, checking its format and version.
    ///
    /// # Errors
    /// Text that is not a report, or a report of another format or version (named).
    pub fn from_json(text: &str) -> Result<Self, CalibrateError> {
        let bad = |e: serde_json::Error| {
            CalibrateError::input(
                "box extension report",
                e,
                "a report written by this program",
            )
        };
        let v: serde_json::Value = serde_json::from_str(text).map_err(bad)?;
        let format = v.get("format").and_then(|f| f.as_str()).unwrap_or("");
        if format != FORMAT {
            return Err(CalibrateError::input("format", format, FORMAT));
        }
        let version = v.get("version").and_then(|f| f.as_u64()).unwrap_or(0);
        if version != u64::from(VERSION) {
            return Err(CalibrateError::input(
                "version",
                version,
                &format!("{VERSION} (the version this program reads)"),
            ));
        }
        serde_json::from_value(v).map_err(bad)
    }

    /// The Markdown section of the calibration summary: each round's box, pressed bounds,
    /// cases and refit, and the stop.
    pub fn summary_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "## Box extension\n");
        let _ = writeln!(
            s,
            "Where the optimum presses a bound of the training box, the bound moves out by {} of \
             its range (up to its physical limit), {} new FE cases fill the slab between the old \
             box and the new one, the surrogate is retrained and the material refitted.\n",
            self.step, self.cases_per_round
        );
        let o = &self.start;
        let _ = writeln!(
            s,
            "Start: {} training cases, box {}; optimum μ0 {} MPa, s {}, α1 {}, α2 {}, χ² {:.1}, on {}.\n",
            o.model_cases,
            o.domain.describe(),
            sig(o.coords.mu0_mpa),
            sig(o.coords.share),
            sig(o.coords.alpha1),
            sig(o.coords.alpha2),
            o.chi2,
            bounds_or_none(&o.active_bounds)
        );
        if !self.rounds.is_empty() {
            let _ = writeln!(
                s,
                "| round | pressed bounds | cases (failed) | training cases | refit μ0 (MPa), s, α1, α2 | χ² | mean BE surrogate (mm) | still on |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
        }
        for r in &self.rounds {
            let pressed: Vec<String> = r.pressed.iter().map(PressedBound::describe).collect();
            let c = &r.refit.coords;
            let _ = writeln!(
                s,
                "| {} | {} | {} ({}){} | {} | {}, {}, {}, {} | {:.1} | {:.2} | {} |",
                r.round,
                pressed.join("; "),
                r.cases,
                r.failed.len(),
                if r.cases_run == 0 {
                    ", read back".to_string()
                } else {
                    format!(", {:.0} s", r.fe_wall_time_s)
                },
                r.refit.model_cases,
                sig(c.mu0_mpa),
                sig(c.share),
                sig(c.alpha1),
                sig(c.alpha2),
                r.refit.chi2,
                r.refit.surrogate_mean_be_mm,
                bounds_or_none(&r.refit.active_bounds)
            );
        }
        let _ = writeln!(
            s,
            "\nStopped: {}. Final box: {}.",
            self.stop.describe(),
            self.final_box.describe()
        );
        s
    }
}

fn bounds_or_none(b: &[String]) -> String {
    if b.is_empty() {
        "no bound".into()
    } else {
        b.join("; ")
    }
}
