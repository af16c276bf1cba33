//! The identification itself: the bounded Levenberg–Marquardt driven by FE sweeps from the
//! start, and the report of its optimum (estimates, correlations, held-out prediction).

use super::evaluation::{evaluate, mean, summary_of, Evaluation};
use super::held_out::held_out;
use super::lm::bounded_lm;
use super::report::{JointEstimate, JointReport, JointSweep};
use super::settings::{JointSettings, JointStop, MIN_GAIN_CHI2};
use super::unknown::{bounds, JointPoint, Unknown};
use crate::calibrate::objective::Recordings;
use crate::calibrate::CalibrateError;
use crate::fe::campaign::WarmPool;

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
    check_correction(s, rec)?;
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
    let x0: Vec<f64> = s.unknowns.iter().map(|&u| x.get(u)).collect();
    let point_at = |v: &[f64]| -> Result<JointPoint, CalibrateError> {
        let mut p = x.clone();
        for (&u, &vi) in s.unknowns.iter().zip(v) {
            p.set(u, vi)?;
        }
        Ok(p)
    };
    let mut evaluations: Vec<(JointPoint, Result<Evaluation, String>)> = Vec::new();
    let pool = s.warm_start.then(WarmPool::new);
    let trace = bounded_lm(
        &x0,
        &bnds,
        s.lambda0,
        s.max_step,
        s.max_sweeps,
        MIN_GAIN_CHI2,
        |v| {
            let p = point_at(v)?;
            let k = evaluations.len() + 1;
            let e = evaluate(s, rec, &p, k, pool.as_ref(), &|d, n| progress(k, d, n));
            if k == 1 {
                if let Ok(e) = &e {
                    if !e.error.is_empty() {
                        return Err(CalibrateError::input(
                            "start",
                            "the FE model",
                            &format!("a start the FE reaches ({})", e.error),
                        ));
                    }
                }
            }
            let out = match &e {
                Ok(e) if e.error.is_empty() => Some((e.r.clone(), e.j.clone())),
                _ => None,
            };
            evaluations.push((p, e.map_err(|e| e.to_string())));
            Ok(out)
        },
    )?;
    let mut sweeps = Vec::new();
    for (step, (p, e)) in trace.steps.iter().zip(&evaluations) {
        let (be, fe, error) = match e {
            Ok(e) => {
                let (be, fe) = summary_of(&e.rows);
                (be, fe, e.error.clone())
            }
            Err(why) => (f64::NAN, f64::NAN, why.clone()),
        };
        sweeps.push(JointSweep {
            point: p.clone(),
            chi2: step.chi2,
            mean_be_mm: be,
            mean_abs_force_error_n: fe,
            accepted: step.accepted,
            lambda: step.lambda,
            predicted_chi2: step.predicted_chi2,
            error,
        });
    }
    let best = trace.best;
    let (xb, eb) = evaluations.swap_remove(best);
    let cur = eb.map_err(|why| CalibrateError::input("optimum", "the FE model", &why))?;
    Ok(report(s, &bnds, xb, cur, sweeps, trace.stop))
}

/// Every recorded configuration has its mesh correction, if there is one.
fn check_correction(s: &JointSettings, rec: &Recordings) -> Result<(), CalibrateError> {
    let Some(c) = &s.correction else {
        return Ok(());
    };
    for b in &rec.bending {
        if c.at(b.n_bellows, b.wall_thickness_mm, b.pressure_bar)
            .is_none()
        {
            return Err(CalibrateError::input(
                "mesh correction",
                &c.fine,
                &format!(
                    "a row for every recorded configuration (N = {}, T = {}, P = {} has none)",
                    b.n_bellows, b.wall_thickness_mm, b.pressure_bar
                ),
            ));
        }
    }
    Ok(())
}

/// The report of the optimum `x` with its evaluation `cur`.
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
    let x_opt: Vec<f64> = s.unknowns.iter().map(|&u| x.get(u)).collect();
    let held_out = held_out(&cur, &x_opt, bnds, 3);
    let rows = cur.rows;
    let (mean_be_mm, mean_abs_force_error_n) = summary_of(&rows);
    let all: Vec<f64> = rows.iter().map(|r| r.be_mm).collect();
    let nine_all: Vec<f64> = rows
        .iter()
        .filter(|r| r.paper_nine)
        .map(|r| r.be_mm)
        .collect();
    let (mean_be_all, mean_be_nine_all) = (mean(&all), mean(&nine_all));
    let nine: Vec<f64> = rows
        .iter()
        .filter(|r| r.paper_nine && !r.tip_excluded)
        .map(|r| r.be_mm)
        .collect();
    let da: Vec<f64> = rows
        .iter()
        .filter(|r| !r.tip_excluded)
        .map(|r| (r.angle_deg[1] - r.angle_deg[0]).powi(2))
        .collect();
    let df: Vec<f64> = rows
        .iter()
        .filter(|r| !r.force_excluded)
        .map(|r| r.force_n[1] - r.force_n[0])
        .filter(|v| v.is_finite())
        .collect();
    JointReport {
        mesh: s.mesh.level.name().to_string(),
        model_sigma: s.model_sigma,
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
        held_out,
        excluded: s.exclude.clone(),
        mean_be_all_mm: (!s.exclude.is_empty()).then_some(mean_be_all),
        mean_be_paper_nine_all_mm: (!s.exclude.is_empty()).then_some(mean_be_nine_all),
        correction: s.correction.clone(),
    }
}
