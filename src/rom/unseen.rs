//! A model against FE cases it never saw: every case of a snapshot set predicted at its design,
//! material and every grid pressure above zero, and compared with its FE. This is how a model
//! is checked end to end on new designs (for example standard-mesh runs at designs spread over
//! the space), and how [`super::held_out_n`] scores the numbers of bellows it held out.
//!
//! ```no_run
//! use surrogate::rom::{unseen, SnapshotSet, Surrogate};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let model = Surrogate::load("models/actuator.json".as_ref())?;
//! let set = SnapshotSet::read("new_designs.csv".as_ref())?.into_cases()?;
//! let report = unseen::check(&model, &set)?;
//! println!("{}", report.table());
//! # Ok(()) }
//! ```
//!
//! The errors are mean absolute errors over the cases and pressures: the tip as the distance
//! between the predicted and the FE tip positions (mm), the bending angle (°) and the blocked
//! force (N, where the set has one).

use serde::{Deserialize, Serialize};

pub use super::metrics::HeldOutErrors;

use super::data::CaseSet;
use super::{RomError, Surrogate, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::Query;

/// One case's errors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnseenCase {
    /// Case identifier.
    pub case_id: String,
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness, mm.
    pub t_mm: f64,
    /// The case's errors (one case).
    pub errors: HeldOutErrors,
}

/// The result of [`check`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnseenReport {
    /// The numbers of bellows of the set, ascending.
    pub n_values: Vec<u32>,
    /// Errors per number of bellows, in `n_values` order.
    pub per_n: Vec<HeldOutErrors>,
    /// Errors over every case.
    pub all: HeldOutErrors,
    /// Every case, in the set's order.
    pub cases: Vec<UnseenCase>,
}

impl UnseenReport {
    /// A text table: one row per case, one per `N` and one for all.
    pub fn table(&self) -> String {
        let mut s =
            String::from("mean |error| over the case's pressures > 0 (tip: distance, mm)\n");
        s.push_str("  case          N    T mm  points  tip mm  (max)   angle °  force N\n");
        for c in &self.cases {
            s.push_str(&format!(
                "  {:<12} {:>2}  {:>6.3}  {}",
                c.case_id,
                c.n_bellows,
                c.t_mm,
                row_tail(&c.errors)
            ));
        }
        s.push_str(&HeldOutErrors::rows_by_n(
            &self.n_values,
            &self.per_n,
            &self.all,
        ));
        s
    }
}

fn row_tail(e: &HeldOutErrors) -> String {
    format!(
        "{:>6}  {:>6.3}  ({:>5.2})  {:>7.3}  {:>7.4}\n",
        e.points, e.tip_mm, e.max_tip_mm, e.angle_deg, e.force_n
    )
}

/// Predicts every case of `set` with `model` and compares with the FE.
///
/// # Errors
/// [`RomError::InvalidInput`] naming the case when the model cannot predict it (a number of
/// bellows it does not predict, an input outside its domain); an empty set.
pub fn check(model: &Surrogate, set: &CaseSet) -> Result<UnseenReport, RomError> {
    let mut n_values: Vec<u32> = set.cases.iter().map(|c| c.inputs.n_bellows).collect();
    n_values.sort_unstable();
    n_values.dedup();
    if n_values.is_empty() {
        return Err(RomError::InsufficientData(
            "the set has no complete case to check".into(),
        ));
    }
    errors_by_n(model, set, &n_values)
}

/// Scores the cases of `set` whose `N` is in `n_values`, grouped by it.
pub(crate) fn errors_by_n(
    model: &Surrogate,
    set: &CaseSet,
    n_values: &[u32],
) -> Result<UnseenReport, RomError> {
    let mut pred = model.new_prediction();
    let mut per_n = vec![Sums::default(); n_values.len()];
    let mut cases = Vec::new();
    for case in &set.cases {
        let Some(k) = n_values.iter().position(|&n| n == case.inputs.n_bellows) else {
            continue;
        };
        let mut one = Sums {
            cases: 1,
            ..Sums::default()
        };
        for (p, fe) in set.pressures.iter().zip(&case.values) {
            if *p <= 0.0 {
                continue;
            }
            let q = Query::from_case(&case.inputs, *p);
            model.predict_scalars_into(&q, &mut pred).map_err(|e| {
                RomError::invalid(
                    "case",
                    &case.case_id,
                    &format!("a case the model predicts ({e})"),
                )
            })?;
            let tip = (pred.tip_uz_mm() - fe[Q_TIP_UZ]).hypot(pred.tip_uy_mm() - fe[Q_TIP_UY]);
            // a bending-only set has no force: its cell is NaN
            let force = (pred.force_n() - fe[Q_FORCE]).abs();
            one.add(tip, (pred.angle_deg() - fe[Q_ANGLE]).abs(), force);
        }
        per_n[k].merge(&one);
        cases.push(UnseenCase {
            case_id: case.case_id.clone(),
            n_bellows: case.inputs.n_bellows,
            t_mm: case.inputs.wall_thickness_mm,
            errors: one.finish(),
        });
    }
    let mut all = Sums::default();
    for s in &per_n {
        all.merge(s);
    }
    Ok(UnseenReport {
        n_values: n_values.to_vec(),
        per_n: per_n.iter().map(Sums::finish).collect(),
        all: all.finish(),
        cases,
    })
}

#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    cases: usize,
    points: usize,
    force_points: usize,
    tip: f64,
    angle: f64,
    force: f64,
    max_tip: f64,
}

impl Sums {
    fn add(&mut self, tip: f64, angle: f64, force: f64) {
        self.points += 1;
        self.tip += tip;
        self.angle += angle;
        if force.is_finite() {
            self.force_points += 1;
            self.force += force;
        }
        self.max_tip = self.max_tip.max(tip);
    }

    fn merge(&mut self, o: &Sums) {
        self.cases += o.cases;
        self.points += o.points;
        self.force_points += o.force_points;
        self.tip += o.tip;
        self.angle += o.angle;
        self.force += o.force;
        self.max_tip = self.max_tip.max(o.max_tip);
    }

    fn finish(&self) -> HeldOutErrors {
        let m = self.points.max(1) as f64;
        HeldOutErrors {
            cases: self.cases,
            points: self.points,
            tip_mm: self.tip / m,
            angle_deg: self.angle / m,
            force_n: self.force / self.force_points.max(1) as f64,
            max_tip_mm: self.max_tip,
        }
    }
}
