//! Model and show: the material refitted together with the chosen effect(s), the effect's
//! size with its confidence interval, the fit before and after, and the gain on designs the
//! fit did not see.
//!
//! Every cell of the residual table that the FE sweep has sensitivities for takes part, each
//! with weight 1 and its own `σ` (the Name stage's cells: the outputs the calibration's
//! objective left out count here, or a force-rig effect could not be estimated). The
//! prediction of cell `i` with the material at unit-box point `u` and effect sizes `θ` (from
//! their neutral values) is
//!
//! ```text
//!   ŷᵢ(u, θ) = surrogateᵢ(u) + Σₖ θₖ ∂yᵢ/∂θₖ + cᵢ
//! ```
//!
//! the effect linearised with the FE sensitivities of the sweep (at about the calibrated
//! material), `cᵢ` a correction that the FE confirmation sets (zero before it: see
//! [`confirm_with_fe`]). Both fits are bounded Levenberg–Marquardt on the surrogate's
//! analytic Jacobian: the material inside the surrogate's training box, each effect inside
//! its library range; a bound that stops a fit is reported.
//!
//! - **Before**: the material alone on every used cell (4 parameters); **after**: material and
//!   effect(s) (4 + k). The nested F test `F = (Δχ²/k) / (χ²₁/(n − 4 − k))`.
//! - **Size**: `θ̂` with standard error from `ŝ² (JᵀJ)⁻¹` at the optimum, `ŝ² = max(1,
//!   χ²₁/(n − 4 − k))` (the recordings' `σ` is the floor; a model that misses by more widens
//!   the interval), and a Student-t interval at the chosen level.
//! - **Held out**: each design `(N, T)` in turn is left out, both fits are redone on the rest
//!   (from the full fits' optima), and the left-out design is predicted: its tip bending
//!   error `BE = |(ΔUz, ΔUy)|` per pressure, its force error and its `χ²`. The noise level a
//!   perfect model would show is `E|(εz, εy)| = σ_tip √(π/2)` per configuration.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, FisherSnedecor, StudentsT};

use super::cells::Cell;
use super::signature::{derivative_of, sensitivity_step, LocalMaterial};
use super::DiagnoseError;
use crate::calibrate::baseline::{
    run_ramps, RampSource, SweepDesign, SweepRamp, SweepSensitivities, SweepSettings,
};
use crate::calibrate::objective::{Evaluator, ObservationSet, Output};
use crate::calibrate::{OgdenSet, ParamSpace};
use crate::fe::effects::{Effect, Effects};
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::sensitivity::Parameter;
use crate::fe::simulate::Mode;
use crate::rom::Surrogate;

/// Settings of [`refit`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefitSettings {
    /// The effects to add to the material (one or more).
    pub effects: Vec<Effect>,
    /// Level of the confidence intervals (0.95).
    pub confidence: f64,
    /// Whether to leave each design out in turn.
    pub held_out: bool,
}

impl RefitSettings {
    /// Refit with `effects`, 95 % intervals, designs held out.
    pub fn new(effects: Vec<Effect>) -> Self {
        Self {
            effects,
            confidence: 0.95,
            held_out: true,
        }
    }

    fn validate(&self) -> Result<(), DiagnoseError> {
        if self.effects.is_empty() {
            return Err(DiagnoseError::input(
                "refit effects",
                "none",
                "at least one effect of the library",
            ));
        }
        for (i, e) in self.effects.iter().enumerate() {
            if self.effects[..i].contains(e) {
                return Err(DiagnoseError::input(
                    "refit effects",
                    e.name(),
                    "each effect at most once",
                ));
            }
        }
        if !(self.confidence > 0.5 && self.confidence < 1.0) {
            return Err(DiagnoseError::input(
                "confidence",
                self.confidence,
                "a level in (0.5, 1)",
            ));
        }
        Ok(())
    }
}

/// One effect's refitted size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EffectSize {
    /// The effect.
    pub effect: String,
    /// Its unit.
    pub unit: String,
    /// Its value (neutral + estimate), what `--effect NAME=VALUE` takes.
    pub value: f64,
    /// Its estimate from the neutral value.
    pub estimate: f64,
    /// Standard error.
    pub std_error: f64,
    /// Confidence interval of the value `[lo, hi]`.
    pub interval: (f64, f64),
    /// A library bound that stopped the fit, in words.
    pub at_bound: Option<String>,
}

/// How well a set of predictions meets the recordings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quality {
    /// Cells.
    pub n_cells: usize,
    /// `Σ z²`.
    pub chi2: f64,
    /// Mean tip bending error over the configurations with tip Uz and Uy (mm; none without).
    pub mean_be_mm: Option<f64>,
    /// Mean force error, predicted − recorded (N; none without force cells).
    pub mean_force_error_n: Option<f64>,
    /// Mean absolute force error (N).
    pub mean_abs_force_error_n: Option<f64>,
    /// Root mean square `z` per output family (`tip Uz`, …).
    pub rms_z: Vec<(String, f64)>,
}

/// One fit of the material (and effects).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FitSummary {
    /// The material.
    pub material: OgdenSet,
    /// Effect values (neutral + estimate), in the order of the settings (empty: material only).
    pub effects: Vec<f64>,
    /// Quality on the cells fitted.
    pub quality: Quality,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// How the fit stopped.
    pub stop: String,
    /// Bounds active at the optimum, in words.
    pub active_bounds: Vec<String>,
}

/// A design left out of both fits, and how each predicts it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeldOutDesign {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// The material-only fit on the rest, on this design.
    pub before: Quality,
    /// The material + effect fit on the rest, on this design.
    pub after: Quality,
    /// The effects' values fitted without this design.
    pub effects: Vec<f64>,
}

/// The held-out comparison, every design in turn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeldOut {
    /// Each design.
    pub designs: Vec<HeldOutDesign>,
    /// Mean tip BE over every held-out configuration, material only (mm).
    pub mean_be_before_mm: Option<f64>,
    /// The same with the effect(s).
    pub mean_be_after_mm: Option<f64>,
    /// Mean absolute force error over every held-out configuration, material only (N).
    pub mean_abs_force_error_before_n: Option<f64>,
    /// The same with the effect(s).
    pub mean_abs_force_error_after_n: Option<f64>,
    /// `Σ z²` over every held-out cell, material only.
    pub chi2_before: f64,
    /// The same with the effect(s).
    pub chi2_after: f64,
}

/// What the Model-and-show stage found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Refit {
    /// Cells used (those with sensitivities).
    pub n_cells: usize,
    /// Where the linearisation comes from (material and mesh of the sweep).
    pub linearised_at: String,
    /// The effects' sizes.
    pub effects: Vec<EffectSize>,
    /// Material alone, every used cell.
    pub before: FitSummary,
    /// Material and effect(s).
    pub after: FitSummary,
    /// The nested F statistic of adding the effect(s).
    pub f: f64,
    /// Its p-value.
    pub p_value: f64,
    /// The mean tip BE a perfect model would show under the recordings' noise (mm).
    pub noise_be_mm: Option<f64>,
    /// Every design left out in turn (none if not asked for).
    pub held_out: Option<HeldOut>,
    /// The FE model with the effect(s) on at the refitted values, if run.
    pub fe: Vec<FeRound>,
    /// The stage in words.
    pub verdict: String,
}

/// One round of the FE confirmation ([`confirm_with_fe`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeRound {
    /// Material the FE ran with.
    pub material: OgdenSet,
    /// Effect values the FE ran with.
    pub effects: Vec<f64>,
    /// The FE predictions against the recordings.
    pub quality: Quality,
    /// Root mean square of (FE − linearised prediction)/σ over the used cells.
    pub rms_fe_minus_linear: f64,
    /// Largest |FE − linearised|/σ, and where.
    pub worst: (f64, String),
    /// FE ramps run (the others came from the cache).
    pub ramps_run: usize,
    /// Ramps that stopped early, in words.
    pub failed: Vec<String>,
}

/// The used cells and their linearised effect columns.
#[derive(Clone, Debug)]
pub(crate) struct Rows {
    pub(crate) cells: Vec<Cell>,
    /// `∂yᵢ/∂θₖ` (unit of the output per unit of the effect), `[i][k]`.
    pub(crate) d: Vec<Vec<f64>>,
    /// FE correction `cᵢ` (unit of the output).
    pub(crate) offset: Vec<f64>,
}

impl Rows {
    /// The cells of `cells` that `sens` covers, with their effect columns.
    pub(crate) fn of(
        cells: &[Cell],
        sens: &SweepSensitivities,
        effects: &[Effect],
    ) -> Result<Self, DiagnoseError> {
        let mut out = Rows {
            cells: Vec::new(),
            d: Vec::new(),
            offset: Vec::new(),
        };
        for c in cells {
            let Some((s, step)) = sensitivity_step(sens, c) else {
                continue;
            };
            let mut row = Vec::with_capacity(effects.len());
            for e in effects {
                let Some(j) = s
                    .parameters
                    .iter()
                    .position(|p| p.parameter == Parameter::Effect(*e))
                else {
                    return Err(DiagnoseError::input(
                        "sensitivities",
                        format!("without {}", e.name()),
                        "a sweep with the sensitivities of every refitted effect",
                    ));
                };
                match derivative_of(&s.steps[step].derivatives[j], c.output) {
                    Some(v) => row.push(v),
                    None => break,
                }
            }
            if row.len() == effects.len() {
                out.cells.push(c.clone());
                out.d.push(row);
                out.offset.push(0.0);
            }
        }
        Ok(out)
    }

    fn subset(&self, keep: impl Fn(&Cell) -> bool) -> Rows {
        let idx: Vec<usize> = (0..self.cells.len())
            .filter(|&i| keep(&self.cells[i]))
            .collect();
        Rows {
            cells: idx.iter().map(|&i| self.cells[i].clone()).collect(),
            d: idx.iter().map(|&i| self.d[i].clone()).collect(),
            offset: idx.iter().map(|&i| self.offset[i]).collect(),
        }
    }

    fn observations(&self) -> ObservationSet {
        super::cells::observations(&self.cells)
    }
}

/// A bounded fit's end point.
#[derive(Clone, Debug)]
struct Fitted {
    /// `[u (4), θ (k)]`.
    x: Vec<f64>,
    chi2: f64,
    iterations: usize,
    stop: &'static str,
    /// `JᵀJ` at the end point.
    jtj: DMatrix<f64>,
    /// Parameters at a bound that pushes outwards.
    active: Vec<bool>,
}

/// The residual problem of a set of rows: material through the surrogate, `k` linear effects.
struct Problem<'a> {
    rows: &'a Rows,
    set: ObservationSet,
    model: &'a Surrogate,
    space: ParamSpace,
    k: usize,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl<'a> Problem<'a> {
    fn new(
        rows: &'a Rows,
        model: &'a Surrogate,
        space: ParamSpace,
        effects: &[Effect],
        k: usize,
    ) -> Self {
        let mut lo = vec![0.0; 4];
        let mut hi = vec![1.0; 4];
        for e in &effects[..k] {
            let i = e.info();
            lo.push(i.range.0 - i.neutral);
            hi.push(i.range.1 - i.neutral);
        }
        Problem {
            rows,
            set: rows.observations(),
            model,
            space,
            k,
            lo,
            hi,
        }
    }

    /// Residuals `z` (and the Jacobian) at `x`.
    fn eval(
        &self,
        ev: &mut Evaluator<'_>,
        x: &[f64],
        r: &mut [f64],
        jac: Option<&mut DMatrix<f64>>,
    ) -> Result<(), DiagnoseError> {
        let u = [x[0], x[1], x[2], x[3]];
        let n = r.len();
        let mut jm = vec![[0.0; 4]; n];
        ev.residuals(&u, r, jac.is_some().then_some(jm.as_mut_slice()))?;
        for (i, ri) in r.iter_mut().enumerate() {
            let sigma = self.rows.cells[i].sigma;
            let mut lin = self.rows.offset[i];
            for k in 0..self.k {
                lin += x[4 + k] * self.rows.d[i][k];
            }
            *ri += lin / sigma;
        }
        if let Some(j) = jac {
            for i in 0..n {
                for a in 0..4 {
                    j[(i, a)] = jm[i][a];
                }
                for k in 0..self.k {
                    j[(i, 4 + k)] = self.rows.d[i][k] / self.rows.cells[i].sigma;
                }
            }
        }
        Ok(())
    }

    /// Predictions (unit of each output) at `x`.
    fn predictions(&self, x: &[f64]) -> Result<Vec<f64>, DiagnoseError> {
        let mut ev = Evaluator::new(self.model, &self.set, self.space.clone());
        let mut r = vec![0.0; self.rows.cells.len()];
        self.eval(&mut ev, x, &mut r, None)?;
        Ok(r.iter()
            .zip(&self.rows.cells)
            .map(|(z, c)| c.recorded + z * c.sigma)
            .collect())
    }

    /// Bounded Levenberg–Marquardt from `start`.
    fn fit(&self, start: &[f64]) -> Result<Fitted, DiagnoseError> {
        let p = 4 + self.k;
        let n = self.rows.cells.len();
        let mut ev = Evaluator::new(self.model, &self.set, self.space.clone());
        let mut x: Vec<f64> = (0..p)
            .map(|i| start[i].clamp(self.lo[i], self.hi[i]))
            .collect();
        let mut r = vec![0.0; n];
        let mut rt = vec![0.0; n];
        let mut j = DMatrix::zeros(n, p);
        self.eval(&mut ev, &x, &mut r, Some(&mut j))?;
        let mut cost: f64 = r.iter().map(|v| v * v).sum();
        let mut lambda = 1e-3;
        let mut stop = "iteration limit";
        let mut it = 0;
        let mut stalls = 0;
        let pushed = |x: &[f64], g: &DVector<f64>| -> Vec<bool> {
            (0..p)
                .map(|i| {
                    let span = self.hi[i] - self.lo[i];
                    (x[i] <= self.lo[i] + 1e-12 * span && g[i] > 0.0)
                        || (x[i] >= self.hi[i] - 1e-12 * span && g[i] < 0.0)
                })
                .collect()
        };
        while it < 300 {
            it += 1;
            let rv = DVector::from_column_slice(&r);
            let g = j.transpose() * &rv;
            let a = j.transpose() * &j;
            let fixed = pushed(&x, &g);
            let free: Vec<usize> = (0..p).filter(|&i| !fixed[i]).collect();
            let pg = free.iter().map(|&i| g[i].abs()).fold(0.0, f64::max);
            if pg < 1e-10 * (1.0 + cost) {
                stop = "gradient";
                break;
            }
            let mut accepted = false;
            let mut tiny = false;
            while lambda < 1e16 {
                let m = free.len();
                let mut af = DMatrix::zeros(m, m);
                let mut bf = DVector::zeros(m);
                for (a_, &ia) in free.iter().enumerate() {
                    bf[a_] = -g[ia];
                    for (b_, &ib) in free.iter().enumerate() {
                        af[(a_, b_)] = a[(ia, ib)];
                    }
                    af[(a_, a_)] += lambda * a[(ia, ia)].max(1e-12);
                }
                let Some(ch) = af.cholesky() else {
                    lambda *= 4.0;
                    continue;
                };
                let d = ch.solve(&bf);
                let mut trial = x.clone();
                for (a_, &ia) in free.iter().enumerate() {
                    trial[ia] = (x[ia] + d[a_]).clamp(self.lo[ia], self.hi[ia]);
                }
                let step = (0..p)
                    .map(|i| (trial[i] - x[i]).abs() / (self.hi[i] - self.lo[i]))
                    .fold(0.0, f64::max);
                if step < 1e-12 {
                    tiny = true;
                    break;
                }
                self.eval(&mut ev, &trial, &mut rt, None)?;
                let ct: f64 = rt.iter().map(|v| v * v).sum();
                if ct < cost {
                    let rel = (cost - ct) / cost.max(1e-300);
                    stalls = if rel < 1e-12 { stalls + 1 } else { 0 };
                    x = trial;
                    cost = ct;
                    lambda = (lambda / 3.0).max(1e-12);
                    accepted = true;
                    break;
                }
                lambda *= 4.0;
            }
            if tiny {
                stop = "step";
                break;
            }
            if !accepted {
                stop = "no descent";
                break;
            }
            self.eval(&mut ev, &x, &mut r, Some(&mut j))?;
            if stalls >= 2 {
                stop = "cost stalled";
                break;
            }
        }
        self.eval(&mut ev, &x, &mut r, Some(&mut j))?;
        let g = j.transpose() * DVector::from_column_slice(&r);
        Ok(Fitted {
            active: pushed(&x, &g),
            chi2: r.iter().map(|v| v * v).sum(),
            jtj: j.transpose() * &j,
            x,
            iterations: it,
            stop,
        })
    }
}

/// The quality of `pred` against the recordings of `cells`.
fn quality(cells: &[Cell], pred: &[f64]) -> Quality {
    let z: Vec<f64> = cells
        .iter()
        .zip(pred)
        .map(|(c, p)| (p - c.recorded) / c.sigma)
        .collect();
    let mut be = Vec::new();
    let mut force = Vec::new();
    for (i, c) in cells.iter().enumerate() {
        match c.output {
            Output::TipUz => {
                if let Some(k) = cells.iter().position(|o| {
                    o.output == Output::TipUy
                        && o.n_bellows == c.n_bellows
                        && o.wall_thickness_mm == c.wall_thickness_mm
                        && o.pressure_bar == c.pressure_bar
                }) {
                    be.push((pred[i] - c.recorded).hypot(pred[k] - cells[k].recorded));
                }
            }
            Output::Force => force.push(pred[i] - c.recorded),
            _ => {}
        }
    }
    let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    let mut rms_z: Vec<(String, f64)> = Vec::new();
    for f in super::cells::Family::ALL {
        let zs: Vec<f64> = cells
            .iter()
            .zip(&z)
            .filter(|(c, _)| c.family == f)
            .map(|(_, v)| v * v)
            .collect();
        if let Some(m) = mean(&zs) {
            rms_z.push((f.label().to_string(), m.sqrt()));
        }
    }
    Quality {
        n_cells: cells.len(),
        chi2: z.iter().map(|v| v * v).sum(),
        mean_be_mm: mean(&be),
        mean_force_error_n: mean(&force),
        mean_abs_force_error_n: mean(&force.iter().map(|v| v.abs()).collect::<Vec<_>>()),
        rms_z,
    }
}

/// The mean tip BE of pure noise: `σ_tip √(π/2)` averaged over the configurations with tip
/// Uz and Uy.
fn noise_be(cells: &[Cell]) -> Option<f64> {
    let v: Vec<f64> = cells
        .iter()
        .filter(|c| c.output == Output::TipUz)
        .map(|c| c.sigma * std::f64::consts::FRAC_PI_2.sqrt())
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

fn summary(pb: &Problem<'_>, f: &Fitted, effects: &[Effect]) -> Result<FitSummary, DiagnoseError> {
    let u = [f.x[0], f.x[1], f.x[2], f.x[3]];
    let names = pb.space.names();
    let mut active_bounds = Vec::new();
    for (i, &a) in f.active.iter().enumerate() {
        if !a {
            continue;
        }
        if i < 4 {
            let side = if f.x[i] <= 0.5 { "lower" } else { "upper" };
            active_bounds.push(format!(
                "{} at its {side} bound {}",
                names[i],
                pb.space.physical(i, f.x[i])
            ));
        } else {
            let e = effects[i - 4].info();
            active_bounds.push(format!(
                "{} at the end of its range ({})",
                e.name,
                e.neutral + f.x[i]
            ));
        }
    }
    Ok(FitSummary {
        material: pb.space.ogden(&u)?,
        effects: (0..pb.k)
            .map(|k| effects[k].info().neutral + f.x[4 + k])
            .collect(),
        quality: quality(&pb.rows.cells, &pb.predictions(&f.x)?),
        iterations: f.iterations,
        stop: f.stop.to_string(),
        active_bounds,
    })
}

/// The material alone refitted from `start` on the cells of `cells` that `sens` covers; per
/// cell of `cells`, its residual `z` there and its row of the material Jacobian (unit-box
/// coordinates, σ-scaled), and the material.
///
/// # Errors
/// Too few cells, a surrogate error.
pub(crate) fn material_refit(
    cells: &[Cell],
    sens: &SweepSensitivities,
    model: &Surrogate,
    start: &OgdenSet,
) -> Result<(LocalMaterial, OgdenSet), DiagnoseError> {
    let idx: Vec<usize> = (0..cells.len())
        .filter(|&i| sensitivity_step(sens, &cells[i]).is_some())
        .collect();
    let n = idx.len();
    if n < 6 {
        return Err(DiagnoseError::input(
            "cells with sensitivities",
            n,
            "at least 6 (the sweep must cover the recorded designs and pressures)",
        ));
    }
    let rows = Rows {
        cells: idx.iter().map(|&i| cells[i].clone()).collect(),
        d: vec![Vec::new(); n],
        offset: vec![0.0; n],
    };
    let space = ParamSpace::training_domain(model)?;
    let pb = Problem::new(&rows, model, space.clone(), &[], 0);
    let u0: Vec<f64> = space
        .unit(start)
        .iter()
        .map(|v| v.clamp(0.0, 1.0))
        .collect();
    let f = pb.fit(&u0)?;
    let mut ev = Evaluator::new(model, &pb.set, space.clone());
    let mut r = vec![0.0; n];
    let mut j = DMatrix::zeros(n, 4);
    pb.eval(&mut ev, &f.x, &mut r, Some(&mut j))?;
    let mut out = vec![None; cells.len()];
    for (k, &i) in idx.iter().enumerate() {
        out[i] = Some((r[k], [j[(k, 0)], j[(k, 1)], j[(k, 2)], j[(k, 3)]]));
    }
    Ok((out, space.ogden(&[f.x[0], f.x[1], f.x[2], f.x[3]])?))
}

/// Refits the material with `s.effects` on the cells of `cells` that `sens` covers, starting
/// from the calibrated set `start` (see the [module docs](self)).
///
/// # Errors
/// A bad setting, a sweep without the effects' sensitivities, too few cells, or a surrogate
/// error.
pub fn refit(
    cells: &[Cell],
    sens: &SweepSensitivities,
    model: &Surrogate,
    start: &OgdenSet,
    s: &RefitSettings,
) -> Result<Refit, DiagnoseError> {
    s.validate()?;
    let rows = Rows::of(cells, sens, &s.effects)?;
    let mut r = fit_rows(&rows, model, start, s)?;
    r.linearised_at = format!(
        "FE sensitivities of the sweep at {} on the {} mesh",
        sens.material
            .ogden_params()
            .map_or("a non-Ogden material".to_string(), |m| format!(
                "Ogden ({}, {}, {}, {})",
                m[0], m[1], m[2], m[3]
            )),
        sens.mesh.level.name()
    );
    Ok(r)
}

pub(crate) fn fit_rows(
    rows: &Rows,
    model: &Surrogate,
    start: &OgdenSet,
    s: &RefitSettings,
) -> Result<Refit, DiagnoseError> {
    let k = s.effects.len();
    let n = rows.cells.len();
    if n < 4 + k + 2 {
        return Err(DiagnoseError::input(
            "cells with sensitivities",
            n,
            &format!(
                "at least {} (the material, {k} effect(s) and a residual)",
                4 + k + 2
            ),
        ));
    }
    let space = ParamSpace::training_domain(model)?;
    let u0 = space.unit(start);
    let mut x0: Vec<f64> = u0.iter().map(|v| v.clamp(0.0, 1.0)).collect();
    let material_only = Problem::new(rows, model, space.clone(), &s.effects, 0);
    let f0 = material_only.fit(&x0)?;
    x0 = f0.x.clone();
    x0.extend(std::iter::repeat_n(0.0, k));
    let with = Problem::new(rows, model, space.clone(), &s.effects, k);
    let f1 = with.fit(&x0)?;
    let dof = (n - 4 - k) as f64;
    let scale = (f1.chi2 / dof).max(1.0);
    let cov = f1
        .jtj
        .clone()
        .try_inverse()
        .unwrap_or_else(|| DMatrix::from_element(4 + k, 4 + k, f64::NAN));
    let t = StudentsT::new(0.0, 1.0, dof)
        .map(|d| d.inverse_cdf(0.5 + s.confidence / 2.0))
        .unwrap_or(f64::NAN);
    let before = summary(&material_only, &f0, &s.effects)?;
    let after = summary(&with, &f1, &s.effects)?;
    let effects: Vec<EffectSize> = s
        .effects
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let info = e.info();
            let est = f1.x[4 + i];
            let se = (scale * cov[(4 + i, 4 + i)]).sqrt();
            EffectSize {
                effect: info.name.into(),
                unit: info.unit.into(),
                value: info.neutral + est,
                estimate: est,
                std_error: se,
                interval: (info.neutral + est - t * se, info.neutral + est + t * se),
                at_bound: f1.active[4 + i].then(|| {
                    format!(
                        "stopped at the end of its range [{}, {}]",
                        info.range.0, info.range.1
                    )
                }),
            }
        })
        .collect();
    let f_stat = ((f0.chi2 - f1.chi2).max(0.0) / k as f64) / (f1.chi2 / dof).max(1e-300);
    let p_value = FisherSnedecor::new(k as f64, dof)
        .map(|d| 1.0 - d.cdf(f_stat))
        .unwrap_or(f64::NAN);
    let held_out = if s.held_out {
        Some(held_out(rows, model, &space, &s.effects, &f0.x, &f1.x)?)
    } else {
        None
    };
    let mut out = Refit {
        n_cells: n,
        linearised_at: String::new(),
        effects,
        before,
        after,
        f: f_stat,
        p_value,
        noise_be_mm: noise_be(&rows.cells),
        held_out,
        fe: Vec::new(),
        verdict: String::new(),
    };
    out.verdict = verdict(&out, s.confidence);
    Ok(out)
}

/// Every design left out in turn, both fits redone on the rest from `x0` / `x1`.
fn held_out(
    rows: &Rows,
    model: &Surrogate,
    space: &ParamSpace,
    effects: &[Effect],
    x0: &[f64],
    x1: &[f64],
) -> Result<HeldOut, DiagnoseError> {
    let k = effects.len();
    let mut designs: Vec<(u32, f64)> = Vec::new();
    for c in &rows.cells {
        if !designs
            .iter()
            .any(|&(n, t)| n == c.n_bellows && t == c.wall_thickness_mm)
        {
            designs.push((c.n_bellows, c.wall_thickness_mm));
        }
    }
    let mut out = Vec::new();
    let (mut be0, mut be1, mut fo0, mut fo1) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut chi0, mut chi1) = (0.0, 0.0);
    for &(n, t) in &designs {
        let inside = |c: &Cell| c.n_bellows == n && c.wall_thickness_mm == t;
        let train = rows.subset(|c| !inside(c));
        let test = rows.subset(inside);
        if train.cells.len() < 4 + k + 2 {
            continue;
        }
        let p0 = Problem::new(&train, model, space.clone(), effects, 0);
        let p1 = Problem::new(&train, model, space.clone(), effects, k);
        let g0 = p0.fit(x0)?;
        let g1 = p1.fit(x1)?;
        let q0 = quality(
            &test.cells,
            &Problem::new(&test, model, space.clone(), effects, 0).predictions(&g0.x)?,
        );
        let q1 = quality(
            &test.cells,
            &Problem::new(&test, model, space.clone(), effects, k).predictions(&g1.x)?,
        );
        // per-configuration values, for means over every held-out configuration
        let per = |q: &Quality, be: &mut Vec<(f64, usize)>, fo: &mut Vec<(f64, usize)>| {
            let ncfg = test
                .cells
                .iter()
                .filter(|c| c.output == Output::TipUz)
                .count();
            let nforce = test
                .cells
                .iter()
                .filter(|c| c.output == Output::Force)
                .count();
            if let Some(v) = q.mean_be_mm {
                be.push((v, ncfg));
            }
            if let Some(v) = q.mean_abs_force_error_n {
                fo.push((v, nforce));
            }
        };
        per(&q0, &mut be0, &mut fo0);
        per(&q1, &mut be1, &mut fo1);
        chi0 += q0.chi2;
        chi1 += q1.chi2;
        out.push(HeldOutDesign {
            n_bellows: n,
            wall_thickness_mm: t,
            before: q0,
            after: q1,
            effects: (0..k)
                .map(|i| effects[i].info().neutral + g1.x[4 + i])
                .collect(),
        });
    }
    let wmean = |v: &[(f64, usize)]| {
        let w: usize = v.iter().map(|p| p.1).sum();
        (w > 0).then(|| v.iter().map(|p| p.0 * p.1 as f64).sum::<f64>() / w as f64)
    };
    Ok(HeldOut {
        designs: out,
        mean_be_before_mm: wmean(&be0),
        mean_be_after_mm: wmean(&be1),
        mean_abs_force_error_before_n: wmean(&fo0),
        mean_abs_force_error_after_n: wmean(&fo1),
        chi2_before: chi0,
        chi2_after: chi1,
    })
}

fn verdict(r: &Refit, level: f64) -> String {
    let sizes: Vec<String> = r
        .effects
        .iter()
        .map(|e| {
            format!(
                "{} = {:.4}{} ({:.0} % interval [{:.4}, {:.4}]{})",
                e.effect,
                e.value,
                super::wording::unit_suffix(&e.unit),
                100.0 * level,
                e.interval.0,
                e.interval.1,
                e.at_bound
                    .as_ref()
                    .map_or(String::new(), |b| format!("; {b}"))
            )
        })
        .collect();
    let mut s = format!(
        "Refitted with {}: χ² {:.1} → {:.1} on {} cells (F = {:.1}, p = {:.2e})",
        sizes.join(", "),
        r.before.quality.chi2,
        r.after.quality.chi2,
        r.n_cells,
        r.f,
        r.p_value
    );
    if let (Some(b0), Some(b1)) = (r.before.quality.mean_be_mm, r.after.quality.mean_be_mm) {
        s.push_str(&format!("; mean tip BE {b0:.2} → {b1:.2} mm"));
    }
    if let Some(h) = &r.held_out {
        if let (Some(b0), Some(b1)) = (h.mean_be_before_mm, h.mean_be_after_mm) {
            s.push_str(&format!(
                "; on designs left out one at a time {b0:.2} → {b1:.2} mm"
            ));
        }
        if let (Some(f0), Some(f1)) = (
            h.mean_abs_force_error_before_n,
            h.mean_abs_force_error_after_n,
        ) {
            s.push_str(&format!(", force |error| {f0:.3} → {f1:.3} N"));
        }
        s.push_str(&format!(
            ", held-out χ² {:.1} → {:.1}",
            h.chi2_before, h.chi2_after
        ));
    }
    if let Some(nb) = r.noise_be_mm {
        s.push_str(&format!(" (noise alone: {nb:.2} mm)"));
    }
    s.push('.');
    s
}

/// Settings of [`confirm_with_fe`].
#[derive(Clone, Debug)]
pub struct FeConfirmSettings {
    /// The sweep's FE settings (mesh, contact, solver); its material and effects are replaced
    /// by the refitted ones each round.
    pub sweep: SweepSettings,
    /// Where the ramps are cached (round 1; round k > 1 in `round_k/` inside it): an
    /// interrupted confirmation resumes.
    pub cache: std::path::PathBuf,
    /// At most this many FE rounds.
    pub rounds: usize,
    /// The FE confirms the refit when the root mean square of (FE − linearised)/σ over the
    /// used cells is below this.
    pub tolerance: f64,
}

impl FeConfirmSettings {
    /// `sweep` cached in `cache`, at most 3 rounds, tolerance 0.5 σ.
    pub fn new(sweep: SweepSettings, cache: &std::path::Path) -> Self {
        Self {
            sweep,
            cache: cache.to_path_buf(),
            rounds: 3,
            tolerance: 0.5,
        }
    }
}

/// The FE value of a cell's output in `ramps`, if its ramp reached its pressure.
fn fe_value(ramps: &[SweepRamp], c: &Cell) -> Option<f64> {
    let mode = if c.output == Output::Force {
        Mode::Force
    } else {
        Mode::Bending
    };
    let r = ramps.iter().find(|r| {
        r.mode == mode
            && r.n_bellows == c.n_bellows as usize
            && r.wall_thickness_mm == c.wall_thickness_mm
    })?;
    let st = r.at(c.pressure_bar)?;
    match c.output {
        Output::TipUz => Some(st.tip_uz_mm),
        Output::TipUy => Some(st.tip_uy_mm),
        Output::Angle => Some(st.angle_deg),
        Output::Force => st.force_n,
        Output::MarkerUz(k) => st.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[0]),
        Output::MarkerUy(k) => st.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[1]),
    }
}

/// What one FE evaluation returns for the used cells: each cell's value (none where its
/// ramp stopped before), the ramps run now, and the ramps that stopped, in words.
pub type FeEvaluation = (Vec<Option<f64>>, usize, Vec<String>);

/// An FE model for the confirmation: `(material, effect values) → FeEvaluation`.
pub type FeModel<'a> = dyn FnMut(&OgdenSet, &[f64]) -> Result<FeEvaluation, DiagnoseError> + 'a;

/// Confirms `refit` with the FE model: the recorded designs run with the refitted material
/// and the effect(s) switched on at their refitted values; where FE and the linearised
/// prediction differ by more than `fe.tolerance` (rms over the cells, in σ), the difference
/// becomes the correction `cᵢ` of the prediction and the refit is redone around it, at most
/// `fe.rounds` times. Each round is recorded in [`Refit::fe`]; the refit returned is the last.
/// `progress(done, total)` after every FE ramp.
///
/// # Errors
/// As [`refit`]; an FE sweep error (a design out of range, an unwritable cache).
pub fn confirm_with_fe(
    cells: &[Cell],
    sens: &SweepSensitivities,
    model: &Surrogate,
    first: Refit,
    s: &RefitSettings,
    fe: &FeConfirmSettings,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Refit, DiagnoseError> {
    s.validate()?;
    let rows = Rows::of(cells, sens, &s.effects)?;
    let mut designs: Vec<SweepDesign> = Vec::new();
    for c in &rows.cells {
        let n = c.n_bellows as usize;
        match designs
            .iter_mut()
            .find(|d| d.n_bellows == n && d.wall_thickness_mm == c.wall_thickness_mm)
        {
            Some(d) => {
                if !d.pressures_bar.contains(&c.pressure_bar) {
                    d.pressures_bar.push(c.pressure_bar);
                }
            }
            None => designs.push(SweepDesign {
                n_bellows: n,
                wall_thickness_mm: c.wall_thickness_mm,
                pressures_bar: vec![0.0, c.pressure_bar],
            }),
        }
    }
    for d in &mut designs {
        d.pressures_bar.sort_by(f64::total_cmp);
        d.pressures_bar.dedup();
    }
    // round 1 in the cache directory, round k > 1 in `round_k/` beside it: every round's
    // ramps stay (one file per design and rig would otherwise be overwritten by the next
    // round's material), so an interrupted confirmation resumes in the round it reached
    let mut round = 0;
    let mut run_fe = |material: &OgdenSet, values: &[f64]| -> Result<FeEvaluation, DiagnoseError> {
        round += 1;
        let cache = if round == 1 {
            fe.cache.clone()
        } else {
            fe.cache.join(format!("round_{round}"))
        };
        let mut effects = Effects::default();
        for (e, v) in s.effects.iter().zip(values) {
            effects
                .set(*e, *v)
                .map_err(|err| DiagnoseError::input(e.name(), v, &err.to_string()))?;
        }
        let settings = SweepSettings {
            material: Material::from_spec(&material.spec(), DEFAULT_BULK_RATIO).map_err(|e| {
                DiagnoseError::input("refitted material", material.spec(), &e.to_string())
            })?,
            effects,
            sensitivities: Vec::new(),
            ..fe.sweep.clone()
        };
        let ramps = run_ramps(&settings, &designs, Some(&cache), progress)
            .map_err(crate::calibrate::CalibrateError::from)?;
        let run = ramps.iter().filter(|r| r.source == RampSource::Run).count();
        let failed: Vec<String> = ramps
            .iter()
            .filter(|r| !r.error.is_empty())
            .map(|r| {
                format!(
                    "N = {}, T = {} mm, {:?}: {}",
                    r.n_bellows, r.wall_thickness_mm, r.mode, r.error
                )
            })
            .collect();
        Ok((
            rows.cells.iter().map(|c| fe_value(&ramps, c)).collect(),
            run,
            failed,
        ))
    };
    let mut out = confirm_with(&rows, model, first, s, fe.rounds, fe.tolerance, &mut run_fe)?;
    out.verdict = out.verdict.replace(
        " FE (",
        &format!(" FE ({} mesh, ", fe.sweep.mesh.level.name()),
    );
    Ok(out)
}

/// The rounds of [`confirm_with_fe`] with any FE model: `fe(material, effect values)` gives
/// the used cells' values.
///
/// # Errors
/// As [`refit`], and whatever `fe` returns.
pub(crate) fn confirm_with(
    rows: &Rows,
    model: &Surrogate,
    first: Refit,
    s: &RefitSettings,
    max_rounds: usize,
    tolerance: f64,
    fe: &mut FeModel<'_>,
) -> Result<Refit, DiagnoseError> {
    let mut rows = rows.clone();
    let space = ParamSpace::training_domain(model)?;
    let mut current = first;
    let mut rounds: Vec<FeRound> = Vec::new();
    loop {
        let material = current.after.material;
        let (values, ramps_run, failed) = fe(&material, &current.after.effects)?;
        let mut x: Vec<f64> = space.unit(&material).to_vec();
        x.extend(
            s.effects
                .iter()
                .zip(&current.after.effects)
                .map(|(e, v)| v - e.info().neutral),
        );
        let pb = Problem::new(&rows, model, space.clone(), &s.effects, s.effects.len());
        let lin = pb.predictions(&x)?;
        let mut fe_pred = lin.clone();
        let mut diffs = vec![0.0; rows.cells.len()];
        let mut worst = (0.0, String::new());
        for (i, c) in rows.cells.iter().enumerate() {
            if let Some(v) = values[i] {
                fe_pred[i] = v;
                diffs[i] = v - lin[i];
                let z = diffs[i].abs() / c.sigma;
                if z > worst.0 {
                    worst = (
                        z,
                        format!(
                            "{} at N = {}, T = {} mm, {} bar",
                            c.output.name(),
                            c.n_bellows,
                            c.wall_thickness_mm,
                            c.pressure_bar
                        ),
                    );
                }
            }
        }
        let rms = (diffs
            .iter()
            .zip(&rows.cells)
            .map(|(d, c)| (d / c.sigma).powi(2))
            .sum::<f64>()
            / rows.cells.len() as f64)
            .sqrt();
        rounds.push(FeRound {
            material,
            effects: current.after.effects.clone(),
            quality: quality(&rows.cells, &fe_pred),
            rms_fe_minus_linear: rms,
            worst,
            ramps_run,
            failed,
        });
        if rms <= tolerance || rounds.len() >= max_rounds.max(1) {
            break;
        }
        for (o, d) in rows.offset.iter_mut().zip(&diffs) {
            *o += d;
        }
        let linearised_at = current.linearised_at.clone();
        let base = linearised_at
            .split(", corrected by the FE")
            .next()
            .unwrap_or_default()
            .to_string();
        current = fit_rows(&rows, model, &material, s)?;
        current.linearised_at = format!("{base}, corrected by the FE of round {}", rounds.len());
    }
    let last = rounds.last().expect("at least one round");
    let confirmed = last.rms_fe_minus_linear <= tolerance;
    current.verdict.push_str(&format!(
        " FE ({} round(s)): {}; with the effect on at {} the FE misses the recordings by a \
         mean tip BE of {} (FE − linearised: rms {:.2} σ, worst {:.2} σ at {}).",
        rounds.len(),
        if confirmed {
            "confirmed"
        } else {
            "NOT confirmed within the tolerance"
        },
        last.effects
            .iter()
            .zip(&s.effects)
            .map(|(v, e)| format!("{} = {v:.4}", e.name()))
            .collect::<Vec<_>>()
            .join(", "),
        last.quality
            .mean_be_mm
            .map_or("—".to_string(), |b| format!("{b:.2} mm")),
        last.rms_fe_minus_linear,
        last.worst.0,
        last.worst.1
    ));
    current.fe = rounds;
    Ok(current)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::rom::Query;

    const DESIGNS: [(u32, f64); 9] = [
        (9, 1.6),
        (9, 2.0),
        (9, 2.4),
        (11, 1.6),
        (11, 2.0),
        (11, 2.4),
        (13, 1.6),
        (13, 2.0),
        (13, 2.4),
    ];

    fn value(model: &Surrogate, m: &OgdenSet, n: u32, t: f64, p: f64, o: Output) -> f64 {
        let mut pred = model.new_prediction();
        model
            .predict_scalars_into(&Query::new(n, t, p, m.as_array()), &mut pred)
            .unwrap();
        match o {
            Output::TipUz => pred.tip_uz_mm(),
            Output::TipUy => pred.tip_uy_mm(),
            _ => pred.angle_deg(),
        }
    }

    /// The effect's "true" response: `g(θ) = θ + 2θ²` times a fixed pattern over the cells.
    fn g(theta: f64) -> f64 {
        theta + 2.0 * theta * theta
    }

    #[test]
    fn fe_rounds_correct_a_nonlinear_effect_that_the_linearisation_misjudges() {
        let model = Surrogate::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/actuator_coarse.json"),
        )
        .unwrap();
        let m = OgdenSet::literature("ogden_002").unwrap();
        let truth = 0.1;
        let mut rows = Rows {
            cells: Vec::new(),
            d: Vec::new(),
            offset: Vec::new(),
        };
        for (n, t) in DESIGNS {
            for p in [1.0, 2.0, 3.0] {
                for o in [Output::TipUz, Output::TipUy, Output::Angle] {
                    let d = match o {
                        Output::TipUz => 8.0 * p * (2.7 - t),
                        Output::TipUy => -3.0 * p,
                        _ => 1.5 * p * f64::from(n) / 11.0,
                    };
                    let mut c = Cell::unit(n, t, p, o, 0.0);
                    c.recorded = value(&model, &m, n, t, p, o) + g(truth) * d;
                    rows.cells.push(c);
                    rows.d.push(vec![d]);
                    rows.offset.push(0.0);
                }
            }
        }
        let mut s = RefitSettings::new(vec![Effect::PressureLoss]);
        s.held_out = false;
        let first = fit_rows(&rows, &model, &m, &s).unwrap();
        // the linearisation (slope 1 at 0) reads g(0.1) = 0.12 as the size
        let linear = first.effects[0].value;
        assert!((linear - g(truth)).abs() < 2e-3, "{}", first.verdict);
        let mut calls = 0;
        let mut fe = |mat: &OgdenSet, v: &[f64]| -> Result<FeEvaluation, DiagnoseError> {
            calls += 1;
            Ok((
                rows.cells
                    .iter()
                    .zip(&rows.d)
                    .map(|(c, d)| {
                        Some(
                            value(
                                &model,
                                mat,
                                c.n_bellows,
                                c.wall_thickness_mm,
                                c.pressure_bar,
                                c.output,
                            ) + g(v[0]) * d[0],
                        )
                    })
                    .collect(),
                2,
                Vec::new(),
            ))
        };
        let r = confirm_with(&rows, &model, first, &s, 8, 0.01, &mut fe).unwrap();
        let last = r.fe.last().unwrap();
        assert!(r.fe.len() >= 3 && r.fe.len() <= 8, "{} rounds", r.fe.len());
        assert_eq!(calls, r.fe.len());
        // the first round sees the linearisation's error; the last one agrees with the FE
        assert!(r.fe[0].rms_fe_minus_linear > 0.05, "{:?}", r.fe[0]);
        assert!(last.rms_fe_minus_linear <= 0.01, "{last:?}");
        assert!((last.effects[0] - truth).abs() < 2e-3, "{:?}", last.effects);
        assert!(r.verdict.contains("round(s)): confirmed;"), "{}", r.verdict);
        assert!(r.linearised_at.contains("corrected by the FE of round"));
    }
}
