//! What the recordings determine: standard errors, correlations, eigen-directions, profile
//! likelihoods, and which extra measurement would determine what is left.
//!
//! ## Linearised statistics
//!
//! At the optimum `θ̂` with whitened residuals `r` (see [`super::objective`]) and
//! `J = ∂r/∂θ` in the reported coordinates (`μ0` in MPa, `s`, `α₁`, `α₂` for the training
//! domain; the Ogden parameters for a raw box), the Fisher information is `F = JᵀJ` and
//!
//! ```text
//!   Cov θ̂ = ŝ² F⁻¹,     ŝ² = max(1, χ²_min / (m − p))
//! ```
//!
//! `ŝ²` inflates the covariance when the model does not fit to within the noise (a
//! structural misfit that the noise model does not describe): the usual
//! "residual-variance" scaling. Correlations are `Cᵢⱼ/√(CᵢᵢCⱼⱼ)`. The eigen-decomposition of
//! `F` in unit-box coordinates (each coordinate scaled by its range, so that directions are
//! comparable) gives the combinations the data determine (large eigenvalue) and those it
//! does not (the standard deviation along eigenvector `k` is `ŝ/√λ_k`, in fractions of the box).
//!
//! ## Profiles
//!
//! For each coordinate `i`, `χ²_p(v) = min over the others of χ²(θ | θᵢ = v)` on a grid across
//! the box (each point from two starts: the previous point and the optimum).
//! The 95 % interval is where `χ²_p(v) − χ²_min ≤ χ²₄(0.95) ŝ² = 9.49 ŝ²`: the projection of the
//! joint confidence region of the four parameters (statrs quantile). The pointwise threshold
//! `χ²₁(0.95) = 3.84` assumes the other parameters are well determined and interior; with
//! weakly determined ones on the box it under-covers (measured on the synthetic FE recordings of
//! `tests/calibrate/calibrate.rs`: 23 of 30 noise seeds covered the true μ0 at 95 %). The projection is
//! conservative for a single parameter, which is the safe side for a report that says what
//! the data determine (`IdentifySettings::simultaneous = false` gives the pointwise
//! interval). A side on which the profile never
//! reaches the threshold inside the box is *open*: the data do not bound the parameter there,
//! only the training domain does. A parameter is **determined** when both sides close,
//! **bounded on one side** when one side is open, **not determined** when both are open.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::objective::{Evaluator, ObservationSet, Output};
use super::optimise::{local_fit, LmSettings};
use super::params::ParamSpace;
use super::CalibrateError;

/// Whether the data determine a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Determinacy {
    /// The profile interval closes on both sides inside the box.
    Determined,
    /// Open at the lower side (only the box bounds it there).
    OpenBelow,
    /// Open at the upper side.
    OpenAbove,
    /// Open on both sides: the data say nothing about it within the box.
    NotDetermined,
}

impl Determinacy {
    /// Plain words.
    pub fn describe(self) -> &'static str {
        match self {
            Determinacy::Determined => "determined",
            Determinacy::OpenBelow => "bounded above only (the training domain bounds it below)",
            Determinacy::OpenAbove => "bounded below only (the training domain bounds it above)",
            Determinacy::NotDetermined => "not determined within the training domain",
        }
    }
}

/// One profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Coordinate name.
    pub name: String,
    /// Grid values (physical units).
    pub values: Vec<f64>,
    /// `χ²_p(v) − χ²_min` at each grid value.
    pub delta_chi2: Vec<f64>,
    /// Threshold `χ²_k(level) ŝ²` (k = 4, or 1 for pointwise intervals).
    pub threshold: f64,
    /// The optimum's value.
    pub optimum: f64,
    /// 95 % profile interval (clipped to the box on an open side).
    pub interval: [f64; 2],
    /// The box.
    pub range: [f64; 2],
    /// Classification.
    pub determinacy: Determinacy,
}

/// One eigen-direction of the information.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Direction {
    /// Eigenvalue of `F` in unit-box coordinates.
    pub eigenvalue: f64,
    /// Standard deviation along the direction, as a fraction of the box (`ŝ/√λ`).
    pub std_fraction: f64,
    /// Unit eigenvector (unit-box coordinates), by coordinate name.
    pub vector: Vec<(String, f64)>,
}

/// Which extra measurement would sharpen the estimate most.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtraMeasurement {
    /// What would be measured.
    pub measurement: String,
    /// Standard error of each coordinate with it added (linearised, same `ŝ`).
    pub std_errors: Vec<f64>,
    /// Ratio to today's standard errors.
    pub ratio: Vec<f64>,
}

/// Identifiability of a fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Identifiability {
    /// Coordinate names.
    pub names: Vec<String>,
    /// Estimates (physical units).
    pub estimate: Vec<f64>,
    /// Linearised standard errors (`ŝ`-scaled; infinite along a null direction).
    pub std_errors: Vec<f64>,
    /// Correlation matrix.
    pub correlation: Vec<Vec<f64>>,
    /// `ŝ²`.
    pub variance_scale: f64,
    /// Observations and free parameters.
    pub dof: usize,
    /// Eigen-directions, strongest first.
    pub directions: Vec<Direction>,
    /// Profiles.
    pub profiles: Vec<Profile>,
    /// Standard errors of `μ₁, α₁, μ₂, α₂` (delta method).
    pub ogden_std_errors: [f64; 4],
    /// Candidate extra measurements, best first for the least determined coordinate.
    pub extra_measurements: Vec<ExtraMeasurement>,
}

impl Identifiability {
    /// Names of the coordinates that are not determined on at least one side.
    pub fn weak(&self) -> Vec<&str> {
        self.profiles
            .iter()
            .filter(|p| p.determinacy != Determinacy::Determined)
            .map(|p| p.name.as_str())
            .collect()
    }
}

/// `∂(physical coordinate)/∂u` for coordinate `i`.
fn dphys_du(space: &ParamSpace, u: &[f64; 4], i: usize) -> f64 {
    let h = 1e-7;
    // exact for the linear coordinates; μ0 = exp(·) is smooth, a central difference is exact
    // to ~1e-12 relative
    (space.physical(i, u[i] + h) - space.physical(i, u[i] - h)) / (2.0 * h)
}

/// Symmetric 4 × 4 eigen-decomposition (nalgebra), eigenvalues descending.
fn eigen(f: &[[f64; 4]; 4]) -> Vec<(f64, [f64; 4])> {
    let m = nalgebra::Matrix4::from_fn(|i, j| f[i][j]);
    let e = nalgebra::SymmetricEigen::new(m);
    let mut out: Vec<(f64, [f64; 4])> = (0..4)
        .map(|k| {
            let v = e.eigenvectors.column(k);
            // sign: largest component positive
            let big = (0..4)
                .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
                .unwrap_or(0);
            let sg = if v[big] < 0.0 { -1.0 } else { 1.0 };
            (e.eigenvalues[k], std::array::from_fn(|i| sg * v[i]))
        })
        .collect();
    out.sort_by(|a, b| b.0.total_cmp(&a.0));
    out
}

/// Pseudo-inverse of a symmetric 4 × 4 matrix (eigenvalues below `1e-12 λ_max` dropped,
/// their directions get infinite variance on the diagonal).
fn covariance(f: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let eig = eigen(f);
    let lmax = eig[0].0.max(1e-300);
    let mut c = [[0.0; 4]; 4];
    for (l, v) in &eig {
        if *l > 1e-12 * lmax {
            for i in 0..4 {
                for j in 0..4 {
                    c[i][j] += v[i] * v[j] / l;
                }
            }
        } else {
            for i in 0..4 {
                if v[i].abs() > 1e-8 {
                    c[i][i] = f64::INFINITY;
                }
            }
        }
    }
    c
}

fn information(j: &[[f64; 4]], scale: &[f64; 4]) -> [[f64; 4]; 4] {
    let mut f = [[0.0; 4]; 4];
    for row in j {
        for p in 0..4 {
            for q in 0..4 {
                f[p][q] += row[p] * row[q] / (scale[p] * scale[q]);
            }
        }
    }
    f
}

/// Settings of the identifiability analysis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct IdentifySettings {
    /// Profile grid points across the box (per coordinate).
    pub profile_points: usize,
    /// Confidence level of the profile intervals.
    pub level: f64,
    /// Intervals as projections of the joint confidence region (`Δχ² ≤ χ²₄(level)`, valid
    /// when the other parameters are weakly determined or on the box) instead of the
    /// pointwise `χ²₁(level)` threshold.
    pub simultaneous: bool,
}

impl Default for IdentifySettings {
    fn default() -> Self {
        IdentifySettings {
            profile_points: 24,
            level: 0.95,
            simultaneous: true,
        }
    }
}

/// The identifiability analysis at the optimum `u` of `ev` (χ² = `chi2_min`).
///
/// # Errors
/// A surrogate evaluation error, or a level outside (0, 1).
pub fn identify(
    ev: &Evaluator<'_>,
    u: &[f64; 4],
    chi2_min: f64,
    settings: &IdentifySettings,
    candidates: &[(String, ObservationSet)],
) -> Result<Identifiability, CalibrateError> {
    if !(settings.level > 0.0 && settings.level < 1.0) {
        return Err(CalibrateError::input(
            "confidence level",
            settings.level,
            "in (0, 1)",
        ));
    }
    let space = ev.space().clone();
    let names: Vec<String> = space.names().iter().map(|s| s.to_string()).collect();
    let m = ev.set().len();
    let mut e = ev.clone();
    let mut r = vec![0.0; m];
    let mut j = vec![[0.0; 4]; m];
    e.residuals(u, &mut r, Some(&mut j))?;
    let dof = m.saturating_sub(4).max(1);
    let s2 = (chi2_min / dof as f64).max(1.0);
    let dp: [f64; 4] = std::array::from_fn(|i| dphys_du(&space, u, i));
    // information in physical coordinates
    let f_phys = information(&j, &dp);
    let c = covariance(&f_phys);
    let std_errors: Vec<f64> = (0..4).map(|i| (s2 * c[i][i]).sqrt()).collect();
    let correlation: Vec<Vec<f64>> = (0..4)
        .map(|a| {
            (0..4)
                .map(|b| {
                    let v = c[a][b] / (c[a][a] * c[b][b]).sqrt();
                    if v.is_finite() {
                        v
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        })
        .collect();
    // directions in unit-box coordinates
    let f_unit = information(&j, &[1.0; 4]);
    let directions = eigen(&f_unit)
        .into_iter()
        .map(|(l, v)| Direction {
            eigenvalue: l,
            std_fraction: if l > 0.0 {
                (s2 / l).sqrt()
            } else {
                f64::INFINITY
            },
            vector: names.iter().cloned().zip(v).collect(),
        })
        .collect();
    // delta method for the Ogden parameters: C_raw = D C_u Dᵀ
    let c_unit = covariance(&f_unit);
    let d = space.ogden_jacobian(u);
    let ogden_std_errors = std::array::from_fn(|a| {
        let mut v = 0.0;
        for p in 0..4 {
            for q in 0..4 {
                let cpq = c_unit[p][q];
                if d[a][p] != 0.0 && d[a][q] != 0.0 {
                    v += d[a][p] * cpq * d[a][q];
                }
            }
        }
        (s2 * v).sqrt()
    });
    let dof_interval = if settings.simultaneous { 4.0 } else { 1.0 };
    let quantile = ChiSquared::new(dof_interval)
        .map_err(|e| CalibrateError::input("chi-squared", 1, &e.to_string()))?
        .inverse_cdf(settings.level);
    let threshold = quantile * s2;
    let profiles = (0..4)
        .into_par_iter()
        .map(|i| profile(ev, u, chi2_min, i, settings.profile_points, threshold))
        .collect::<Result<Vec<_>, _>>()?;
    let extra_measurements = extra(&e, u, &f_phys, &dp, s2, &std_errors, candidates)?;
    Ok(Identifiability {
        estimate: (0..4).map(|i| space.physical(i, u[i])).collect(),
        names,
        std_errors,
        correlation,
        variance_scale: s2,
        dof,
        directions,
        profiles,
        ogden_std_errors,
        extra_measurements,
    })
}

fn profile(
    ev: &Evaluator<'_>,
    u: &[f64; 4],
    chi2_min: f64,
    i: usize,
    points: usize,
    threshold: f64,
) -> Result<Profile, CalibrateError> {
    let space = ev.space().clone();
    let mut e = ev.clone();
    let mut fixed = [false; 4];
    fixed[i] = true;
    let local = LmSettings {
        max_iterations: 60,
        ..LmSettings::default()
    };
    let n = points.max(4);
    let grid: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    let mut below: Vec<(f64, f64)> = vec![(u[i], 0.0)];
    let mut above: Vec<(f64, f64)> = Vec::new();
    // march outwards from the optimum, warm-starting each point from the previous one
    for (side, out) in [(-1.0, &mut below), (1.0, &mut above)] {
        let mut prev = *u;
        let vals: Vec<f64> = if side < 0.0 {
            grid.iter()
                .rev()
                .copied()
                .filter(|&v| v < u[i] - 1e-9)
                .collect()
        } else {
            grid.iter().copied().filter(|&v| v > u[i] + 1e-9).collect()
        };
        for v in vals {
            // the other coordinates are often weakly determined with several local minima:
            // warm start from the previous grid point and from the optimum's values; the
            // lower end point is the profile's value
            let mut best: Option<super::optimise::LocalFit> = None;
            for base in [prev, *u] {
                let mut start = base;
                start[i] = v;
                let fit = local_fit(&mut e, start, fixed, &local)?;
                if best.as_ref().is_none_or(|b| fit.chi2 < b.chi2) {
                    best = Some(fit);
                }
            }
            let Some(fit) = best else { break };
            // a value below the global minimum means a better minimum elsewhere, kept as found
            out.push((v, fit.chi2 - chi2_min));
            prev = fit.u;
            if fit.chi2 - chi2_min > 2.0 * threshold {
                break;
            }
        }
    }
    let lower = crossing(&below, threshold);
    let upper = crossing(
        &std::iter::once((u[i], 0.0))
            .chain(above.iter().copied())
            .collect::<Vec<_>>(),
        threshold,
    );
    let mut pts: Vec<(f64, f64)> = below.into_iter().chain(above).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let determinacy = match (lower, upper) {
        (Some(_), Some(_)) => Determinacy::Determined,
        (None, Some(_)) => Determinacy::OpenBelow,
        (Some(_), None) => Determinacy::OpenAbove,
        (None, None) => Determinacy::NotDetermined,
    };
    let lo_u = lower.unwrap_or(0.0);
    let hi_u = upper.unwrap_or(1.0);
    Ok(Profile {
        name: space.names()[i].to_string(),
        values: pts.iter().map(|p| space.physical(i, p.0)).collect(),
        delta_chi2: pts.iter().map(|p| p.1).collect(),
        threshold,
        optimum: space.physical(i, u[i]),
        interval: [space.physical(i, lo_u), space.physical(i, hi_u)],
        range: [space.physical(i, 0.0), space.physical(i, 1.0)],
        determinacy,
    })
}

/// First crossing of `threshold` along `side`, which walks from the optimum outwards
/// (linear interpolation between grid points); `None` when it never crosses.
fn crossing(side: &[(f64, f64)], threshold: f64) -> Option<f64> {
    let mut prev = *side.first()?;
    for &(v, d) in &side[1..] {
        if d > threshold {
            let p = prev.1.max(0.0);
            let t = (threshold - p) / (d - p);
            return Some(prev.0 + t * (v - prev.0));
        }
        prev = (v, d);
    }
    None
}

fn extra(
    ev: &Evaluator<'_>,
    u: &[f64; 4],
    f_phys: &[[f64; 4]; 4],
    dp: &[f64; 4],
    s2: f64,
    now: &[f64],
    candidates: &[(String, ObservationSet)],
) -> Result<Vec<ExtraMeasurement>, CalibrateError> {
    let mut out = Vec::new();
    for (name, set) in candidates {
        let mut e = Evaluator::new(ev.model(), set, ev.space().clone());
        let mut r = vec![0.0; set.len()];
        let mut j = vec![[0.0; 4]; set.len()];
        e.residuals(u, &mut r, Some(&mut j))?;
        let add = information(&j, dp);
        let mut f = *f_phys;
        for p in 0..4 {
            for q in 0..4 {
                f[p][q] += add[p][q];
            }
        }
        let c = covariance(&f);
        let se: Vec<f64> = (0..4).map(|i| (s2 * c[i][i]).sqrt()).collect();
        let ratio = se.iter().zip(now).map(|(a, b)| a / b).collect();
        out.push(ExtraMeasurement {
            measurement: name.clone(),
            std_errors: se,
            ratio,
        });
    }
    // best first for the coordinate with the largest relative standard error today
    let worst = (0..4)
        .max_by(|&a, &b| {
            let ra = now[a] / ev.space().physical(a, 0.5).abs().max(1e-12);
            let rb = now[b] / ev.space().physical(b, 0.5).abs().max(1e-12);
            ra.total_cmp(&rb)
        })
        .unwrap_or(0);
    out.sort_by(|a, b| a.ratio[worst].total_cmp(&b.ratio[worst]));
    Ok(out)
}

/// The outputs an extra measurement would add (used to describe candidates).
pub fn describe_outputs(set: &ObservationSet) -> Vec<Output> {
    let mut v: Vec<Output> = set.obs.iter().map(|o| o.output).collect();
    v.sort();
    v.dedup();
    v
}
