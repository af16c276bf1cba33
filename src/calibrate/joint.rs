//! Joint identification of the material and the dimensions the reference study leaves
//! unstated, straight on the FE model.
//!
//! ## Unknowns
//!
//! `θ` collects the chosen [`Unknown`]s: Ogden parameters (`mu1`, `alpha1`, `mu2`, `alpha2`),
//! the unstated dimensions of the actuator as one [`Geometry`] shared by every design
//! (`gap`, `base`, `duct`, `side_wall`, `free_length`, mm), and any effect of the library
//! (`plate_offset` for the force rig's printed square, `wall_bias_bellows`, `clamp_compliance`,
//! …). Each has bounds: the physical range of a dimension ([`crate::fe::preset`]), the range of
//! an effect, and for the material a sign-keeping box around the start
//! (`μᵢ ∈ [μᵢ⁰/5, 5μᵢ⁰]`, `|αᵢ| ∈ [0.5, 12]`).
//!
//! ## Objective
//!
//! The calibrator's noise model ([`super::objective`]): per recorded configuration the tip
//! `Uz`, `Uy` with `σ = r·σ_α` (`r` the recorded chord, `σ_α` the recorded angle scatter) and
//! the blocked force with its recorded `σ_F`; `r(θ) = (y_FE(θ) − y)/σ`, `χ² = Σ r²`.
//!
//! ## Method: FE-direct Levenberg–Marquardt
//!
//! Every evaluation of `θ` is one sweep of the FE model over the recorded designs (one bending
//! and one blocked-force ramp per design, [`super::baseline::run_ramps`]) with the direct
//! sensitivities of every output with respect to every unknown ([`crate::fe::sensitivity`]):
//! a dimension `d` of the geometry is differentiated through its bias effect at zero
//! (`∂/∂gap = ∂/∂gap_bias`, `∂/∂side_wall = ∂/∂wall_bias_side`, …). So one sweep gives `r`
//! and the Jacobian `J`, and the step solves
//!
//! ```text
//!   (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr,     θ' = clip(θ + δ, bounds)
//! ```
//!
//! A step is taken when the FE at `θ'` lowers `χ²` (gain ratio `ρ` of actual to linearly
//! predicted decrease `> 0`); `λ` follows Nielsen's rule (`λ·max(1/3, 1 − (2ρ − 1)³)` on
//! success, `λ·ν`, `ν ← 2ν` on failure). A sweep whose FE fails counts as a failed step. It
//! stops when `χ²` falls by less than a relative `1e-3` over an accepted step, when `λ`
//! exceeds `1e8`, or after the iteration budget ([`JointStop`]).
//!
//! Every sweep is cached (one file per ramp, keyed by everything that defines it), so an
//! interrupted identification rerun with the same settings replays the same sequence of
//! steps from the cache and resumes where it stopped.
//!
//! ## What the data determine
//!
//! At the optimum, `C = (JᵀJ)⁻¹` (residuals are already in units of σ) gives each unknown's
//! standard error and the correlations; an unknown on a bound is reported as such.

use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::baseline::{run_ramps, SweepDesign, SweepRamp, SweepSettings};
use super::experiments::bending_error;
use super::objective::{Recordings, FREE_LENGTH_MM};
use super::CalibrateError;
use crate::fe::effects::{Effect, Effects};
use crate::fe::geometry::PRINTED_WALL_RANGE;
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::mesh::MeshOptions;
use crate::fe::preset::{
    Geometry, BASE_RANGE, DUCT_HALF_WIDTH_RANGE, FREE_LENGTH_RANGE, GAP_RANGE,
};
use crate::fe::sensitivity::{OgdenParameter, Parameter};
use crate::fe::simulate::Mode;

/// One unknown of the identification.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unknown {
    /// An Ogden parameter.
    Material(OgdenParameter),
    /// Gap between the bellows (mm).
    Gap,
    /// Base thickness (mm).
    Base,
    /// Duct half-width (mm).
    Duct,
    /// Side-wall thickness, the same for every T (mm).
    SideWall,
    /// Free length (mm).
    FreeLength,
    /// An effect of the library at one value for every ramp.
    Effect(Effect),
}

impl Unknown {
    /// Its name on the command line and in reports.
    pub fn name(self) -> String {
        match self {
            Unknown::Material(m) => Parameter::Material(m).name().to_string(),
            Unknown::Gap => "gap".into(),
            Unknown::Base => "base".into(),
            Unknown::Duct => "duct".into(),
            Unknown::SideWall => "side_wall".into(),
            Unknown::FreeLength => "free_length".into(),
            Unknown::Effect(e) => e.name().to_string(),
        }
    }

    /// The unknown called `name`.
    ///
    /// # Errors
    /// [`CalibrateError::Input`] listing the names.
    pub fn from_name(name: &str) -> Result<Self, CalibrateError> {
        Ok(match name {
            "gap" => Unknown::Gap,
            "base" => Unknown::Base,
            "duct" => Unknown::Duct,
            "side_wall" => Unknown::SideWall,
            "free_length" => Unknown::FreeLength,
            n => match Parameter::from_name(n) {
                Ok(Parameter::Material(m)) => Unknown::Material(m),
                Ok(Parameter::Effect(e)) => match e {
                    Effect::GapBias
                    | Effect::BaseBias
                    | Effect::DuctBias
                    | Effect::WallBiasSide
                    | Effect::FreeLengthBias => {
                        return Err(CalibrateError::input(
                            "unknown",
                            n,
                            "the dimension itself (gap, base, duct, side_wall, free_length), \
                             not its bias",
                        ))
                    }
                    e => Unknown::Effect(e),
                },
                Err(_) => {
                    return Err(CalibrateError::input(
                        "unknown",
                        n,
                        "mu1, alpha1, mu2, alpha2, gap, base, duct, side_wall, free_length or \
                         an effect name (surrogate effects)",
                    ))
                }
            },
        })
    }

    /// The parameter whose sensitivities are this unknown's derivatives.
    pub fn parameter(self) -> Parameter {
        match self {
            Unknown::Material(m) => Parameter::Material(m),
            Unknown::Gap => Parameter::Effect(Effect::GapBias),
            Unknown::Base => Parameter::Effect(Effect::BaseBias),
            Unknown::Duct => Parameter::Effect(Effect::DuctBias),
            Unknown::SideWall => Parameter::Effect(Effect::WallBiasSide),
            Unknown::FreeLength => Parameter::Effect(Effect::FreeLengthBias),
            Unknown::Effect(e) => Parameter::Effect(e),
        }
    }
}

/// A point of the identification: material, geometry, effects.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointPoint {
    /// Ogden `[μ1, α1, μ2, α2]`.
    pub ogden: [f64; 4],
    /// The geometry.
    pub geometry: Geometry,
    /// The effects (rig, tolerances).
    pub effects: Effects,
}

impl JointPoint {
    /// The value of `u` here.
    pub fn get(&self, u: Unknown) -> f64 {
        let g = &self.geometry;
        match u {
            Unknown::Material(m) => self.ogden[m as usize],
            Unknown::Gap => g.gap_mm,
            Unknown::Base => g.base_thickness_mm,
            Unknown::Duct => g.duct_half_width_mm,
            Unknown::SideWall => g.side_wall_mm.unwrap_or(f64::NAN),
            Unknown::FreeLength => g.free_length_mm,
            Unknown::Effect(e) => self.effects.get(e),
        }
    }

    /// This point with `u` set to `v`.
    ///
    /// # Errors
    /// An effect value outside its range.
    pub fn set(&mut self, u: Unknown, v: f64) -> Result<(), CalibrateError> {
        let g = &mut self.geometry;
        match u {
            Unknown::Material(m) => self.ogden[m as usize] = v,
            Unknown::Gap => g.gap_mm = v,
            Unknown::Base => g.base_thickness_mm = v,
            Unknown::Duct => g.duct_half_width_mm = v,
            Unknown::SideWall => g.side_wall_mm = Some(v),
            Unknown::FreeLength => g.free_length_mm = v,
            Unknown::Effect(e) => self
                .effects
                .set(e, v)
                .map_err(|err| CalibrateError::input(e.name(), v, &err.to_string()))?,
        }
        Ok(())
    }
}

/// Bounds of `u` for a start at `x0`.
pub fn bounds(u: Unknown, x0: f64) -> (f64, f64) {
    match u {
        Unknown::Material(OgdenParameter::Mu1 | OgdenParameter::Mu2) => {
            let (a, b) = (x0 / 5.0, x0 * 5.0);
            (a.min(b), a.max(b))
        }
        Unknown::Material(_) if x0 >= 0.0 => (0.5, 12.0),
        Unknown::Material(_) => (-12.0, -0.5),
        Unknown::Gap => GAP_RANGE,
        Unknown::Base => BASE_RANGE,
        Unknown::Duct => DUCT_HALF_WIDTH_RANGE,
        Unknown::SideWall => PRINTED_WALL_RANGE,
        Unknown::FreeLength => FREE_LENGTH_RANGE,
        Unknown::Effect(e) => e.info().range,
    }
}

/// Settings of an identification.
#[derive(Clone, Debug)]
pub struct JointSettings {
    /// The unknowns.
    pub unknowns: Vec<Unknown>,
    /// Where it starts.
    pub start: JointPoint,
    /// The FE mesh.
    pub mesh: MeshOptions,
    /// Largest number of FE sweeps (each one evaluation of `θ` with its Jacobian).
    pub max_sweeps: usize,
    /// Initial damping `λ` (relative to `diag(JᵀJ)`).
    pub lambda0: f64,
    /// Cache directory of the ramps (resumable).
    pub cache: Option<PathBuf>,
}

/// How the identification stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointStop {
    /// `χ²` fell by less than a relative 1e-3 over an accepted step.
    Converged,
    /// The damping grew past 1e8 without a successful step.
    NoDescent,
    /// The sweep budget ran out.
    Budget,
}

/// One FE sweep of the identification.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointSweep {
    /// The point.
    pub point: JointPoint,
    /// `χ²` there (`inf` when the FE failed).
    pub chi2: f64,
    /// Mean tip bending error over the recorded configurations (mm).
    pub mean_be_mm: f64,
    /// Mean |F_FE − F| (N).
    pub mean_abs_force_error_n: f64,
    /// Whether the step to it was taken.
    pub accepted: bool,
    /// The damping `λ` of the step that led here (0 for the start).
    pub lambda: f64,
    /// `χ²` predicted by the linearisation for this step.
    pub predicted_chi2: f64,
    /// The FE's message where a ramp failed.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub error: String,
}

/// One recorded configuration at the optimum.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointRow {
    /// N.
    pub n_bellows: usize,
    /// T (mm).
    pub wall_thickness_mm: f64,
    /// P (bar).
    pub pressure_bar: f64,
    /// One of the reference study's nine (T and P together: 1.6/1, 2.0/2, 2.4/3).
    pub paper_nine: bool,
    /// Recorded, FE tip Uz (mm).
    pub uz_mm: [f64; 2],
    /// Recorded, FE tip Uy (mm).
    pub uy_mm: [f64; 2],
    /// Recorded, FE angle (deg).
    pub angle_deg: [f64; 2],
    /// Recorded, FE blocked force (N).
    pub force_n: [f64; 2],
    /// Tip bending error (mm).
    pub be_mm: f64,
}

/// An unknown at the optimum.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointEstimate {
    /// Its name.
    pub name: String,
    /// Start value.
    pub start: f64,
    /// Value at the optimum.
    pub value: f64,
    /// Standard error from `(JᵀJ)⁻¹` (NaN where `JᵀJ` is singular).
    pub std_error: f64,
    /// Bounds.
    pub bounds: (f64, f64),
    /// Whether it sits on a bound (within 1e-6 of the range).
    pub on_bound: bool,
}

/// The identification's report.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointReport {
    /// The FE mesh level.
    pub mesh: String,
    /// The unknowns at the optimum.
    pub estimates: Vec<JointEstimate>,
    /// Correlations of the unknowns (row-major, in the order of `estimates`).
    pub correlations: Vec<Vec<f64>>,
    /// The optimum.
    pub optimum: JointPoint,
    /// Every sweep, in order.
    pub sweeps: Vec<JointSweep>,
    /// How it stopped.
    pub stop: JointStop,
    /// Each recorded configuration at the optimum.
    pub rows: Vec<JointRow>,
    /// Mean BE over all configurations (mm).
    pub mean_be_mm: f64,
    /// Mean BE over the reference study's nine (mm).
    pub mean_be_paper_nine_mm: f64,
    /// RMS angle error (deg).
    pub rms_angle_error_deg: f64,
    /// Mean |force error| (N).
    pub mean_abs_force_error_n: f64,
    /// Mean force error, FE − recorded (N).
    pub mean_force_error_n: f64,
}

/// Whether `(t, p)` is one of the reference study's nine configurations: T and P move
/// together there (T 1.6 mm at 1 bar, 2.0 at 2 bar, 2.4 at 3 bar), for each N.
pub fn in_paper_nine(t: f64, p: f64) -> bool {
    [(1.6, 1.0), (2.0, 2.0), (2.4, 3.0)]
        .iter()
        .any(|&(tt, pp)| (t - tt).abs() < 1e-9 && (p - pp).abs() < 1e-9)
}

/// One evaluation: residuals, Jacobian, the rows.
struct Evaluation {
    r: DVector<f64>,
    j: DMatrix<f64>,
    rows: Vec<JointRow>,
    error: String,
}

/// The sweep settings of a point.
fn sweep_settings(s: &JointSettings, x: &JointPoint) -> Result<SweepSettings, CalibrateError> {
    let [m1, a1, m2, a2] = x.ogden;
    let material = Material::from_spec(&format!("{m1},{a1},{m2},{a2}"), DEFAULT_BULK_RATIO)
        .map_err(|e| CalibrateError::input("material", format!("{:?}", x.ogden), &e.to_string()))?;
    x.geometry
        .validate()
        .map_err(|e| CalibrateError::input("geometry", &x.geometry.name, &e.to_string()))?;
    let mut settings = SweepSettings {
        geometry: x.geometry.clone(),
        effects: x.effects.clone(),
        sensitivities: s.unknowns.iter().map(|u| u.parameter()).collect(),
        ..SweepSettings::new(material, s.mesh)
    };
    settings.solver.max_pressure_increment = crate::diagnose::sweep::SWEEP_MAX_PRESSURE_INCREMENT;
    settings.solver.rtol = crate::diagnose::sweep::SWEEP_RTOL;
    Ok(settings)
}

/// The designs of the recordings with 0 and their pressures.
fn designs(rec: &Recordings) -> Vec<SweepDesign> {
    super::baseline::recorded_designs(&rec.bending)
}

fn evaluate(
    s: &JointSettings,
    rec: &Recordings,
    x: &JointPoint,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Evaluation, CalibrateError> {
    let settings = sweep_settings(s, x)?;
    let ramps = run_ramps(&settings, &designs(rec), s.cache.as_deref(), progress)?;
    Ok(residuals(s, rec, &ramps))
}

fn residuals(s: &JointSettings, rec: &Recordings, ramps: &[SweepRamp]) -> Evaluation {
    let k = s.unknowns.len();
    let params: Vec<Parameter> = s.unknowns.iter().map(|u| u.parameter()).collect();
    let mut r = Vec::new();
    let mut jac: Vec<Vec<f64>> = Vec::new();
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    let find = |n: usize, t: f64, mode: Mode| {
        ramps
            .iter()
            .find(|x| x.mode == mode && x.n_bellows == n && x.wall_thickness_mm == t)
    };
    for b in &rec.bending {
        let (n, t, p) = (b.n_bellows, b.wall_thickness_mm, b.pressure_bar);
        let mut row = JointRow {
            n_bellows: n,
            wall_thickness_mm: t,
            pressure_bar: p,
            paper_nine: in_paper_nine(t, p),
            uz_mm: [b.tip_uz_mm, f64::NAN],
            uy_mm: [b.tip_uy_mm, f64::NAN],
            angle_deg: [b.angle_deg, f64::NAN],
            force_n: [f64::NAN; 2],
            be_mm: f64::NAN,
        };
        let chord = (FREE_LENGTH_MM - b.tip_uz_mm).hypot(b.tip_uy_mm);
        let st = chord * b.angle_std_deg.to_radians();
        match derivs(find(n, t, Mode::Bending), p, &params) {
            Some((v, d)) => {
                row.uz_mm[1] = v.tip_uz_mm;
                row.uy_mm[1] = v.tip_uy_mm;
                row.angle_deg[1] = v.angle_deg;
                row.be_mm = bending_error(b.tip_uz_mm, b.tip_uy_mm, v.tip_uz_mm, v.tip_uy_mm);
                r.push((v.tip_uz_mm - b.tip_uz_mm) / st);
                jac.push(d.iter().map(|o| o.tip_uz_mm / st).collect());
                r.push((v.tip_uy_mm - b.tip_uy_mm) / st);
                jac.push(d.iter().map(|o| o.tip_uy_mm / st).collect());
            }
            None => errors.push(format!("bending N = {n}, T = {t}, {p} bar")),
        }
        if let Some(f) = rec
            .force
            .iter()
            .find(|f| f.n_bellows == n && f.wall_thickness_mm == t && f.pressure_bar == p)
        {
            row.force_n[0] = f.force_n;
            match derivs(find(n, t, Mode::Force), p, &params) {
                Some((v, d)) => {
                    let fe = v.force_n.unwrap_or(f64::NAN);
                    row.force_n[1] = fe;
                    r.push((fe - f.force_n) / f.force_std_n);
                    jac.push(
                        d.iter()
                            .map(|o| o.force_n.unwrap_or(0.0) / f.force_std_n)
                            .collect(),
                    );
                }
                None => errors.push(format!("force N = {n}, T = {t}, {p} bar")),
            }
        }
        rows.push(row);
    }
    let m = r.len();
    let j = DMatrix::from_fn(m, k, |i, c| jac[i][c]);
    let error = if errors.is_empty() {
        String::new()
    } else {
        let why: Vec<&str> = ramps
            .iter()
            .filter(|x| !x.error.is_empty())
            .map(|x| x.error.as_str())
            .collect();
        format!("no FE result at {}: {}", errors.join(", "), why.join("; "))
    };
    Evaluation {
        r: DVector::from_vec(r),
        j,
        rows,
        error,
    }
}

/// The outputs at pressure `p` of a ramp and their derivatives by `params`.
fn derivs(
    ramp: Option<&SweepRamp>,
    p: f64,
    params: &[Parameter],
) -> Option<(
    crate::fe::sensitivity::Outputs,
    Vec<crate::fe::sensitivity::Outputs>,
)> {
    let sens = ramp?.sensitivities.as_ref()?;
    let i = sens
        .steps
        .iter()
        .position(|st| (st.pressure_bar - p).abs() < 1e-9)?;
    let d = params
        .iter()
        .map(|&q| sens.derivative(i, q).cloned())
        .collect::<Option<Vec<_>>>()?;
    Some((sens.steps[i].values.clone(), d))
}

fn chi2(e: &Evaluation) -> f64 {
    if e.error.is_empty() {
        e.r.norm_squared()
    } else {
        f64::INFINITY
    }
}

fn summary_of(rows: &[JointRow]) -> (f64, f64) {
    let be: Vec<f64> = rows.iter().map(|r| r.be_mm).collect();
    let fe: Vec<f64> = rows
        .iter()
        .map(|r| (r.force_n[1] - r.force_n[0]).abs())
        .filter(|v| v.is_finite())
        .collect();
    (mean(&be), mean(&fe))
}

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Identifies the unknowns of `settings` on the recordings `rec`;
/// `progress(sweep, ramp, ramps)` after every FE ramp.
///
/// # Errors
/// A start outside the bounds or with an invalid geometry or material; an FE failure at the
/// start; an unwritable cache.
pub fn identify(
    settings: &JointSettings,
    rec: &Recordings,
    progress: impl Fn(usize, usize, usize) + Sync,
) -> Result<JointReport, CalibrateError> {
    let s = settings;
    if s.unknowns.is_empty() {
        return Err(CalibrateError::input(
            "unknowns",
            "none",
            "at least one unknown",
        ));
    }
    let mut x = s.start.clone();
    let bnds: Vec<(f64, f64)> = s
        .unknowns
        .iter()
        .map(|&u| {
            if u == Unknown::SideWall && x.geometry.side_wall_mm.is_none() {
                x.geometry.side_wall_mm = Some(2.0);
            }
            bounds(u, s.start.get(u))
        })
        .collect();
    for (&u, &(lo, hi)) in s.unknowns.iter().zip(&bnds) {
        let v = x.get(u);
        if !(v >= lo && v <= hi) {
            return Err(CalibrateError::input(
                &u.name(),
                v,
                &format!("a start inside its bounds [{lo}, {hi}]"),
            ));
        }
    }
    let mut sweep_no = 0usize;
    let mut eval_at = |x: &JointPoint| {
        sweep_no += 1;
        let k = sweep_no;
        evaluate(s, rec, x, &|d, n| progress(k, d, n))
    };
    let mut cur = eval_at(&x)?;
    if !cur.error.is_empty() {
        return Err(CalibrateError::input(
            "start",
            "the FE model",
            &format!("a start the FE reaches ({})", cur.error),
        ));
    }
    let (be0, f0) = summary_of(&cur.rows);
    let mut sweeps = vec![JointSweep {
        point: x.clone(),
        chi2: chi2(&cur),
        mean_be_mm: be0,
        mean_abs_force_error_n: f0,
        accepted: true,
        lambda: 0.0,
        predicted_chi2: chi2(&cur),
        error: String::new(),
    }];
    let mut lambda = s.lambda0;
    let mut nu = 2.0;
    let stop = loop {
        if sweeps.len() >= s.max_sweeps {
            break JointStop::Budget;
        }
        if lambda > 1e8 {
            break JointStop::NoDescent;
        }
        let jtj = cur.j.transpose() * &cur.j;
        let g = cur.j.transpose() * &cur.r;
        let mut a = jtj.clone();
        for i in 0..a.nrows() {
            a[(i, i)] += lambda * jtj[(i, i)].max(1e-12);
        }
        let Some(delta) = a.cholesky().map(|c| c.solve(&(-&g))) else {
            lambda *= nu;
            nu *= 2.0;
            continue;
        };
        let mut trial = x.clone();
        let mut step = DVector::zeros(delta.len());
        for (i, (&u, &(lo, hi))) in s.unknowns.iter().zip(&bnds).enumerate() {
            let v = (x.get(u) + delta[i]).clamp(lo, hi);
            step[i] = v - x.get(u);
            trial.set(u, v)?;
        }
        let predicted = (&cur.r + &cur.j * &step).norm_squared();
        let c0 = chi2(&cur);
        let next = eval_at(&trial);
        let (c1, next) = match next {
            Ok(e) => (chi2(&e), Some(e)),
            Err(e) => {
                sweeps.push(JointSweep {
                    point: trial.clone(),
                    chi2: f64::INFINITY,
                    mean_be_mm: f64::NAN,
                    mean_abs_force_error_n: f64::NAN,
                    accepted: false,
                    lambda,
                    predicted_chi2: predicted,
                    error: e.to_string(),
                });
                lambda *= nu;
                nu *= 2.0;
                continue;
            }
        };
        let next = next.expect("set above");
        let rho = (c0 - c1) / (c0 - predicted).max(1e-300);
        let (be, fe) = summary_of(&next.rows);
        let accepted = c1.is_finite() && rho > 0.0;
        sweeps.push(JointSweep {
            point: trial.clone(),
            chi2: c1,
            mean_be_mm: be,
            mean_abs_force_error_n: fe,
            accepted,
            lambda,
            predicted_chi2: predicted,
            error: next.error.clone(),
        });
        if accepted {
            x = trial;
            cur = next;
            lambda *= (1.0 / 3.0f64).max(1.0 - (2.0 * rho - 1.0).powi(3));
            nu = 2.0;
            if (c0 - c1) / c0 < 1e-3 {
                break JointStop::Converged;
            }
        } else {
            lambda *= nu;
            nu *= 2.0;
        }
    };
    Ok(report(s, &bnds, x, cur, sweeps, stop))
}

fn report(
    s: &JointSettings,
    bnds: &[(f64, f64)],
    x: JointPoint,
    cur: Evaluation,
    sweeps: Vec<JointSweep>,
    stop: JointStop,
) -> JointReport {
    let k = s.unknowns.len();
    let cov = (cur.j.transpose() * &cur.j).try_inverse();
    let se = |i: usize| cov.as_ref().map_or(f64::NAN, |c| c[(i, i)].max(0.0).sqrt());
    let estimates = s
        .unknowns
        .iter()
        .enumerate()
        .map(|(i, &u)| {
            let (lo, hi) = bnds[i];
            let v = x.get(u);
            JointEstimate {
                name: u.name(),
                start: s.start.get(u),
                value: v,
                std_error: se(i),
                bounds: (lo, hi),
                on_bound: (v - lo).abs() <= 1e-6 * (hi - lo) || (hi - v).abs() <= 1e-6 * (hi - lo),
            }
        })
        .collect();
    let correlations = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| {
                    cov.as_ref()
                        .map_or(f64::NAN, |c| c[(i, j)] / (se(i) * se(j)))
                })
                .collect()
        })
        .collect();
    let rows = cur.rows;
    let (mean_be_mm, mean_abs_force_error_n) = summary_of(&rows);
    let nine: Vec<f64> = rows
        .iter()
        .filter(|r| r.paper_nine)
        .map(|r| r.be_mm)
        .collect();
    let da: Vec<f64> = rows
        .iter()
        .map(|r| (r.angle_deg[1] - r.angle_deg[0]).powi(2))
        .collect();
    let df: Vec<f64> = rows
        .iter()
        .map(|r| r.force_n[1] - r.force_n[0])
        .filter(|v| v.is_finite())
        .collect();
    JointReport {
        mesh: s.mesh.level.name().to_string(),
        estimates,
        correlations,
        optimum: x,
        sweeps,
        stop,
        rows,
        mean_be_mm,
        mean_be_paper_nine_mm: mean(&nine),
        rms_angle_error_deg: mean(&da).sqrt(),
        mean_abs_force_error_n,
        mean_force_error_n: mean(&df),
    }
}

impl JointReport {
    /// The report in words (Markdown).
    pub fn summary(&self) -> String {
        let mut s = String::new();
        s.push_str(&format!(
            "# Joint identification of the material and the unstated dimensions\n\n\
             FE-direct Levenberg–Marquardt on the {} mesh: {} sweeps, stopped: {:?}.\n\n\
             | | value |\n|---|---|\n\
             | mean tip BE, all {} configurations | {:.2} mm |\n\
             | mean tip BE, the reference study's nine | {:.2} mm |\n\
             | rms angle error | {:.2}° |\n\
             | mean abs. blocked-force error | {:.3} N |\n\
             | mean blocked-force error (FE − recorded) | {:+.3} N |\n\n",
            self.mesh,
            self.sweeps.len(),
            self.stop,
            self.rows.len(),
            self.mean_be_mm,
            self.mean_be_paper_nine_mm,
            self.rms_angle_error_deg,
            self.mean_abs_force_error_n,
            self.mean_force_error_n
        ));
        s.push_str("| unknown | start | value | std. error | bounds | on a bound |\n|---|---|---|---|---|---|\n");
        for e in &self.estimates {
            s.push_str(&format!(
                "| {} | {:.6} | {:.6} | {:.3e} | [{}, {}] | {} |\n",
                e.name,
                e.start,
                e.value,
                e.std_error,
                e.bounds.0,
                e.bounds.1,
                if e.on_bound {
                    "**yes**: the range truncates the optimum"
                } else {
                    "no"
                }
            ));
        }
        s.push_str("\n## Sweeps\n\n| # | χ² | predicted χ² | λ | mean BE (mm) | mean abs. F error (N) | taken |\n|---|---|---|---|---|---|---|\n");
        for (i, w) in self.sweeps.iter().enumerate() {
            s.push_str(&format!(
                "| {} | {:.1} | {:.1} | {:.2e} | {:.2} | {:.3} | {} |\n",
                i + 1,
                w.chi2,
                w.predicted_chi2,
                w.lambda,
                w.mean_be_mm,
                w.mean_abs_force_error_n,
                if w.accepted { "yes" } else { "no" }
            ));
        }
        s.push_str("\n## Configurations at the optimum\n\n| N | T | P | nine | Uz rec/FE | Uy rec/FE | angle rec/FE | F rec/FE | BE |\n|---|---|---|---|---|---|---|---|---|\n");
        for r in &self.rows {
            s.push_str(&format!(
                "| {} | {} | {} | {} | {:.1} / {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.3} / {:.3} | {:.2} |\n",
                r.n_bellows,
                r.wall_thickness_mm,
                r.pressure_bar,
                if r.paper_nine { "yes" } else { "" },
                r.uz_mm[0],
                r.uz_mm[1],
                r.uy_mm[0],
                r.uy_mm[1],
                r.angle_deg[0],
                r.angle_deg[1],
                r.force_n[0],
                r.force_n[1],
                r.be_mm
            ));
        }
        s
    }

    /// Writes `report.json` and `summary.md` into `dir`, atomically.
    ///
    /// # Errors
    /// An unwritable directory.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        let json = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::io::write_atomic(&dir.join("report.json"), json.as_bytes())?;
        crate::io::write_atomic(&dir.join("summary.md"), self.summary().as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_nine_move_t_and_p_together() {
        assert!(in_paper_nine(1.6, 1.0) && in_paper_nine(2.0, 2.0) && in_paper_nine(2.4, 3.0));
        assert!(!in_paper_nine(1.6, 3.0) && !in_paper_nine(2.4, 1.0));
    }

    #[test]
    fn unknowns_are_named_and_biases_refused() {
        for n in [
            "mu1",
            "alpha2",
            "gap",
            "side_wall",
            "plate_offset",
            "wall_bias_bellows",
        ] {
            assert_eq!(Unknown::from_name(n).unwrap().name(), n);
        }
        let e = Unknown::from_name("gap_bias").unwrap_err().to_string();
        assert!(e.contains("not its bias"), "{e}");
        assert!(Unknown::from_name("colour").is_err());
        assert_eq!(
            Unknown::SideWall.parameter(),
            Parameter::Effect(Effect::WallBiasSide)
        );
        assert_eq!(
            bounds(Unknown::Material(OgdenParameter::Mu2), -5.0),
            (-25.0, -1.0)
        );
        assert_eq!(
            bounds(Unknown::Material(OgdenParameter::Alpha2), -2.0),
            (-12.0, -0.5)
        );
    }
}
