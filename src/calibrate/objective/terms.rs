//! What is recorded and how much each term counts: outputs, terms, weights.

use std::collections::BTreeSet;

use serde::{Deserialize, Serialize};

use crate::calibrate::CalibrateError;
use crate::schema::{self, Quantity};

/// One recorded output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Output {
    /// Tip `Uz` (mm).
    TipUz,
    /// Tip `Uy` (mm).
    TipUy,
    /// Bending angle (deg).
    Angle,
    /// Blocked force (N).
    Force,
    /// Marker `k` (1..9) `Uz` (mm).
    MarkerUz(u8),
    /// Marker `k` (1..9) `Uy` (mm).
    MarkerUy(u8),
}

impl Output {
    /// Index of the output among the surrogate's 22 quantities.
    pub fn quantity(self) -> usize {
        match self {
            Output::TipUz => crate::rom::Q_TIP_UZ,
            Output::TipUy => crate::rom::Q_TIP_UY,
            Output::Angle => crate::rom::Q_ANGLE,
            Output::Force => crate::rom::Q_FORCE,
            Output::MarkerUz(k) => 2 * (k as usize - 1),
            Output::MarkerUy(k) => 2 * (k as usize - 1) + 1,
        }
    }

    /// The term of the objective the output belongs to.
    pub fn term(self) -> Term {
        match self {
            Output::TipUz | Output::TipUy => Term::Tip,
            Output::Angle => Term::Angle,
            Output::Force => Term::Force,
            Output::MarkerUz(_) | Output::MarkerUy(_) => Term::Markers,
        }
    }

    /// A readable name: the output's [`schema`] column (`tip_uz_mm`, `m3_uy_mm`, …).
    pub fn name(self) -> String {
        let marker = |list: &[Quantity; 9], k: u8, component: &str| match list
            .get(usize::from(k).wrapping_sub(1))
        {
            Some(q) => q.name.to_string(),
            None => format!("marker {k} {component} (not a marker 1..9)"),
        };
        match self {
            Output::TipUz => schema::TIP_UZ.name.into(),
            Output::TipUy => schema::TIP_UY.name.into(),
            Output::Angle => schema::ANGLE.name.into(),
            Output::Force => schema::FORCE.name.into(),
            Output::MarkerUz(k) => marker(&schema::MARKER_UZ, k, "Uz"),
            Output::MarkerUy(k) => marker(&schema::MARKER_UY, k, "Uy"),
        }
    }

    /// Name of the surrogate's validation entry holding this output's held-out error.
    pub(super) fn validation_name(self) -> &'static str {
        match self {
            Output::TipUz => schema::TIP_UZ.name,
            Output::TipUy => schema::TIP_UY.name,
            Output::Angle => schema::ANGLE.name,
            Output::Force => schema::FORCE.name,
            Output::MarkerUz(_) | Output::MarkerUy(_) => schema::MARKERS.name,
        }
    }
}

/// A term of the objective.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// Tip Uz and Uy (the study's BE).
    Tip,
    /// Bending angle.
    Angle,
    /// Blocked force.
    Force,
    /// Markers along the actuator.
    Markers,
}

impl Term {
    /// All terms.
    pub const ALL: [Term; 4] = [Term::Tip, Term::Angle, Term::Force, Term::Markers];

    /// Name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Term::Tip => "tip",
            Term::Angle => "angle",
            Term::Force => "force",
            Term::Markers => "markers",
        }
    }
}

/// Weight of each term (0 = not fitted).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Weights {
    /// Tip Uz, Uy.
    pub tip: f64,
    /// Angle.
    pub angle: f64,
    /// Blocked force.
    pub force: f64,
    /// Markers.
    pub markers: f64,
}

impl Default for Weights {
    /// `tip` alone (the study's objective).
    fn default() -> Self {
        Weights {
            tip: 1.0,
            angle: 0.0,
            force: 0.0,
            markers: 0.0,
        }
    }
}

impl Weights {
    /// Weight of a term.
    pub fn of(&self, t: Term) -> f64 {
        match t {
            Term::Tip => self.tip,
            Term::Angle => self.angle,
            Term::Force => self.force,
            Term::Markers => self.markers,
        }
    }

    fn set(&mut self, t: Term, w: f64) {
        match t {
            Term::Tip => self.tip = w,
            Term::Angle => self.angle = w,
            Term::Force => self.force = w,
            Term::Markers => self.markers = w,
        }
    }

    /// Parses `tip`, `angle`, `force`, `markers`, `all`, or a weighted list such as
    /// `tip=1,force=0.5` (terms not named get 0).
    ///
    /// # Errors
    /// An unknown term, a weight that is not a finite number ≥ 0, a term named twice, or all
    /// weights zero.
    pub fn parse(text: &str) -> Result<Self, CalibrateError> {
        let expected = "tip, angle, force, markers, all, or term=weight,... (e.g. tip=1,force=2)";
        let mut w = Weights {
            tip: 0.0,
            angle: 0.0,
            force: 0.0,
            markers: 0.0,
        };
        let mut seen = BTreeSet::new();
        for item in text.split(',').map(str::trim) {
            let (name, weight) = match item.split_once('=') {
                Some((n, v)) => {
                    let x: f64 = v.trim().parse().map_err(|_| {
                        CalibrateError::input(
                            &format!("objective weight of {n}"),
                            v,
                            "a number ≥ 0",
                        )
                    })?;
                    (n.trim(), x)
                }
                None => (item, 1.0),
            };
            if !(weight.is_finite() && weight >= 0.0) {
                return Err(CalibrateError::input(
                    &format!("objective weight of {name}"),
                    weight,
                    "a finite number ≥ 0",
                ));
            }
            let terms: Vec<Term> = if name == "all" {
                Term::ALL.to_vec()
            } else {
                vec![Term::ALL
                    .into_iter()
                    .find(|t| t.name() == name)
                    .ok_or_else(|| CalibrateError::input("objective", name, expected))?]
            };
            for t in terms {
                if !seen.insert(t) {
                    return Err(CalibrateError::input(
                        "objective",
                        text,
                        "each term at most once",
                    ));
                }
                w.set(t, weight);
            }
        }
        if Term::ALL.iter().all(|&t| w.of(t) == 0.0) {
            return Err(CalibrateError::input(
                "objective",
                text,
                "at least one weight > 0",
            ));
        }
        Ok(w)
    }

    /// `tip=1,force=0.5` form of the non-zero weights.
    pub fn describe(&self) -> String {
        Term::ALL
            .iter()
            .filter(|&&t| self.of(t) > 0.0)
            .map(|&t| format!("{}={}", t.name(), self.of(t)))
            .collect::<Vec<_>>()
            .join(",")
    }
}
