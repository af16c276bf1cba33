//! What a design search returns: the best wall per number of bellows, how each search
//! stopped, the pick and its two errors.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::target::{Output, Target};
use crate::case::OgdenSet;
use crate::rom::model_form;

/// How a search in `T` from one start ended ([module docs](super)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// The step fell below the tolerance: a stationary point.
    Converged,
    /// On an end of the interval, with the descent pointing out of it.
    Bound,
    /// No shortened step lowered the cost.
    NoDescent,
    /// The outputs do not change with `T` there (`Σ J² = 0`).
    Flat,
    /// The iteration limit was reached.
    Iterations,
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stop::Converged => "converged",
            Stop::Bound => "on a bound",
            Stop::NoDescent => "no descent",
            Stop::Flat => "flat in T",
            Stop::Iterations => "iteration limit",
        })
    }
}

/// Which end of the interval of `T`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The smallest `T`.
    Lower,
    /// The largest `T`.
    Upper,
}

/// What sets an end of the interval of `T`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TLimit {
    /// The designer's bounds ([`super::DesignBounds`]).
    Bounds,
    /// The model's training range of `T`.
    Model,
    /// The largest wall that leaves a cavity for this `N` (buildability).
    Buildable,
}

impl fmt::Display for TLimit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TLimit::Bounds => "the given bounds",
            TLimit::Model => "the model's range",
            TLimit::Buildable => "the buildable wall",
        })
    }
}

/// An optimum on an end of the interval of `T`: a target that no wall in the interval
/// reaches pushes it there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BoundHit {
    /// Which end.
    pub side: Side,
    /// What sets it.
    pub limit: TLimit,
}

impl fmt::Display for BoundHit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let side = match self.side {
            Side::Lower => "lower",
            Side::Upper => "upper",
        };
        write!(f, "on the {side} bound ({})", self.limit)
    }
}

/// The best wall found for one number of bellows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Wall thickness, mm.
    pub t_mm: f64,
    /// Its cost `Φ`.
    pub cost: f64,
    /// The predicted value of each target's output, in target order.
    pub predicted: Vec<f64>,
    /// The end of the interval it lies on, if any.
    pub bound: Option<BoundHit>,
    /// Gauss–Newton steps taken from its start.
    pub iterations: usize,
    /// How the search from its start ended.
    pub stop: Stop,
}

/// The search for one number of bellows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignAtN {
    /// Number of bellows.
    pub n: u32,
    /// The interval of `T` searched, mm (`t_max_mm < t_min_mm`: no buildable wall in the
    /// bounds).
    pub t_min_mm: f64,
    /// Its upper end, mm.
    pub t_max_mm: f64,
    /// What sets the upper end.
    pub t_max_limit: TLimit,
    /// The best wall (`None`: no buildable wall in the bounds).
    pub best: Option<Candidate>,
}

/// One target at the pick: the prediction and its two errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PickedOutput {
    /// The target.
    pub target: Target,
    /// The predicted value.
    pub predicted: f64,
    /// The surrogate's standard deviation: its error against the FE model.
    pub surrogate_std: f64,
    /// The model-form error (rms of the calibration residuals at this pressure), `None`
    /// when the model file carries none for this output.
    pub model_form: Option<f64>,
}

/// The design of least cost over every `N`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pick {
    /// Number of bellows.
    pub n: u32,
    /// Wall thickness, mm.
    pub t_mm: f64,
    /// Its cost `Φ`.
    pub cost: f64,
    /// The end of the interval it lies on, if any.
    pub bound: Option<BoundHit>,
    /// Each target at the pick.
    pub outputs: Vec<PickedOutput>,
}

/// Whether the accuracy of a prediction against real actuators is known.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Accuracy {
    /// The model file carries a model-form error, learned from this calibration report.
    Known {
        /// The calibration report.
        calibration_report: String,
    },
    /// The model file carries none: the accuracy against real actuators is unknown.
    Unknown,
}

impl fmt::Display for Accuracy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Accuracy::Known { calibration_report } => {
                write!(f, "{} from {calibration_report}", model_form::LABEL)
            }
            Accuracy::Unknown => write!(
                f,
                "the model file carries no {}: the accuracy against real actuators is unknown \
                 (the std is the {} only)",
                model_form::LABEL,
                model_form::STD_LABEL
            ),
        }
    }
}

/// Surrogate evaluations of a search, each at one design and one pressure.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Evaluations {
    /// Values only, on the starting scans (the scalar fast path).
    pub scan: usize,
    /// Values and derivatives in `T`, in the descents.
    pub gradient: usize,
}

/// The result of [`super::search`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignReport {
    /// The material the outputs were predicted with (in the file: `[μ₁ MPa, α₁, μ₂ MPa, α₂]`).
    #[serde(with = "crate::case::material::array")]
    pub material: OgdenSet,
    /// The targets.
    pub targets: Vec<Target>,
    /// The geometry preset buildability was judged with.
    pub geometry: String,
    /// One entry per number of bellows searched, increasing.
    pub designs: Vec<DesignAtN>,
    /// The design of least cost.
    pub pick: Pick,
    /// Whether the model-form errors of the pick are known.
    pub accuracy: Accuracy,
    /// Surrogate evaluations the search made.
    pub evaluations: Evaluations,
}

impl DesignReport {
    /// The search for `n` bellows, if it was searched.
    pub fn at(&self, n: u32) -> Option<&DesignAtN> {
        self.designs.iter().find(|d| d.n == n)
    }

    /// The outputs the targets are stated on, each once, in target order.
    pub fn outputs(&self) -> Vec<Output> {
        let mut out: Vec<Output> = Vec::new();
        for t in &self.targets {
            if !out.contains(&t.output) {
                out.push(t.output);
            }
        }
        out
    }
}
