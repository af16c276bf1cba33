//! One evaluation of a point: the FE sweep over the recorded designs, and from it the
//! whitened residuals, their Jacobian with respect to the unknowns and the recorded
//! configurations side by side with the FE.

use nalgebra::{DMatrix, DVector};

use super::report::JointRow;
use super::settings::JointSettings;
use super::unknown::JointPoint;
use crate::calibrate::baseline::{
    recorded_designs, run_ramps, SweepDesign, SweepRamp, SweepSettings,
    SWEEP_MAX_PRESSURE_INCREMENT, SWEEP_RTOL,
};
use crate::calibrate::experiments::bending_error;
use crate::calibrate::objective::{Config, Recording, Recordings, FREE_LENGTH_MM};
use crate::calibrate::CalibrateError;
use crate::fe::campaign::WarmPool;
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::sensitivity::Parameter;
use crate::fe::simulate::Mode;

/// Whether `(t, p)` is one of the reference study's nine configurations: T and P move
/// together there (T 1.6 mm at 1 bar, 2.0 at 2 bar, 2.4 at 3 bar), for each N.
pub fn in_paper_nine(t: f64, p: f64) -> bool {
    [(1.6, 1.0), (2.0, 2.0), (2.4, 3.0)]
        .iter()
        .any(|&(tt, pp)| (t - tt).abs() < 1e-9 && (p - pp).abs() < 1e-9)
}

/// One evaluation: residuals, Jacobian, the rows.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub struct Evaluation {
    pub r: DVector<f64>,
    pub j: DMatrix<f64>,
    /// What each residual is: design `(N, T)`, pressure, output, σ.
    pub what: Vec<Residual>,
    pub rows: Vec<JointRow>,
    pub error: String,
}

/// What one residual of an evaluation is.
// public for the tests in tests/calibrate/
#[doc(hidden)]
#[derive(Clone, Copy, Debug)]
pub struct Residual {
    pub n: usize,
    pub t: f64,
    pub output: Recorded,
    pub sigma: f64,
}

/// A recorded output of the identification.
// public for the tests in tests/calibrate/
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recorded {
    TipUz,
    TipUy,
    Force,
}

/// The distinct parameters whose sensitivities the unknowns read, in the unknowns' order.
fn parameters(s: &JointSettings) -> Vec<Parameter> {
    let mut out: Vec<Parameter> = Vec::new();
    for u in &s.unknowns {
        if !out.contains(&u.parameter()) {
            out.push(u.parameter());
        }
    }
    out
}

/// The sweep settings of a point.
fn sweep_settings(
    s: &JointSettings,
    x: &JointPoint,
    pool: Option<&WarmPool>,
) -> Result<SweepSettings, CalibrateError> {
    let material = Material::from_spec(&x.ogden.spec(), DEFAULT_BULK_RATIO).map_err(|e| {
        CalibrateError::input(
            "material",
            format!("{:?}", x.ogden.as_array()),
            &e.to_string(),
        )
    })?;
    x.geometry
        .validate()
        .map_err(|e| CalibrateError::input("geometry", &x.geometry.name, &e.to_string()))?;
    let mut settings = SweepSettings {
        geometry: x.geometry.clone(),
        effects: x.effects.clone(),
        sensitivities: parameters(s),
        warm: pool.cloned(),
        warm_point: s.unknowns.iter().map(|&u| x.get(u)).collect(),
        ..SweepSettings::new(material, s.mesh)
    };
    settings.solver.max_pressure_increment = SWEEP_MAX_PRESSURE_INCREMENT;
    settings.solver.rtol = SWEEP_RTOL;
    Ok(settings)
}

/// The designs of the recordings with 0 and their pressures.
fn designs(rec: &Recordings) -> Vec<SweepDesign> {
    recorded_designs(&rec.bending)
}

/// Evaluation `k` (from 1) caches its ramps in `sweep_k/` of the cache: a rerun with the same
/// settings takes the same steps and finds each sweep where it left it.
pub(super) fn evaluate(
    s: &JointSettings,
    rec: &Recordings,
    x: &JointPoint,
    k: usize,
    pool: Option<&WarmPool>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Evaluation, CalibrateError> {
    let settings = sweep_settings(s, x, pool)?;
    // a point where a recorded design cannot be built (a printed cavity closed by the walls)
    // is a failed step before any FE runs
    for d in designs(rec) {
        x.geometry
            .design(d.n_bellows, d.wall_thickness_mm)
            .map_err(|e| CalibrateError::input("geometry", &x.geometry.name, &e.to_string()))?;
    }
    let cache = s.cache.as_ref().map(|c| c.join(format!("sweep_{k:02}")));
    let ramps = run_ramps(&settings, &designs(rec), cache.as_deref(), progress)?;
    Ok(residuals(s, rec, x, &ramps))
}

// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn residuals(
    s: &JointSettings,
    rec: &Recordings,
    x: &JointPoint,
    ramps: &[SweepRamp],
) -> Evaluation {
    let params: Vec<Parameter> = s.unknowns.iter().map(|u| u.parameter()).collect();
    let mut acc = Accumulator::default();
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    let find = |n: usize, t: f64, mode: Mode| {
        ramps
            .iter()
            .find(|x| x.mode == mode && x.n_bellows == n && x.wall_thickness_mm == t)
    };
    for b in &rec.bending {
        let (n, t, p) = (b.n_bellows, b.wall_thickness_mm, b.pressure_bar);
        let fac: Vec<f64> = s
            .unknowns
            .iter()
            .map(|u| u.design_factor(&x.geometry, n, t))
            .collect();
        let shift = s.correction.as_ref().and_then(|c| c.at(n, t, p)).copied();
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
            tip_excluded: excluded(s, n, t, p, Recording::Bending),
            force_excluded: excluded(s, n, t, p, Recording::Force),
        };
        match derivs(find(n, t, Mode::Bending), p, &params) {
            Some((v, d)) => {
                let (dz, dy, da) =
                    shift.map_or((0.0, 0.0, 0.0), |c| (c.uz_mm, c.uy_mm, c.angle_deg));
                row.uz_mm[1] = v.tip_uz_mm + dz;
                row.uy_mm[1] = v.tip_uy_mm + dy;
                row.angle_deg[1] = v.angle_deg + da;
                row.be_mm = bending_error(b.tip_uz_mm, b.tip_uy_mm, row.uz_mm[1], row.uy_mm[1]);
                if !row.tip_excluded {
                    let chord = (FREE_LENGTH_MM - b.tip_uz_mm).hypot(b.tip_uy_mm);
                    let st = (chord * b.angle_std_deg.to_radians()).hypot(s.model_sigma.tip_mm);
                    let at = |output| Residual {
                        n,
                        t,
                        output,
                        sigma: st,
                    };
                    acc.push(
                        at(Recorded::TipUz),
                        row.uz_mm[1] - b.tip_uz_mm,
                        &d,
                        &fac,
                        |o| o.tip_uz_mm,
                    );
                    acc.push(
                        at(Recorded::TipUy),
                        row.uy_mm[1] - b.tip_uy_mm,
                        &d,
                        &fac,
                        |o| o.tip_uy_mm,
                    );
                }
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
                    let fe = v.force_n.unwrap_or(f64::NAN) + shift.map_or(0.0, |c| c.force_n);
                    row.force_n[1] = fe;
                    if !row.force_excluded {
                        let sigma = f.force_std_n.hypot(s.model_sigma.force_n);
                        let at = Residual {
                            n,
                            t,
                            output: Recorded::Force,
                            sigma,
                        };
                        acc.push(at, fe - f.force_n, &d, &fac, |o| o.force_n.unwrap_or(0.0));
                    }
                }
                None => errors.push(format!("force N = {n}, T = {t}, {p} bar")),
            }
        }
        rows.push(row);
    }
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
    let (r, j, what) = acc.finish(s.unknowns.len());
    Evaluation {
        r,
        j,
        what,
        rows,
        error,
    }
}

/// The whitened residuals, their Jacobian rows and what each one is, as they are found.
#[derive(Default)]
struct Accumulator {
    r: Vec<f64>,
    jac: Vec<Vec<f64>>,
    what: Vec<Residual>,
}

impl Accumulator {
    /// One residual `difference / σ` with its derivatives `f · d(output) / σ` by each
    /// unknown (`f` the unknown's design factor).
    fn push(
        &mut self,
        at: Residual,
        difference: f64,
        d: &[crate::fe::sensitivity::Outputs],
        fac: &[f64],
        output: impl Fn(&crate::fe::sensitivity::Outputs) -> f64,
    ) {
        self.r.push(difference / at.sigma);
        self.jac.push(
            d.iter()
                .zip(fac)
                .map(|(o, f)| f * output(o) / at.sigma)
                .collect(),
        );
        self.what.push(at);
    }

    fn finish(self, k: usize) -> (DVector<f64>, DMatrix<f64>, Vec<Residual>) {
        let m = self.r.len();
        let jac = self.jac;
        let j = DMatrix::from_fn(m, k, |i, c| jac[i][c]);
        (DVector::from_vec(self.r), j, self.what)
    }
}

/// Whether the settings leave the row of `recording` at `(n, t, p)` out of the fit.
fn excluded(s: &JointSettings, n: usize, t: f64, p: f64, recording: Recording) -> bool {
    let c = Config::of(n, t, p);
    s.exclude.iter().any(|e| e.applies(&c, recording))
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

/// Mean tip BE and mean |force error| over the rows fitted (the excluded ones left out).
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn summary_of(rows: &[JointRow]) -> (f64, f64) {
    let be: Vec<f64> = rows
        .iter()
        .filter(|r| !r.tip_excluded)
        .map(|r| r.be_mm)
        .collect();
    let fe: Vec<f64> = rows
        .iter()
        .filter(|r| !r.force_excluded)
        .map(|r| (r.force_n[1] - r.force_n[0]).abs())
        .filter(|v| v.is_finite())
        .collect();
    (mean(&be), mean(&fe))
}

pub(super) fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}
