//! What a designer asks for: targets on the outputs, bounds on `N` and `T`, and the search's
//! settings.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::rom::{Surrogate, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::schema::{self, Quantity};

/// An output a target or a map is stated on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Output {
    /// Bending angle, degrees (`angle_deg`).
    AngleDeg,
    /// Blocked force, N (`force_n`).
    ForceN,
    /// Tip Uz, mm (`tip_uz_mm`).
    TipUzMm,
    /// Tip Uy, mm (`tip_uy_mm`).
    TipUyMm,
}

impl Output {
    /// Every output, in the order of the CSV columns.
    pub const ALL: [Output; 4] = [
        Output::TipUzMm,
        Output::TipUyMm,
        Output::AngleDeg,
        Output::ForceN,
    ];

    /// Its column: name, unit and meaning ([`schema`]).
    pub fn quantity(self) -> Quantity {
        match self {
            Output::AngleDeg => schema::ANGLE,
            Output::ForceN => schema::FORCE,
            Output::TipUzMm => schema::TIP_UZ,
            Output::TipUyMm => schema::TIP_UY,
        }
    }

    /// Its index among the surrogate's 22 quantities.
    pub fn index(self) -> usize {
        match self {
            Output::AngleDeg => Q_ANGLE,
            Output::ForceN => Q_FORCE,
            Output::TipUzMm => Q_TIP_UZ,
            Output::TipUyMm => Q_TIP_UY,
        }
    }

    /// The column name (`angle_deg`, …).
    pub fn name(self) -> &'static str {
        self.quantity().name
    }

    /// The unit (`deg`, `N`, `mm`).
    pub fn unit(self) -> &'static str {
        self.quantity().unit
    }
}

impl fmt::Display for Output {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Output {
    type Err = String;

    /// A column name (`angle_deg`) or its short form (`angle`, `force`, `tip_uz`, `tip_uy`).
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        Output::ALL
            .into_iter()
            .find(|o| {
                let name = o.name();
                s == name || name.rsplit_once('_').is_some_and(|(short, _)| s == short)
            })
            .ok_or_else(|| {
                format!(
                    "{s:?} is not an output: expected angle_deg, force_n, tip_uz_mm or tip_uy_mm"
                )
            })
    }
}

/// A target: output `output` at pressure `p_bar` should be `value`, with `tolerance` the
/// scale of its residual ([module docs](super)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Target {
    /// The output.
    pub output: Output,
    /// The pressure, bar (inside the model's pressure grid).
    pub p_bar: f64,
    /// The value, in the output's unit.
    pub value: f64,
    /// The scale of the residual, in the output's unit (> 0).
    pub tolerance: f64,
}

impl Target {
    /// A target.
    pub fn new(output: Output, p_bar: f64, value: f64, tolerance: f64) -> Self {
        Target {
            output,
            p_bar,
            value,
            tolerance,
        }
    }
}

/// The designs the search may choose from: `N` in `n.0 ..= n.1` (those the model predicts)
/// and `T` in `t_mm.0 ..= t_mm.1` mm (further capped per `N` by buildability).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignBounds {
    /// Smallest and largest number of bellows.
    pub n: (u32, u32),
    /// Smallest and largest wall thickness, mm.
    pub t_mm: (f64, f64),
}

impl DesignBounds {
    /// Bounds.
    pub fn new(n: (u32, u32), t_mm: (f64, f64)) -> Self {
        DesignBounds { n, t_mm }
    }

    /// The whole domain of `model`: its smallest to largest `N` and its range of `T`
    /// ([`Surrogate::domain`]).
    pub fn of_model(model: &Surrogate) -> Self {
        let n = (
            model.n_allowed.iter().copied().min().unwrap_or(0),
            model.n_allowed.iter().copied().max().unwrap_or(0),
        );
        let t = model_t_range(model);
        DesignBounds {
            n,
            t_mm: (t[0], t[1]),
        }
    }
}

/// Settings of the search in `T` ([module docs](super)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignSearch {
    /// Starting values of `T` per `N`, spread evenly over its interval (≥ 1; one: the middle).
    pub starts: usize,
    /// Largest number of Gauss–Newton iterations per start (≥ 1).
    pub max_iterations: usize,
    /// A step shorter than this (mm) ends a start (> 0).
    pub step_tolerance_mm: f64,
    /// Largest number of halvings of a step that raises the cost.
    pub max_halvings: usize,
}

impl Default for DesignSearch {
    fn default() -> Self {
        DesignSearch {
            starts: 13,
            max_iterations: 30,
            step_tolerance_mm: 1e-7,
            max_halvings: 12,
        }
    }
}

/// The model's range of `T`, mm.
pub(super) fn model_t_range(model: &Surrogate) -> [f64; 2] {
    model
        .domain()
        .ranges
        .get(1)
        .copied()
        .flatten()
        .or_else(|| model.inputs.get(1).map(|s| [s.min, s.max]))
        .unwrap_or([f64::NAN; 2])
}
