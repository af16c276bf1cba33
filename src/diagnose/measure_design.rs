//! What to measure next: up to three measurements that would best tell apart the candidates
//! the recordings cannot separate.
//!
//! The tie set is the Name stage's ([`super::name`]): the leading candidate `ℓ` (the named
//! one, else the first of the ranking) and every candidate reported as indistinguishable from
//! it. The measurements that could be added are those the FE sensitivity sweep evaluates and
//! the recordings lack, each with the σ it would be recorded with ([`super::measurements`]).
//!
//! The criterion is T-optimality for model discrimination (Atkinson and Fedorov 1975;
//! [`super::discrimination`] has the formulas). Each candidate is fitted jointly with the
//! material on the recorded cells (linearised with the sweep, weighed as the Name stage weighs
//! them); if it is the truth at that size, the rival, refitted with the material on the
//! recorded cells and the added measurements, misses them by
//!
//! ```text
//!   T_ab(ξ) = θ̂_a² ‖ P⊥_[M b] a ‖²_ξ,      δ_ab = min(T_ab, T_ba)
//! ```
//!
//! (in σ², the expected increase of the wrong candidate's `χ²`; over `ŝ²`, the scatter the
//! leading candidate's fit leaves, where that exceeds the recordings' σ, as the Name stage's
//! tests measure it: [`Discrimination::scale`](super::discrimination::Discrimination::scale)).
//! Up to `k ≤ 3` measurements
//! are added greedily, each raising the separations `δ_ℓj` of every rival `j` most (leximin:
//! the weakest first). Each planned item reports, for the two leading candidates (`ℓ` and the
//! first rival of the ranking), the expected separation `√δ` in σ and the expected log Bayes
//! factor `δ/2` once it and the items before it are added, and the gain of `δ/2` it brings;
//! and the rival then least separated from `ℓ`.
//!
//! The added measurements are taken independent of the recorded cells and of each other, with
//! their own σ only (the diagnosing model's error covariance, when given, weighs the recorded
//! cells alone), and the expectation is that of the linearised models at the fitted sizes: a
//! plan to test, not a promise.

use nalgebra::DVector;
use serde::{Deserialize, Serialize};

use super::approx_error::ErrorSpread;
use super::cells::Cell;
use super::discrimination::Pick;
use super::measurements::{candidates, discrimination, Measurement, MeasurementKind};
use super::name::{derivs_of, sweep_parameters, whitening, Naming};
use super::DiagnoseError;
use crate::calibrate::baseline::SweepSensitivities;
use crate::calibrate::objective::Output;
use crate::fe::effects::Effect;
use crate::fe::sensitivity::Parameter;

/// The most measurements a plan proposes.
pub const MAX_PLANNED: usize = 3;

/// Settings of [`plan`].
#[derive(Clone, Debug, PartialEq, Default)]
pub struct PlanSettings {
    /// Measurements to propose, 1..=[`MAX_PLANNED`].
    pub k: usize,
    /// The diagnosing model's error covariance over the cells, as the Name stage weighs them
    /// ([`super::name::NameSettings::error_spread`]).
    pub error_spread: Option<ErrorSpread>,
    /// The kinds of measurement the plan may propose (empty: every kind the sweep
    /// evaluates). A lab that cannot move its plate, or the blind study, whose twins' FE
    /// holds the recorded designs only, narrows it.
    pub kinds: Vec<MeasurementKind>,
}

impl PlanSettings {
    /// `k` measurements, the recordings' σ alone.
    pub fn new(k: usize) -> Self {
        PlanSettings {
            k,
            error_spread: None,
            kinds: Vec::new(),
        }
    }

    /// # Errors
    /// [`DiagnoseError::Input`] for `k` outside `1..=MAX_PLANNED`.
    pub fn validate(&self) -> Result<(), DiagnoseError> {
        if !(1..=MAX_PLANNED).contains(&self.k) {
            return Err(DiagnoseError::input(
                "measurements to plan",
                self.k,
                &format!("1 to {MAX_PLANNED}"),
            ));
        }
        Ok(())
    }
}

/// One measurement of the plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedMeasurement {
    /// What to measure, and with which σ.
    pub measurement: Measurement,
    /// The other outputs the same reading gives (a marker's other component; the tip and the
    /// angle of one pose), counted with it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<String>,
    /// `√δ` of the two leading candidates once this and the items before it are added (σ).
    pub separation_sigma: f64,
    /// `δ/2`: the expected log Bayes factor between the two leading candidates then.
    pub log_bayes_factor: f64,
    /// What this item adds to [`Self::log_bayes_factor`].
    pub gain: f64,
    /// The rival then least separated from the leading candidate.
    pub weakest: String,
    /// Its `√δ` (σ).
    pub weakest_separation_sigma: f64,
}

impl PlannedMeasurement {
    /// The measurement in words, with the outputs its reading also gives:
    /// `m8_uy_mm at N = 13, T = 2.4 mm, 2 bar (bending), with m8_uz_mm`.
    pub fn text(&self) -> String {
        if self.also.is_empty() {
            self.measurement.text()
        } else {
            format!("{}, with {}", self.measurement.text(), self.also.join(", "))
        }
    }
}

/// The plan: what to measure next to separate the tied candidates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeasurementPlan {
    /// The criterion, in words.
    pub criterion: String,
    /// The leading candidate.
    pub leader: String,
    /// The candidates tied with it that the plan separates, in the ranking's order.
    pub rivals: Vec<String>,
    /// Tied candidates the plan cannot score (the model's own error has no FE sensitivities
    /// at unrecorded outputs), in words.
    pub left_out: Vec<String>,
    /// Measurements considered.
    pub considered: usize,
    /// `ŝ`: the scatter, in the recordings' σ, that the separations are measured in (the
    /// leading candidate's fit on the recorded cells, at least 1).
    pub scale: f64,
    /// `√δ` of the two leading candidates on the recordings alone (σ).
    pub separation_sigma: f64,
    /// `δ/2` on the recordings alone.
    pub log_bayes_factor: f64,
    /// The measurements, in the order chosen.
    pub items: Vec<PlannedMeasurement>,
    /// Why the plan is empty or short, when it is.
    pub note: String,
}

/// The criterion as the plan states it.
const CRITERION: &str = "T-optimal discrimination (Atkinson–Fedorov): δ = min(T_ab, T_ba), \
    T_ab = θ̂_a² ‖P⊥[M b] a‖², the material refitted; greedy, leximin over the rivals of the \
    leading candidate";

/// The leading candidate and its tied rivals (ranking order), and the tied candidates that
/// are errors of the model itself.
fn tie_set(n: &Naming) -> Option<(String, Vec<String>, Vec<String>)> {
    let leader = n
        .named()
        .or_else(|| n.candidates.iter().find(|c| !c.model_error))?;
    let tied = |c: &str| {
        n.indistinguishable
            .iter()
            .any(|p| (p.a == leader.effect && p.b == c) || (p.b == leader.effect && p.a == c))
    };
    let (mut rivals, mut left_out) = (Vec::new(), Vec::new());
    for c in n.candidates.iter().filter(|c| tied(&c.effect)) {
        if c.model_error {
            left_out.push(format!(
                "{}: an error of the diagnosing model, without FE sensitivities at unrecorded \
                 outputs",
                c.effect
            ));
        } else {
            rivals.push(c.effect.clone());
        }
    }
    Some((leader.effect.clone(), rivals, left_out))
}

/// The recorded cells' whitened residual and a column per parameter of the sweep.
fn recorded(
    cells: &[Cell],
    sens: &SweepSensitivities,
    spread: Option<&ErrorSpread>,
) -> Result<(DVector<f64>, Vec<DVector<f64>>), DiagnoseError> {
    let mut rows: Vec<(&Cell, Vec<f64>)> = Vec::new();
    let mut row_cell = Vec::new();
    for (i, c) in cells.iter().enumerate() {
        if let Some(d) = derivs_of(sens, c) {
            rows.push((c, d));
            row_cell.push(i);
        }
    }
    let n = rows.len();
    let width = rows.first().map_or(0, |r| r.1.len());
    if n == 0 || rows.iter().any(|r| r.1.len() != width) {
        return Err(DiagnoseError::input(
            "cells with sensitivities",
            n,
            "at least one, every ramp with the same parameters",
        ));
    }
    let l = whitening(spread, cells, &rows, &row_cell)?;
    let w = |v: DVector<f64>| match &l {
        Some(l) => l
            .solve_lower_triangular(&v)
            .expect("a Cholesky factor of I + DDᵀ is regular"),
        None => v,
    };
    let z = w(DVector::from_iterator(
        n,
        rows.iter().map(|(c, _)| c.standardised),
    ));
    let columns = (0..width)
        .map(|j| w(DVector::from_iterator(n, rows.iter().map(|(_, d)| d[j]))))
        .collect();
    Ok((z, columns))
}

/// The measurement plan for the candidates of `naming` that the recordings `cells` cannot
/// separate (see the [module docs](self)), with the FE sensitivities `sens`. A tie set of one
/// gives an empty plan that says why.
///
/// # Errors
/// [`DiagnoseError::Input`] for a bad setting, a sweep without the material's parameters or
/// without sensitivities at the recorded cells.
pub fn plan(
    cells: &[Cell],
    sens: &SweepSensitivities,
    naming: &Naming,
    s: &PlanSettings,
) -> Result<MeasurementPlan, DiagnoseError> {
    s.validate()?;
    let params: Vec<Parameter> = sweep_parameters(sens);
    let Some((leader, rivals, left_out)) = tie_set(naming) else {
        return Ok(empty("", "the Name stage has no candidate effect".into()));
    };
    if rivals.is_empty() {
        let mut p = empty(&leader, format!("no candidate is tied with {leader}"));
        p.left_out = left_out;
        return Ok(p);
    }
    let effects = std::iter::once(&leader)
        .chain(&rivals)
        .map(|e| Effect::from_name(e).map(Parameter::Effect))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| DiagnoseError::input("tied candidate", e, "an effect of the library"))?;
    let (z, columns) = recorded(cells, sens, s.error_spread.as_ref())?;
    let items = menu(cells, sens, &params, &s.kinds);
    let column = |p: Parameter| {
        params
            .iter()
            .position(|q| *q == p)
            .map(|j| columns[j].clone())
    };
    let d = discrimination(&z, column, &params, &effects, &items).ok_or_else(|| {
        DiagnoseError::input(
            "sensitivities",
            "without mu1, alpha1, mu2, alpha2 or a tied effect",
            "a sweep with the material's four parameters and every effect",
        )
    })?;
    let others: Vec<usize> = (1..effects.len()).collect();
    let scale = d.scale(0);
    let records = records(&items);
    let mut picks = d.greedy_records(0, &others, s.k, &records);
    picks
        .iter_mut()
        .for_each(|p| p.separations.iter_mut().for_each(|v| *v /= scale));
    let before = d.separation(0, 1, &[]) / scale;
    let planned = planned(&picks, &items, &records, &rivals, before);
    let note = if planned.len() < s.k {
        format!(
            "only {} of the {} measurements asked for raise the separation",
            planned.len(),
            s.k
        )
    } else {
        String::new()
    };
    Ok(MeasurementPlan {
        criterion: CRITERION.into(),
        leader,
        rivals,
        left_out,
        considered: items.len(),
        scale: scale.sqrt(),
        separation_sigma: before.sqrt(),
        log_bayes_factor: before / 2.0,
        items: planned,
        note,
    })
}

/// The measurements of [`candidates`] whose kind `kinds` admits (empty: every kind), with
/// their rows in the order of `params`.
pub(crate) fn menu(
    cells: &[Cell],
    sens: &SweepSensitivities,
    params: &[Parameter],
    kinds: &[MeasurementKind],
) -> Vec<(Measurement, Vec<f64>)> {
    let mut items = candidates(cells, sens, params);
    if !kinds.is_empty() {
        items.retain(|(m, _)| kinds.contains(&m.kind));
    }
    items
}

fn empty(leader: &str, note: String) -> MeasurementPlan {
    MeasurementPlan {
        criterion: CRITERION.into(),
        leader: leader.into(),
        rivals: Vec::new(),
        left_out: Vec::new(),
        considered: 0,
        scale: 1.0,
        separation_sigma: 0.0,
        log_bayes_factor: 0.0,
        items: Vec::new(),
        note,
    }
}

/// The record of each measurement, as an index: what one reading gives together. A marker's
/// two components; the tip's two components and the angle of one pose (a photograph at a
/// pressure); a force reading, at the recorded plate height or a moved one.
pub(crate) fn records(items: &[(Measurement, Vec<f64>)]) -> Vec<usize> {
    let key = |m: &Measurement| {
        let what = match m.output {
            Output::TipUz | Output::TipUy | Output::Angle => "pose".to_string(),
            Output::MarkerUz(k) | Output::MarkerUy(k) => format!("marker {k}"),
            Output::Force if m.kind == MeasurementKind::PlateHeight => "force, plate moved".into(),
            Output::Force => "force".into(),
        };
        (
            m.n_bellows,
            m.wall_thickness_mm.to_bits(),
            m.pressure_bar.to_bits(),
            what,
        )
    };
    let mut seen: Vec<(u32, u64, u64, String)> = Vec::new();
    items
        .iter()
        .map(|(m, _)| {
            let k = key(m);
            seen.iter().position(|s| *s == k).unwrap_or_else(|| {
                seen.push(k);
                seen.len() - 1
            })
        })
        .collect()
}

/// The greedy picks as planned measurements, the leading pair's separation after each, each
/// with the other outputs its record gives.
fn planned(
    picks: &[Pick],
    items: &[(Measurement, Vec<f64>)],
    records: &[usize],
    rivals: &[String],
    before: f64,
) -> Vec<PlannedMeasurement> {
    let mut out: Vec<PlannedMeasurement> = Vec::new();
    let mut previous = before / 2.0;
    for p in picks {
        let lead = p.separations[0];
        let (weakest, min) = p
            .separations
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .map_or((0, 0.0), |(j, v)| (j, *v));
        let also = (0..items.len())
            .filter(|&j| j != p.item && records[j] == records[p.item])
            .map(|j| items[j].0.output.name())
            .collect();
        out.push(PlannedMeasurement {
            measurement: items[p.item].0.clone(),
            also,
            separation_sigma: lead.sqrt(),
            log_bayes_factor: lead / 2.0,
            gain: lead / 2.0 - previous,
            weakest: rivals[weakest].clone(),
            weakest_separation_sigma: min.sqrt(),
        });
        previous = lead / 2.0;
    }
    out
}

impl MeasurementPlan {
    /// The plan in a few lines of Markdown.
    pub fn markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        if self.items.is_empty() {
            let _ = writeln!(s, "No plan: {}.", self.note);
            return s;
        }
        let first = &self.rivals[0];
        let _ = writeln!(
            s,
            "The recordings cannot tell {} from {}. On them, {} and {first} are {:.2} σ apart \
             (expected log Bayes factor {:.2}; σ the recordings' σ times the scatter {:.2} the \
             fit leaves). Measured with the σ given, these {} of the {} measurements the FE \
             sensitivities can evaluate would separate them most:\n",
            self.leader,
            super::wording::and_list(self.rivals.clone()),
            self.leader,
            self.separation_sigma,
            self.log_bayes_factor,
            self.scale,
            self.items.len(),
            self.considered
        );
        for (i, it) in self.items.iter().enumerate() {
            let m = &it.measurement;
            let _ = writeln!(
                s,
                "{}. {} ({}; σ = {:.3} {}, {}): {} vs {first} {:.2} σ apart, expected log Bayes \
                 factor {:.2} (+{:.2}); least separated: {} at {:.2} σ.",
                i + 1,
                it.text(),
                m.kind.label(),
                m.sigma,
                super::cells::Family::of(m.output).unit(),
                m.sigma_from,
                self.leader,
                it.separation_sigma,
                it.log_bayes_factor,
                it.gain,
                it.weakest,
                it.weakest_separation_sigma
            );
        }
        for l in &self.left_out {
            let _ = writeln!(s, "\nNot scored: {l}.");
        }
        if !self.note.is_empty() {
            let _ = writeln!(s, "\nNote: {}.", self.note);
        }
        let _ = writeln!(
            s,
            "\nCriterion: {}; the expectation of the linearised models at their fitted sizes.",
            self.criterion
        );
        s
    }
}
