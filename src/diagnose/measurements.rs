//! What could be measured next: every output the FE sensitivity sweep evaluates that the
//! recordings lack, with the σ it would be recorded with. The design of
//! [`super::measure_design`] chooses among them.
//!
//! A sweep holds, per design, rig (bending, blocked force) and pressure level, the derivative
//! of every output (tip, markers 1..8, angle, force) by every parameter. The measurements it
//! can evaluate, by kind ([`MeasurementKind`]):
//!
//! - a **marker** (Uz or Uy of markers 1..8; marker 9 is the tip) at a recorded design and
//!   pressure;
//! - an **output at another pressure**: a level of the sweep the design was not recorded at
//!   (0 bar, the self-weight alone, or an intermediate level);
//! - an **output at another design**: a design of the sweep without any recording;
//! - a **blocked force** at a recorded design and pressure without one, or a scalar bending
//!   output (tip, angle) missing there;
//! - a **blocked force at another plate height**, where a force is recorded and the sweep
//!   differentiates by `plate_offset`: the plate moved by a known offset. The sweep holds the
//!   first derivatives at the recorded plate height only (no mixed derivative by the offset
//!   and an effect), so to first order the reading carries the signatures of the recorded
//!   force: it counts as a second, independent force reading.
//!
//! **Noise.** Each measurement gets the σ of the same output in the recordings, at the nearest
//! recorded configuration (distance `|ΔN|/2 + |ΔT|/0.4 mm + |ΔP|/1 bar`, one step of the
//! shipped plan in each). Where the recordings hold none of that output:
//!
//! - a marker `k` or the tip: the noise model of the calibrator and the twins
//!   ([`crate::calibrate::objective`]), the angle's scatter `σ_α` (the nearest recorded angle's
//!   σ, in radians) moved across the chord from the support, `σ = σ_α √((z_k − Uz_k)² + Uy_k²)`,
//!   `z_k = k L_f / 9`, with `Uz_k`, `Uy_k` the sweep's values there;
//! - a blocked force: [`DEFAULT_FORCE_SIGMA_N`].

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::cells::Cell;
use super::discrimination::{Discrimination, ItemRow};
use super::signature::derivative_of;
use crate::calibrate::baseline::SweepSensitivities;
use crate::calibrate::objective::{Output, FREE_LENGTH_MM};
use crate::fe::effects::Effect;
use crate::fe::sensitivity::{OgdenParameter, Outputs, Parameter};
use crate::fe::simulate::Mode;

/// σ of a blocked force where the recordings hold none (N): about the median `force_std_n`
/// of the shipped experiments (0.038 N over 27 configurations).
pub const DEFAULT_FORCE_SIGMA_N: f64 = 0.04;

/// What kind of measurement it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MeasurementKind {
    /// A marker at a recorded design and pressure.
    Marker,
    /// An output at a pressure the design was not recorded at.
    Pressure,
    /// An output at a design without recordings.
    Design,
    /// A blocked force at a recorded configuration without one.
    Force,
    /// A blocked force at another plate height (to first order a second force reading).
    PlateHeight,
    /// A tip or angle output missing at a recorded configuration.
    Output,
}

impl MeasurementKind {
    /// The kind in words.
    pub fn label(self) -> &'static str {
        match self {
            MeasurementKind::Marker => "a marker at a recorded configuration",
            MeasurementKind::Pressure => "another pressure",
            MeasurementKind::Design => "a design not recorded",
            MeasurementKind::Force => "a blocked force where none is recorded",
            MeasurementKind::PlateHeight => "a blocked force at another plate height",
            MeasurementKind::Output => "an output not recorded at a recorded configuration",
        }
    }
}

/// A measurement that could be added.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Measurement {
    /// Its kind.
    pub kind: MeasurementKind,
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// The output.
    pub output: Output,
    /// The σ it would be recorded with (unit of the output).
    pub sigma: f64,
    /// Where the σ comes from, in words.
    pub sigma_from: String,
}

impl Measurement {
    /// The measurement in words: `marker4_uy_mm at N = 11, T = 2 mm, 2 bar (bending)`.
    pub fn text(&self) -> String {
        let rig = match self.output {
            Output::Force => "blocked force",
            _ => "bending",
        };
        let plate = if self.kind == MeasurementKind::PlateHeight {
            ", plate moved"
        } else {
            ""
        };
        format!(
            "{} at N = {}, T = {} mm, {} bar ({rig}{plate})",
            self.output.name(),
            self.n_bellows,
            self.wall_thickness_mm,
            self.pressure_bar
        )
    }
}

/// Every measurement `sens` can evaluate that `cells` lack (module docs), each with its row:
/// the derivative of its output by every parameter of `params` (the sweep's order), over its σ.
/// Parameters a ramp lacks get 0.
pub(crate) fn candidates(
    cells: &[Cell],
    sens: &SweepSensitivities,
    params: &[Parameter],
) -> Vec<(Measurement, Vec<f64>)> {
    let mut out = Vec::new();
    let plate = params.contains(&Parameter::Effect(Effect::PlateOffset));
    for d in &sens.designs {
        let s = &d.sensitivities;
        let at: Vec<Option<usize>> = params
            .iter()
            .map(|p| s.parameters.iter().position(|i| i.parameter == *p))
            .collect();
        let (n, t) = (d.n_bellows as u32, d.wall_thickness_mm);
        for st in &s.steps {
            let p = st.pressure_bar;
            for output in outputs_of(d.mode) {
                let Some(kind) = kind_of(cells, n, t, p, output) else {
                    continue;
                };
                let Some((sigma, from)) = sigma_for(cells, (n, t, p), output, &st.values) else {
                    continue;
                };
                let Some(row) = at
                    .iter()
                    .map(|j| match j {
                        Some(j) => derivative_of(&st.derivatives[*j], output).map(|v| v / sigma),
                        None => Some(0.0),
                    })
                    .collect::<Option<Vec<f64>>>()
                else {
                    continue;
                };
                let m = Measurement {
                    kind,
                    n_bellows: n,
                    wall_thickness_mm: t,
                    pressure_bar: p,
                    output,
                    sigma,
                    sigma_from: from,
                };
                out.push((m, row));
            }
            if plate && d.mode == Mode::Force {
                out.extend(plate_heights(cells, (n, t, p), &at, st));
            }
        }
    }
    out
}

/// The force reading at another plate height at `(n, t, p)`, where a force is recorded.
fn plate_heights(
    cells: &[Cell],
    (n, t, p): (u32, f64, f64),
    at: &[Option<usize>],
    st: &crate::fe::sensitivity::StepSensitivities,
) -> Option<(Measurement, Vec<f64>)> {
    cells
        .iter()
        .find(|c| same(c, n, t, p) && c.output == Output::Force)?;
    let (sigma, from) = sigma_for(cells, (n, t, p), Output::Force, &st.values)?;
    let row = at
        .iter()
        .map(|j| match j {
            Some(j) => st.derivatives[*j].force_n.map(|v| v / sigma),
            None => Some(0.0),
        })
        .collect::<Option<Vec<f64>>>()?;
    Some((
        Measurement {
            kind: MeasurementKind::PlateHeight,
            n_bellows: n,
            wall_thickness_mm: t,
            pressure_bar: p,
            output: Output::Force,
            sigma,
            sigma_from: from,
        },
        row,
    ))
}

/// The outputs a ramp of `mode` measures (marker 9 is the tip).
fn outputs_of(mode: Mode) -> Vec<Output> {
    match mode {
        Mode::Force => vec![Output::Force],
        Mode::Bending => [Output::TipUz, Output::TipUy, Output::Angle]
            .into_iter()
            .chain((1..=8).flat_map(|k| [Output::MarkerUz(k), Output::MarkerUy(k)]))
            .collect(),
    }
}

fn same(c: &Cell, n: u32, t: f64, p: f64) -> bool {
    c.n_bellows == n && (c.wall_thickness_mm - t).abs() < 1e-9 && (c.pressure_bar - p).abs() < 1e-9
}

/// The kind of measuring `output` at `(n, t, p)`, none when it is recorded.
fn kind_of(cells: &[Cell], n: u32, t: f64, p: f64, output: Output) -> Option<MeasurementKind> {
    if cells.iter().any(|c| same(c, n, t, p) && c.output == output) {
        return None;
    }
    let design = cells
        .iter()
        .any(|c| c.n_bellows == n && (c.wall_thickness_mm - t).abs() < 1e-9);
    let config = cells.iter().any(|c| same(c, n, t, p));
    Some(match (design, config, output) {
        (false, _, _) => MeasurementKind::Design,
        (true, false, _) => MeasurementKind::Pressure,
        (true, true, Output::MarkerUz(_) | Output::MarkerUy(_)) => MeasurementKind::Marker,
        (true, true, Output::Force) => MeasurementKind::Force,
        (true, true, _) => MeasurementKind::Output,
    })
}

/// The recorded cell nearest `(n, t, p)` among those `keep` accepts.
fn nearest(
    cells: &[Cell],
    (n, t, p): (u32, f64, f64),
    keep: impl Fn(&Cell) -> bool,
) -> Option<&Cell> {
    let dist = |c: &Cell| {
        (f64::from(c.n_bellows) - f64::from(n)).abs() / 2.0
            + (c.wall_thickness_mm - t).abs() / 0.4
            + (c.pressure_bar - p).abs()
    };
    cells
        .iter()
        .filter(|c| keep(c))
        .min_by(|a, b| dist(a).total_cmp(&dist(b)))
}

/// The σ of measuring `output` at `at` (module docs), and where it comes from; none for an
/// angle without any recorded angle.
pub(crate) fn sigma_for(
    cells: &[Cell],
    at: (u32, f64, f64),
    output: Output,
    values: &Outputs,
) -> Option<(f64, String)> {
    if let Some(c) = nearest(cells, at, |c| c.output == output) {
        return Some((
            c.sigma,
            format!(
                "the recorded σ of {} at N = {}, T = {} mm, {} bar",
                output.name(),
                c.n_bellows,
                c.wall_thickness_mm,
                c.pressure_bar
            ),
        ));
    }
    let k = match output {
        Output::Force => {
            return Some((
                DEFAULT_FORCE_SIGMA_N,
                "no force recorded: the default blocked-force σ".into(),
            ))
        }
        Output::Angle => return None,
        Output::TipUz | Output::TipUy => 9,
        Output::MarkerUz(k) | Output::MarkerUy(k) => k,
    };
    let angle = nearest(cells, at, |c| c.output == Output::Angle)?;
    let (uz, uy) = match k {
        9 => (values.tip_uz_mm, values.tip_uy_mm),
        k => {
            let m = values.markers.get(usize::from(k) - 1)?;
            (m[0], m[1])
        }
    };
    let chord = (FREE_LENGTH_MM * f64::from(k) / 9.0 - uz).hypot(uy);
    Some((
        chord * angle.sigma.to_radians(),
        format!(
            "the recorded angle σ at N = {}, T = {} mm, {} bar across a chord of {chord:.1} mm",
            angle.n_bellows, angle.wall_thickness_mm, angle.pressure_bar
        ),
    ))
}

/// The [`Discrimination`] of the candidates `effects` on the recorded cells, the material as
/// nuisance: `z` the (whitened) residual, `column(p)` the (whitened, σ-scaled) column of
/// parameter `p` over the recorded cells, `items` the measurements of [`candidates`] with
/// their rows in the order of `params`. None when the sweep lacks the material's four
/// parameters or one of `effects`.
pub(crate) fn discrimination(
    z: &DVector<f64>,
    column: impl Fn(Parameter) -> Option<DVector<f64>>,
    params: &[Parameter],
    effects: &[Parameter],
    items: &[(Measurement, Vec<f64>)],
) -> Option<Discrimination> {
    let material: Vec<Parameter> = OgdenParameter::ALL.map(Parameter::Material).to_vec();
    let at = |p: &Parameter| params.iter().position(|q| q == p);
    let m_idx = material.iter().map(at).collect::<Option<Vec<usize>>>()?;
    let e_idx = effects.iter().map(at).collect::<Option<Vec<usize>>>()?;
    let nuisance = DMatrix::from_columns(
        &material
            .iter()
            .map(|p| column(*p))
            .collect::<Option<Vec<_>>>()?,
    );
    let signatures = effects
        .iter()
        .map(|p| column(*p))
        .collect::<Option<Vec<_>>>()?;
    let rows = items
        .iter()
        .map(|(_, r)| ItemRow {
            nuisance: m_idx.iter().map(|&j| r[j]).collect(),
            candidates: e_idx.iter().map(|&j| r[j]).collect(),
        })
        .collect();
    Discrimination::new(z, nuisance, signatures, rows).ok()
}
