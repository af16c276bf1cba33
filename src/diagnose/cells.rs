//! The residual table: one standardised residual per recorded number at the calibrated set,
//! the fitted outputs from the calibration, the others predicted through the same surrogate.

use serde::{Deserialize, Serialize};

use super::DiagnoseError;
use crate::calibrate::objective::{
    Evaluator, Exclusion, ObservationSet, Output, Recording, Recordings, Selection, Weights,
};
use crate::calibrate::Calibration;
use crate::case::Query;
use crate::rom::Surrogate;

/// An output as the diagnosis groups it: a scalar output, or one component of the markers
/// (all markers together; the marker number is a cell's position along the actuator).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    /// Tip `Uz` (mm).
    TipUz,
    /// Tip `Uy` (mm).
    TipUy,
    /// Bending angle (deg).
    Angle,
    /// Blocked force (N).
    Force,
    /// Markers' `Uz` (mm).
    MarkerUz,
    /// Markers' `Uy` (mm).
    MarkerUy,
}

impl Family {
    /// Every family, in report order.
    pub const ALL: [Family; 6] = [
        Family::TipUz,
        Family::TipUy,
        Family::Angle,
        Family::Force,
        Family::MarkerUz,
        Family::MarkerUy,
    ];

    /// The family of an output.
    pub fn of(o: Output) -> Family {
        match o {
            Output::TipUz => Family::TipUz,
            Output::TipUy => Family::TipUy,
            Output::Angle => Family::Angle,
            Output::Force => Family::Force,
            Output::MarkerUz(_) => Family::MarkerUz,
            Output::MarkerUy(_) => Family::MarkerUy,
        }
    }

    /// Name in sentences and tables (`tip Uz`, `blocked force`).
    pub fn label(self) -> &'static str {
        match self {
            Family::TipUz => "tip Uz",
            Family::TipUy => "tip Uy",
            Family::Angle => "bending angle",
            Family::Force => "blocked force",
            Family::MarkerUz => "marker Uz",
            Family::MarkerUy => "marker Uy",
        }
    }

    /// Unit of the recorded values.
    pub fn unit(self) -> &'static str {
        match self {
            Family::Angle => "deg",
            Family::Force => "N",
            _ => "mm",
        }
    }

    /// Whether a residual of sign `sign` (predicted − recorded) means that the model bends
    /// further than the actuator (`Some(true)`), less far (`Some(false)`), or neither (the
    /// force). `Uz = −Δz` grows as the tip curls back towards the support; `Uy = Δy` is
    /// negative downwards; the angle grows with bending.
    pub fn bends_too_far(self, sign: f64) -> Option<bool> {
        match self {
            Family::TipUz | Family::MarkerUz | Family::Angle => Some(sign > 0.0),
            Family::TipUy | Family::MarkerUy => Some(sign < 0.0),
            Family::Force => None,
        }
    }

    /// What a residual of sign `sign` says, in words (`predicts less force than recorded`).
    pub fn direction(self, sign: f64) -> &'static str {
        let up = sign > 0.0;
        match (self, up) {
            (Family::TipUz | Family::MarkerUz, true) => "predicts more Uz than recorded",
            (Family::TipUz | Family::MarkerUz, false) => "predicts less Uz than recorded",
            (Family::TipUy | Family::MarkerUy, true) => "predicts less downward Uy than recorded",
            (Family::TipUy | Family::MarkerUy, false) => "predicts more downward Uy than recorded",
            (Family::Angle, true) => "predicts a larger angle than recorded",
            (Family::Angle, false) => "predicts a smaller angle than recorded",
            (Family::Force, true) => "predicts more force than recorded",
            (Family::Force, false) => "predicts less force than recorded",
        }
    }
}

/// A group of cells: those sharing one value of a factor (or all of them).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "by")]
pub enum Group {
    /// One design.
    Design {
        /// Number of bellows.
        n_bellows: u32,
        /// Wall thickness (mm).
        wall_thickness_mm: f64,
    },
    /// One number of bellows.
    N {
        /// Number of bellows.
        n_bellows: u32,
    },
    /// One wall thickness.
    T {
        /// Wall thickness (mm).
        wall_thickness_mm: f64,
    },
    /// One pressure.
    P {
        /// Pressure (bar).
        pressure_bar: f64,
    },
    /// One marker along the actuator.
    Marker {
        /// Marker number 1..9 (9 is the tip).
        marker: u8,
    },
}

impl Group {
    /// Whether a cell belongs to the group.
    pub fn holds(&self, c: &Cell) -> bool {
        let eq = |a: f64, b: f64| (a - b).abs() < 1e-9;
        match *self {
            Group::Design {
                n_bellows,
                wall_thickness_mm,
            } => c.n_bellows == n_bellows && eq(c.wall_thickness_mm, wall_thickness_mm),
            Group::N { n_bellows } => c.n_bellows == n_bellows,
            Group::T { wall_thickness_mm } => eq(c.wall_thickness_mm, wall_thickness_mm),
            Group::P { pressure_bar } => eq(c.pressure_bar, pressure_bar),
            Group::Marker { marker } => c.marker == Some(marker),
        }
    }

    /// The group in words (`T = 1.6 mm`, `N = 9, T = 2 mm`).
    pub fn label(&self) -> String {
        match *self {
            Group::Design {
                n_bellows,
                wall_thickness_mm,
            } => format!("N = {n_bellows}, T = {wall_thickness_mm} mm"),
            Group::N { n_bellows } => format!("N = {n_bellows}"),
            Group::T { wall_thickness_mm } => format!("T = {wall_thickness_mm} mm"),
            Group::P { pressure_bar } => format!("P = {pressure_bar} bar"),
            Group::Marker { marker } => format!("marker {marker}"),
        }
    }

    /// What varies inside the group (`across N and P`).
    pub fn across(&self) -> &'static str {
        match self {
            Group::Design { .. } => "across P",
            Group::N { .. } => "across T and P",
            Group::T { .. } => "across N and P",
            Group::P { .. } => "across the designs",
            Group::Marker { .. } => "across the configurations",
        }
    }
}

/// One recorded number at the calibrated set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// The output.
    pub output: Output,
    /// Its family.
    pub family: Family,
    /// Marker number (marker outputs only).
    pub marker: Option<u8>,
    /// Recorded value.
    pub recorded: f64,
    /// Predicted at the calibrated set.
    pub predicted: f64,
    /// `σ` (measurement and surrogate, in quadrature).
    pub sigma: f64,
    /// `z = (predicted − recorded) / σ`.
    pub standardised: f64,
    /// `z² / χ²` over every cell of the table.
    pub chi2_share: f64,
    /// Whether the output took part in the calibration.
    pub fitted: bool,
    /// Share of the calibration's (weighted) `χ²`, for fitted cells.
    pub fit_chi2_share: Option<f64>,
}

/// The cells as calibration observations (recorded value and σ; each its own weight 1), in
/// their order: what the surrogate evaluates for the later stages.
pub(crate) fn observations(cells: &[Cell]) -> crate::calibrate::objective::ObservationSet {
    use crate::calibrate::objective::{Config, Observation, ObservationSet};
    ObservationSet::from_observations(
        cells
            .iter()
            .map(|c| Observation {
                config: Config::of(c.n_bellows as usize, c.wall_thickness_mm, c.pressure_bar),
                output: c.output,
                value: c.recorded,
                sigma_meas: c.sigma,
                sigma_model: 0.0,
                weight: 1.0,
                source: String::new(),
            })
            .collect(),
    )
}

/// The table and the rows it could not use.
#[derive(Clone, Debug)]
pub struct Table {
    /// Cells, ordered by design, pressure and output.
    pub cells: Vec<Cell>,
    /// `Σ z²`.
    pub chi2: f64,
    /// Recorded rows outside the surrogate's domain (not used), in words.
    pub outside_domain: Vec<String>,
}

/// The residual table of `cal` (see the [module docs](super)).
///
/// # Errors
/// A calibration without residuals or with an objective that does not parse, or a surrogate
/// query that fails.
pub fn residual_table(
    cal: &Calibration,
    model: &Surrogate,
    rec: &Recordings,
) -> Result<Table, DiagnoseError> {
    if cal.residuals.is_empty() {
        return Err(DiagnoseError::input(
            "calibration residuals",
            "none",
            "a calibration with at least one residual",
        ));
    }
    let mut cells = fitted(cal);
    let (inside, outside_domain) = in_domain(model, cal, rec);
    cells.extend(unfitted(cal, model, &inside)?);
    for c in &cells {
        if !(c.standardised.is_finite() && c.sigma > 0.0) {
            return Err(DiagnoseError::input(
                &format!(
                    "residual of {} at N={} T={} P={}",
                    c.output.name(),
                    c.n_bellows,
                    c.wall_thickness_mm,
                    c.pressure_bar
                ),
                c.standardised,
                "a finite standardised residual with σ > 0",
            ));
        }
    }
    let chi2: f64 = cells.iter().map(|c| c.standardised.powi(2)).sum();
    for c in &mut cells {
        c.chi2_share = c.standardised.powi(2) / chi2.max(1e-300);
    }
    cells.sort_by(|a, b| {
        (a.n_bellows, a.wall_thickness_mm, a.pressure_bar)
            .partial_cmp(&(b.n_bellows, b.wall_thickness_mm, b.pressure_bar))
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.output.cmp(&b.output))
    });
    Ok(Table {
        cells,
        chi2,
        outside_domain,
    })
}

/// The cells of the outputs the calibration fitted, from its residuals.
fn fitted(cal: &Calibration) -> Vec<Cell> {
    cal.residuals
        .iter()
        .map(|r| Cell {
            n_bellows: r.config.n_bellows,
            wall_thickness_mm: r.config.wall_thickness_mm,
            pressure_bar: r.config.pressure_bar,
            output: r.output,
            family: Family::of(r.output),
            marker: marker_of(r.output),
            recorded: r.recorded,
            predicted: r.predicted,
            sigma: r.sigma,
            standardised: r.standardised,
            chi2_share: 0.0,
            fitted: true,
            fit_chi2_share: Some(r.chi2_share),
        })
        .collect()
}

fn marker_of(o: Output) -> Option<u8> {
    match o {
        Output::MarkerUz(k) | Output::MarkerUy(k) => Some(k),
        _ => None,
    }
}

/// The recordings inside the surrogate's domain, and the rows left out (in words).
fn in_domain(model: &Surrogate, cal: &Calibration, rec: &Recordings) -> (Recordings, Vec<String>) {
    let m = cal.best;
    let inside = |n: usize, t: f64, p: f64| {
        model.n_allowed.contains(&(n as u32))
            && model.check_query(&Query::new(n as u32, t, p, m)).is_ok()
    };
    let mut out = Vec::new();
    let mut keep = rec.clone();
    let mut note = |kind: &str, source: &str, i: usize, n: usize, t: f64, p: f64| {
        out.push(format!(
            "{kind} N={n} T={t} P={p} ({source}, line {}): outside the surrogate's domain",
            i + 2
        ))
    };
    for (i, r) in rec.bending.iter().enumerate() {
        if !inside(r.n_bellows, r.wall_thickness_mm, r.pressure_bar) {
            note(
                "bending",
                &rec.bending_source,
                i,
                r.n_bellows,
                r.wall_thickness_mm,
                r.pressure_bar,
            );
        }
    }
    for (i, r) in rec.force.iter().enumerate() {
        if !inside(r.n_bellows, r.wall_thickness_mm, r.pressure_bar) {
            note(
                "force",
                &rec.force_source,
                i,
                r.n_bellows,
                r.wall_thickness_mm,
                r.pressure_bar,
            );
        }
    }
    keep.bending
        .retain(|r| inside(r.n_bellows, r.wall_thickness_mm, r.pressure_bar));
    keep.force
        .retain(|r| inside(r.n_bellows, r.wall_thickness_mm, r.pressure_bar));
    let before = keep.markers.len();
    keep.markers
        .retain(|r| inside(r.n_bellows, r.wall_thickness_mm, r.pressure_bar));
    if keep.markers.len() < before {
        out.push(format!(
            "{} marker rows of {}: outside the surrogate's domain",
            before - keep.markers.len(),
            rec.markers_source
        ));
    }
    (keep, out)
}

/// Cells of the outputs the calibration's objective left out, at its optimum.
fn unfitted(
    cal: &Calibration,
    model: &Surrogate,
    rec: &Recordings,
) -> Result<Vec<Cell>, DiagnoseError> {
    let fitted = Weights::parse(&cal.objective)?;
    let w = Weights {
        tip: f64::from(u8::from(fitted.tip == 0.0 && !rec.bending.is_empty())),
        angle: f64::from(u8::from(fitted.angle == 0.0 && !rec.bending.is_empty())),
        force: f64::from(u8::from(fitted.force == 0.0 && !rec.force.is_empty())),
        markers: f64::from(u8::from(fitted.markers == 0.0 && !rec.markers.is_empty())),
    };
    if w.tip + w.angle + w.force + w.markers == 0.0 {
        return Ok(Vec::new());
    }
    let all = ObservationSet::build(model, rec, &w, &Selection::default())?;
    let excluded = |e: &Exclusion, o: &crate::calibrate::objective::Observation| {
        let r = match o.output {
            Output::Force => Recording::Force,
            _ => Recording::Bending,
        };
        e.config.same(&o.config) && (e.recording == Recording::Both || e.recording == r)
    };
    let kept: Vec<_> = all
        .obs
        .into_iter()
        .filter(|o| !cal.excluded.iter().any(|e| excluded(e, o)))
        .collect();
    if kept.is_empty() {
        return Ok(Vec::new());
    }
    let set = ObservationSet::from_observations(kept);
    let mut ev = Evaluator::new(model, &set, cal.domain.clone());
    let pred = ev.predictions(&cal.domain.unit(&cal.best))?;
    Ok(set
        .obs
        .iter()
        .zip(pred)
        .map(|(o, p)| Cell {
            n_bellows: o.config.n_bellows,
            wall_thickness_mm: o.config.wall_thickness_mm,
            pressure_bar: o.config.pressure_bar,
            output: o.output,
            family: Family::of(o.output),
            marker: marker_of(o.output),
            recorded: o.value,
            predicted: p,
            sigma: o.sigma(),
            standardised: (p - o.value) / o.sigma(),
            chi2_share: 0.0,
            fitted: false,
            fit_chi2_share: None,
        })
        .collect())
}
