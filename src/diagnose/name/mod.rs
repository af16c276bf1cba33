//! Name: which effect of the library explains the located residual, once the material has
//! taken what it can.
//!
//! For every cell `i` of the residual table ([`locate`](mod@super::locate)) and every parameter `j`, the
//! FE sensitivities of the sweep at (about) the calibrated material give the signature
//!
//! ```text
//!   S_ij = (∂ŷᵢ/∂θⱼ) / σᵢ          (the cell's change per unit of θⱼ, in its own σ)
//! ```
//!
//! The material's four columns `S_m` span what a material re-fit absorbs. With `Q` an
//! orthonormal basis of that span (thin SVD, directions below 10⁻¹⁰ of the largest dropped)
//! and `P⊥ = I − QQᵀ`, the residual after a linearised material re-fit on every cell is
//! `r = P⊥ z`, and an effect's signature seen past the material is `s̃ = P⊥ s`. Adding one
//! effect to the re-fit (nested, one more parameter):
//!
//! ```text
//!   θ̂ = −s̃ᵀr / s̃ᵀs̃,     Δχ² = (s̃ᵀr)² / s̃ᵀs̃,     χ²₁ = rᵀr − Δχ²
//!   F = Δχ² / (χ²₁ / (n − 5)) ~ F(1, n − 5),     se(θ̂) = √(χ²₁ / (n − 5)) / |s̃|
//! ```
//!
//! The scale is estimated from what the effect leaves (the recordings' σ is too small for a
//! model that misses them by several σ, so a test against it would call every candidate
//! significant). The candidates' p-values are corrected together by Holm's step-down
//! procedure at level `α`; `ΔAIC = 2 − Δχ²/ŝ²` and `ΔBIC = ln n − Δχ²/ŝ²` (`ŝ²` the
//! material-only scale) rank them too. An effect whose signature the material absorbs
//! (`|s̃| ≤ 10⁻³ |s|`) or that moves nothing these recordings hold (a force-rig effect without
//! force recordings) is listed as not testable, with the reason.
//!
//! With the covariance `Γ̃` of the diagnosing model's own error over the cells
//! ([`super::approx_error`], in the cells' σ), the residual, the material's columns and
//! every signature are first multiplied by `L⁻¹`, `LLᵀ = I + Γ̃` (generalised least
//! squares): what varies with the model's own error between materials weighs less, and
//! every quantity above (`χ²`, `θ̂`, `F`) is that of the weighted fit.
//!
//! Two candidates whose projected signatures are nearly collinear (`|cos| ≥ 0.95`) explain
//! the residual the same way on these recordings and are reported as indistinguishable,
//! with the one output the sweep computes but the recordings lack (markers, force, other
//! pressures and designs, [`super::measurements`]) that would separate them most by the
//! T-optimality criterion, the material refitted ([`super::discrimination`]; the plan of up
//! to three such measurements for the whole tie set is [`super::measure_design`]). So is a pair of the first (or the
//! named) candidate with another that it does not beat significantly: when the fit with
//! both is not significantly better than the fit with the other alone (F test, 1 and
//! `n − 6` degrees of freedom, at the level α), or when neither of the two non-nested fits
//! is significantly better than the other (their likelihood ratio, as in Vuong's test,
//! two-sided at α), the recordings do
//! not prefer the first one, however the ranking ordered them. The verdict names the best
//! significant candidate whose size lies in the library's plausible range; a significant one
//! that needs an implausible size (a negative compliance, a wall 0.8 mm thinner than printed)
//! is reported, not named. When no candidate is significant the verdict says so and names
//! nothing.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, FisherSnedecor, Normal};

use super::approx_error::ErrorSpread;
use super::cells::Cell;
use super::discrimination::{orthonormal, Discrimination};
use super::measurements::{self, Measurement};
use super::mesh_error::{ErrorDirection, MODEL_ERROR_UNIT, PLAUSIBLE_MODEL_ERROR};
use super::signature::{cell_spike, derivative_of, sensitivity_step, LocalMaterial};
use super::DiagnoseError;
use crate::calibrate::baseline::SweepSensitivities;
use crate::fe::sensitivity::{OgdenParameter, Parameter};

/// Settings of [`name`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NameSettings {
    /// Family-wise significance level of the candidates' tests (Holm).
    pub alpha: f64,
    /// `|cos|` between two projected signatures above which the two are indistinguishable.
    pub collinear: f64,
    /// Errors of the diagnosing model itself (its mesh error, [`super::mesh_error`]),
    /// tested beside the effects: when one explains the residual best, the verdict says so
    /// and names no physics.
    #[serde(default)]
    pub model_errors: Vec<ErrorDirection>,
    /// The covariance of the diagnosing model's own error over the cells
    /// ([`super::approx_error`]): the residual and every signature are weighed by
    /// `(I + Γ̃)^(−1/2)` (a Cholesky factor) before the tests. None: the recordings' σ alone.
    #[serde(default)]
    pub error_spread: Option<ErrorSpread>,
}

impl Default for NameSettings {
    fn default() -> Self {
        Self {
            alpha: 0.05,
            collinear: 0.95,
            model_errors: Vec::new(),
            error_spread: None,
        }
    }
}

/// One candidate effect, tested.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// The effect's name.
    pub effect: String,
    /// Its unit.
    pub unit: String,
    /// Whether it is an error of the diagnosing model itself (its mesh), not physics.
    #[serde(default)]
    pub model_error: bool,
    /// `|s|`: how strongly the recordings see it (σ per unit).
    pub signature_norm: f64,
    /// Share of `|s|²` the material absorbs.
    pub absorbed_by_material: f64,
    /// Its estimated size `θ̂` (unit of the effect, from its neutral value).
    pub estimate: f64,
    /// Standard error of `θ̂`.
    pub std_error: f64,
    /// Whether `θ̂` lies in the library's plausible range.
    pub plausible: bool,
    /// `Δχ²` of adding it to the material re-fit.
    pub delta_chi2: f64,
    /// `Δχ²` over the material-only `χ²`.
    pub explained: f64,
    /// The F statistic.
    pub f: f64,
    /// Its p-value.
    pub p_value: f64,
    /// Whether it is significant after Holm's correction.
    pub significant: bool,
    /// `ΔAIC` against the material-only re-fit (negative: better).
    pub delta_aic: f64,
    /// `ΔBIC` against the material-only re-fit.
    pub delta_bic: f64,
    /// `|θ̂| maxᵢ |s̃ᵢ|`: the largest change its estimated size makes to one recorded number
    /// past what the material can mimic, in that number's σ.
    #[serde(default)]
    pub max_move_sigma: f64,
}

/// Two candidates the recordings cannot tell apart.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Indistinguishable {
    /// First effect.
    pub a: String,
    /// Second effect.
    pub b: String,
    /// `cos` between their projected signatures.
    pub cosine: f64,
    /// For a pair with the first or the named candidate: the p-value of the better one's
    /// `Δχ²` beyond the other's (F test of the fit with both against the fit with the other
    /// alone). Above the level: the recordings do not prefer it, so the two cannot be told
    /// apart even when their signatures are not collinear.
    #[serde(default)]
    pub p_separation: Option<f64>,
    /// For the same pairs: the z of the likelihood ratio of the two non-nested one-effect
    /// fits (positive: `a` fits better; see the module docs). Within the two-sided normal
    /// quantile of the level: neither fits significantly better.
    #[serde(default)]
    pub vuong_z: Option<f64>,
    /// Where their two explanations differ most among outputs the recordings lack.
    pub separated_by: Option<String>,
}

impl Indistinguishable {
    /// Why the two cannot be told apart, in words.
    pub fn why(&self) -> String {
        match (self.p_separation, self.vuong_z) {
            (Some(p), Some(z)) => format!(
                "cos {:.3}; the better one beyond the other: p = {p:.2}; likelihood-ratio z = {z:+.2}",
                self.cosine
            ),
            _ => format!("cos {:.3}", self.cosine),
        }
    }
}

/// An effect that could not be tested, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Untestable {
    /// The effect.
    pub effect: String,
    /// Why.
    pub reason: String,
}

/// What the Name stage found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Naming {
    /// The material of the nonlinear re-fit on every used cell ([`name_refitted`]; none:
    /// the re-fit was linearised with the sweep's material sensitivities).
    #[serde(default)]
    pub refitted_material: Option<crate::calibrate::OgdenSet>,
    /// Cells used (those with sensitivities).
    pub n_cells: usize,
    /// Cells without sensitivities in the sweep, in words.
    pub unmatched: Vec<String>,
    /// Used cells whose FE sensitivities hold a derivative spike (more than 10 times the
    /// same derivative at the ramp's other pressures, as at a contact switch): their
    /// linearisation is doubtful, in words.
    #[serde(default)]
    pub spikes: Vec<String>,
    /// `χ²` of the used cells at the calibrated set.
    pub chi2: f64,
    /// `χ²` after the material re-fit on every used cell.
    pub chi2_material: f64,
    /// The candidates, largest `Δχ²` first.
    pub candidates: Vec<Candidate>,
    /// Pairs the recordings cannot separate.
    pub indistinguishable: Vec<Indistinguishable>,
    /// Effects not testable on these recordings.
    pub untestable: Vec<Untestable>,
    /// The verdict in words.
    pub verdict: String,
}

impl Naming {
    /// The best significant candidate at a plausible size (an effect or an error of the
    /// model itself).
    pub fn best(&self) -> Option<&Candidate> {
        self.candidates
            .iter()
            .find(|c| c.significant && c.plausible)
    }

    /// The named effect: the best significant candidate at a plausible size, when it is
    /// physics (none when the verdict names nothing or the model's own error explains the
    /// residual best).
    pub fn named(&self) -> Option<&Candidate> {
        self.best().filter(|c| !c.model_error)
    }

    /// The model's own error, when it explains the residual best.
    pub fn model_error(&self) -> Option<&Candidate> {
        self.best().filter(|c| c.model_error)
    }
}

/// Every parameter's derivative of `c`'s output in the sweep, σ-scaled.
pub(crate) fn derivs_of(sens: &SweepSensitivities, c: &Cell) -> Option<Vec<f64>> {
    sensitivity_step(sens, c).and_then(|(se, i)| {
        se.steps[i]
            .derivatives
            .iter()
            .map(|d| derivative_of(d, c.output).map(|v| v / c.sigma))
            .collect::<Option<Vec<f64>>>()
    })
}

pub use super::sweep::MIN_NAME_CELLS;

/// Names the effect behind the residual of `cells` (see the [module docs](self)).
///
/// # Errors
/// [`DiagnoseError::Input`] if the sweep lacks the material parameters (they are projected
/// out) or no cell has sensitivities, or a bad setting.
pub fn name(
    cells: &[Cell],
    sens: &SweepSensitivities,
    s: &NameSettings,
) -> Result<Naming, DiagnoseError> {
    name_inner(cells, sens, None, s)
}

/// [`name`] after a nonlinear material re-fit through the surrogate: the material alone is
/// refitted from `start` on every cell with sensitivities (bounded Levenberg–Marquardt, as
/// [`super::refit`] does), and the residual and the material directions projected out are
/// those of that fit, the directions from the surrogate's analytic Jacobian there. The
/// calibration's objective may leave outputs out (the force under `tip`), and a material
/// the recordings hardly determine may sit far from the sweep's: the linearised re-fit of
/// [`name`] around the calibrated set is then poor, this one is exact for the material.
///
/// # Errors
/// As [`name`], and a surrogate error.
pub fn name_refitted(
    cells: &[Cell],
    sens: &SweepSensitivities,
    model: &crate::rom::Surrogate,
    start: &crate::calibrate::OgdenSet,
    s: &NameSettings,
) -> Result<Naming, DiagnoseError> {
    let (local, material) = super::refit::material_refit(cells, sens, model, start)?;
    let mut n = name_inner(cells, sens, Some(&local), s)?;
    n.refitted_material = Some(material);
    Ok(n)
}

/// A column tested against the residual: an effect of the sweep or an error of the model.
struct Tested {
    name: String,
    unit: String,
    neutral: f64,
    range: (f64, f64),
    /// `S_j` (σ-scaled), per used cell.
    column: DVector<f64>,
    /// The sweep's parameter (none: a model error).
    parameter: Option<Parameter>,
}

fn name_inner(
    cells: &[Cell],
    sens: &SweepSensitivities,
    local: Option<&LocalMaterial>,
    s: &NameSettings,
) -> Result<Naming, DiagnoseError> {
    if !(s.alpha > 0.0 && s.alpha < 1.0) {
        return Err(DiagnoseError::input("alpha", s.alpha, "a level in (0, 1)"));
    }
    if !(s.collinear > 0.0 && s.collinear < 1.0) {
        return Err(DiagnoseError::input(
            "collinear",
            s.collinear,
            "a cosine in (0, 1)",
        ));
    }
    let params: Vec<Parameter> = sens
        .designs
        .first()
        .map(|d| {
            d.sensitivities
                .parameters
                .iter()
                .map(|p| p.parameter)
                .collect()
        })
        .unwrap_or_default();
    let material: Vec<usize> = OgdenParameter::ALL
        .iter()
        .filter_map(|k| params.iter().position(|p| *p == Parameter::Material(*k)))
        .collect();
    if material.len() != 4 && local.is_none() {
        return Err(DiagnoseError::input(
            "sensitivities",
            "without mu1, alpha1, mu2, alpha2",
            "a sweep with the four material parameters (validate --sensitivities all)",
        ));
    }
    // rows: cells with sensitivities; columns: every parameter (σ-scaled)
    let mut rows: Vec<(&Cell, Vec<f64>)> = Vec::new();
    let mut row_cell: Vec<usize> = Vec::new();
    let mut spikes: Vec<String> = Vec::new();
    let mut refitted: Vec<(f64, [f64; 4])> = Vec::new();
    let mut unmatched = Vec::new();
    for (ci, c) in cells.iter().enumerate() {
        let derivs = match local {
            Some(l) => match l.get(ci).copied().flatten() {
                Some(v) => {
                    refitted.push(v);
                    derivs_of(sens, c)
                }
                None => None,
            },
            None => derivs_of(sens, c),
        };
        match derivs {
            Some(d) => {
                if let Some((p, ratio)) = cell_spike(sens, c) {
                    spikes.push(format!(
                        "N = {}, T = {} mm, {} bar, {}: its FE derivative by {p} is {ratio:.0} \
                         times its largest at the ramp's other pressures",
                        c.n_bellows,
                        c.wall_thickness_mm,
                        c.pressure_bar,
                        c.output.name()
                    ));
                }
                rows.push((c, d));
                row_cell.push(ci);
            }
            None => {
                if local.is_some() && refitted.len() > rows.len() {
                    refitted.pop();
                }
                unmatched.push(format!(
                    "N = {}, T = {} mm, {} bar, {}",
                    c.n_bellows,
                    c.wall_thickness_mm,
                    c.pressure_bar,
                    c.output.name(),
                ))
            }
        }
    }
    let n = rows.len();
    if n < MIN_NAME_CELLS {
        return Err(DiagnoseError::input(
            "cells with sensitivities",
            n,
            &format!(
                "at least {MIN_NAME_CELLS} (the sweep must cover the recorded designs and \
                 pressures: {})",
                super::sweep::COMPUTE_MISSING
            ),
        ));
    }
    let whiten = whitening(s.error_spread.as_ref(), cells, &rows, &row_cell)?;
    let w = |v: DVector<f64>| -> DVector<f64> {
        match &whiten {
            Some(l) => l
                .solve_lower_triangular(&v)
                .expect("a Cholesky factor of I + DDᵀ is regular"),
            None => v,
        }
    };
    let z = w(DVector::from_iterator(
        n,
        rows.iter().map(|(c, _)| c.standardised),
    ));
    let column = |j: usize| DVector::from_iterator(n, rows.iter().map(|(_, d)| d[j]));
    let (sm, z_fit) = match local {
        Some(_) => (
            DMatrix::from_fn(n, 4, |i, k| refitted[i].1[k]),
            w(DVector::from_iterator(n, refitted.iter().map(|v| v.0))),
        ),
        None => (
            DMatrix::from_columns(&material.iter().map(|&j| column(j)).collect::<Vec<_>>()),
            z.clone(),
        ),
    };
    let sm = match &whiten {
        Some(l) => l
            .solve_lower_triangular(&sm)
            .expect("a Cholesky factor of I + DDᵀ is regular"),
        None => sm,
    };
    let q = orthonormal(&sm);
    let project = |v: &DVector<f64>| -> DVector<f64> { v - &q * (q.transpose() * v) };
    let r = project(&z_fit);
    let chi2 = z.norm_squared();
    let chi2_material = r.norm_squared();
    let dof = n as f64 - 5.0;
    let scale0 = chi2_material / (n as f64 - 4.0);
    let mut candidates = Vec::new();
    let mut untestable = Vec::new();
    let mut projected: Vec<(String, f64, DVector<f64>, Option<Parameter>)> = Vec::new();
    for nu in &s.model_errors {
        if nu.per_cell.len() != cells.len() {
            return Err(DiagnoseError::input(
                "model error",
                format!("{} ({} values)", nu.name, nu.per_cell.len()),
                &format!("one value per cell of the table ({})", cells.len()),
            ));
        }
    }
    // the effects of the sweep, then the model's own errors
    let mut tested: Vec<Tested> = Vec::new();
    for (j, p) in params.iter().enumerate() {
        let Parameter::Effect(e) = *p else { continue };
        let info = e.info();
        tested.push(Tested {
            name: e.name().into(),
            unit: info.unit.into(),
            neutral: info.neutral,
            range: info.range,
            column: column(j),
            parameter: Some(*p),
        });
    }
    for nu in &s.model_errors {
        tested.push(Tested {
            name: nu.name.clone(),
            unit: MODEL_ERROR_UNIT.into(),
            neutral: 0.0,
            range: PLAUSIBLE_MODEL_ERROR,
            column: DVector::from_iterator(
                n,
                row_cell
                    .iter()
                    .zip(&rows)
                    .map(|(&ci, (c, _))| nu.at(ci) / c.sigma),
            ),
            parameter: None,
        });
    }
    for t in tested {
        let sj = w(t.column);
        let norm = sj.norm();
        if norm == 0.0 {
            untestable.push(Untestable {
                effect: t.name,
                reason: "moves nothing these recordings hold".into(),
            });
            continue;
        }
        let st = project(&sj);
        let kept = st.norm();
        if kept <= 1e-3 * norm {
            untestable.push(Untestable {
                effect: t.name,
                reason: format!(
                    "the material absorbs its signature ({:.4} % left)",
                    100.0 * kept / norm
                ),
            });
            continue;
        }
        let proj = st.dot(&r);
        let delta = proj * proj / (kept * kept);
        let chi2_1 = (chi2_material - delta).max(0.0);
        let scale = chi2_1 / dof;
        let f = if scale > 0.0 {
            delta / scale
        } else {
            f64::INFINITY
        };
        let p_value = FisherSnedecor::new(1.0, dof)
            .map(|d| 1.0 - d.cdf(f))
            .unwrap_or(f64::NAN);
        let estimate = -proj / (kept * kept);
        let size = t.neutral + estimate;
        candidates.push(Candidate {
            effect: t.name.clone(),
            unit: t.unit,
            model_error: t.parameter.is_none(),
            signature_norm: norm,
            absorbed_by_material: 1.0 - (kept / norm).powi(2),
            estimate,
            std_error: scale.sqrt() / kept,
            plausible: (t.range.0..=t.range.1).contains(&size),
            delta_chi2: delta,
            explained: delta / chi2_material.max(f64::MIN_POSITIVE),
            f,
            p_value,
            significant: false,
            delta_aic: 2.0 - delta / scale0,
            delta_bic: (n as f64).ln() - delta / scale0,
            max_move_sigma: estimate.abs() * st.amax(),
        });
        projected.push((t.name, estimate, st, t.parameter));
    }
    holm(&mut candidates, s.alpha);
    candidates.sort_by(|a, b| b.delta_chi2.total_cmp(&a.delta_chi2));
    // what separates a tied pair: the sweep's unrecorded outputs, the material refitted
    let effects: Vec<Parameter> = params
        .iter()
        .copied()
        .filter(|p| matches!(p, Parameter::Effect(_)))
        .collect();
    let items = measurements::candidates(cells, sens, &params);
    let design = measurements::discrimination(
        &z,
        |p| params.iter().position(|q| *q == p).map(|j| w(column(j))),
        &params,
        &effects,
        &items,
    );
    let fit = PairFit {
        residual: &r,
        chi2_material,
        dof,
        alpha: s.alpha,
        collinear: s.collinear,
    };
    let separating = design
        .as_ref()
        .map(|d| (d, effects.as_slice(), items.as_slice()));
    let indistinguishable = pairs(&projected, &candidates, separating, &fit);
    let verdict = verdict(&candidates, &indistinguishable, chi2_material);
    Ok(Naming {
        refitted_material: None,
        n_cells: n,
        unmatched,
        spikes,
        chi2,
        chi2_material,
        candidates,
        indistinguishable,
        untestable,
        verdict,
    })
}

/// The lower Cholesky factor `L` of `I + D̃D̃ᵀ` over the used cells (`D̃` the spread's
/// deviations over each cell's σ), or none without a spread; `L⁻¹` whitens.
pub(crate) fn whitening(
    spread: Option<&ErrorSpread>,
    cells: &[Cell],
    rows: &[(&Cell, Vec<f64>)],
    row_cell: &[usize],
) -> Result<Option<DMatrix<f64>>, DiagnoseError> {
    let Some(spread) = spread else {
        return Ok(None);
    };
    if let Some(d) = spread.deviations.iter().find(|d| d.len() != cells.len()) {
        return Err(DiagnoseError::input(
            "error spread",
            format!("{} values per sample", d.len()),
            &format!("one value per cell of the table ({})", cells.len()),
        ));
    }
    let n = rows.len();
    let d = DMatrix::from_fn(n, spread.deviations.len(), |i, k| {
        spread.deviations[k][row_cell[i]] / rows[i].0.sigma
    });
    let gamma = DMatrix::identity(n, n) + &d * d.transpose();
    let chol = gamma.cholesky().ok_or_else(|| {
        DiagnoseError::input(
            "error spread",
            "not finite",
            "finite deviations (I + DDᵀ is then positive definite)",
        )
    })?;
    Ok(Some(chol.l()))
}

/// Holm's step-down correction at level `alpha` over every candidate.
fn holm(c: &mut [Candidate], alpha: f64) {
    let mut order: Vec<usize> = (0..c.len()).collect();
    order.sort_by(|&a, &b| c[a].p_value.total_cmp(&c[b].p_value));
    let m = c.len();
    for (k, &i) in order.iter().enumerate() {
        if c[i].p_value <= alpha / (m - k) as f64 {
            c[i].significant = true;
        } else {
            break;
        }
    }
}

/// `Δχ²` of the fit with two signatures `a`, `b` together, from their Gram entries
/// (`aa = a·a`, `bb`, `ab`) and their products with the residual (`ar`, `br`); the better
/// single fit's where the two are collinear.
fn joint_delta(aa: f64, bb: f64, ab: f64, ar: f64, br: f64) -> f64 {
    let det = aa * bb - ab * ab;
    if det > 1e-12 * aa * bb {
        (bb * ar * ar - 2.0 * ab * ar * br + aa * br * br) / det
    } else {
        (ar * ar / aa).max(br * br / bb)
    }
}

/// What [`pairs`] tests two candidates with.
struct PairFit<'a> {
    /// The residual after the material re-fit (whitened, material directions projected out).
    residual: &'a DVector<f64>,
    /// Its `χ²`.
    chi2_material: f64,
    /// Degrees of freedom of a one-effect fit.
    dof: f64,
    /// Level of the separation test.
    alpha: f64,
    /// `|cos|` above which two signatures are collinear.
    collinear: f64,
}

impl PairFit<'_> {
    /// The p-value of the better of `sa`, `sb` beyond the other: the fit with both against
    /// the fit with the worse one alone (F with 1 and `dof − 1` degrees of freedom).
    fn p_separation(&self, sa: &DVector<f64>, sb: &DVector<f64>) -> f64 {
        let r = self.residual;
        let (aa, bb, ab) = (sa.dot(sa), sb.dot(sb), sa.dot(sb));
        let (ar, br) = (sa.dot(r), sb.dot(r));
        let (da, db) = (ar * ar / aa, br * br / bb);
        let joint = joint_delta(aa, bb, ab, ar, br);
        let extra = (joint - da.min(db)).max(0.0);
        let dof = self.dof - 1.0;
        let scale = (self.chi2_material - joint).max(0.0) / dof;
        if scale <= 0.0 || dof < 1.0 {
            return 0.0;
        }
        FisherSnedecor::new(1.0, dof).map_or(f64::NAN, |d| 1.0 - d.cdf(extra / scale))
    }

    /// The likelihood-ratio test of two non-nested one-effect fits (Vuong's idea, with the
    /// Gaussian variance of the cells rather than the empirical one): `D = χ²_b − χ²_a`
    /// (twice the log-likelihood ratio, in units of the variance `s²` of the fit with both),
    /// whose standard deviation is `2 s |ŷ_a − ŷ_b|` (`ŷ` the fitted explanations) to first
    /// order; `z = D / sd`, positive when `sa` fits better. Two identical fits give 0.
    fn vuong_z(&self, sa: &DVector<f64>, sb: &DVector<f64>) -> f64 {
        let r = self.residual;
        let (aa, bb, ab) = (sa.dot(sa), sb.dot(sb), sa.dot(sb));
        let (ar, br) = (sa.dot(r), sb.dot(r));
        let (ca, cb) = (ar / aa, br / bb);
        let d = ar * ar / aa - br * br / bb;
        // |ca sa − cb sb|
        let gap = (ca * ca * aa - 2.0 * ca * cb * ab + cb * cb * bb)
            .max(0.0)
            .sqrt();
        let joint = joint_delta(aa, bb, ab, ar, br);
        let s2 = (self.chi2_material - joint).max(0.0) / (self.dof - 1.0).max(1.0);
        if gap <= 1e-12 * r.norm().max(1e-300) || s2 <= 0.0 {
            return 0.0;
        }
        d / (2.0 * s2.sqrt() * gap)
    }

    /// Whether the recordings cannot tell `sa` from `sb`: the better one adds nothing
    /// significant beyond the other, or neither fits significantly better (Vuong).
    fn tied(&self, p_separation: f64, vuong_z: f64) -> bool {
        let z_crit = Normal::new(0.0, 1.0).map_or(1.96, |d| d.inverse_cdf(1.0 - 0.5 * self.alpha));
        p_separation > self.alpha || vuong_z.abs() < z_crit
    }
}

/// The criterion's problem, its candidates' parameters and the measurements it can add.
type Separating<'a> = (
    &'a Discrimination,
    &'a [Parameter],
    &'a [(Measurement, Vec<f64>)],
);

/// Pairs the recordings cannot tell apart, with the unrecorded output that separates them:
/// nearly collinear pairs among the significant candidates (or the two best when none is),
/// and pairs of the first or the named candidate with another whose fit it does not beat
/// significantly ([`PairFit::tied`]).
fn pairs(
    projected: &[(String, f64, DVector<f64>, Option<Parameter>)],
    ranked: &[Candidate],
    separating: Option<Separating>,
    fit: &PairFit,
) -> Vec<Indistinguishable> {
    let mut interesting: Vec<&str> = ranked
        .iter()
        .filter(|c| c.significant)
        .map(|c| c.effect.as_str())
        .collect();
    if interesting.is_empty() {
        interesting = ranked.iter().take(2).map(|c| c.effect.as_str()).collect();
    }
    // the candidates a reader acts on: the first of the ranking and the named one, when
    // significant
    let leading: Vec<&str> = ranked
        .first()
        .into_iter()
        .chain(ranked.iter().find(|c| c.significant && c.plausible))
        .filter(|c| c.significant)
        .map(|c| c.effect.as_str())
        .collect();
    let mut out = Vec::new();
    for (a, (na, _, sa, pa)) in projected.iter().enumerate() {
        for (nb, _, sb, pb) in projected.iter().skip(a + 1) {
            if !interesting.contains(&na.as_str()) && !interesting.contains(&nb.as_str()) {
                continue;
            }
            let cos = sa.dot(sb) / (sa.norm() * sb.norm());
            let tests = (leading.contains(&na.as_str()) || leading.contains(&nb.as_str()))
                .then(|| (fit.p_separation(sa, sb), fit.vuong_z(sa, sb)));
            let tied = tests.is_some_and(|(p, z)| fit.tied(p, z));
            if cos.abs() < fit.collinear && !tied {
                continue;
            }
            out.push(Indistinguishable {
                a: na.clone(),
                b: nb.clone(),
                cosine: cos,
                p_separation: tests.map(|t| t.0),
                vuong_z: tests.map(|t| t.1),
                separated_by: match (pa, pb, separating) {
                    (Some(pa), Some(pb), Some((d, effects, items))) => {
                        separation(d, effects, items, *pa, *pb)
                    }
                    _ => None,
                },
            });
        }
    }
    out
}

/// The single unrecorded measurement that separates `a` from `b` most
/// ([`Discrimination::best_single`]: the T-optimality criterion, the material refitted), in
/// words, in the scatter of the better fit ([`Discrimination::scale`]); `effects` the design's candidates in order.
fn separation(
    design: &Discrimination,
    effects: &[Parameter],
    items: &[(Measurement, Vec<f64>)],
    a: Parameter,
    b: Parameter,
) -> Option<String> {
    let ia = effects.iter().position(|p| *p == a)?;
    let ib = effects.iter().position(|p| *p == b)?;
    let scale = design.scale(ia).min(design.scale(ib));
    let before = design.separation(ia, ib, &[]) / scale;
    let (item, after) = design.best_single(ia, ib)?;
    let after = after / scale;
    Some(format!(
        "{}, σ = {:.3}: the two expected {:.2} σ apart (log Bayes factor {:.2}), {:.2} σ on \
         these recordings",
        items[item].0.text(),
        items[item].0.sigma,
        after.sqrt(),
        after / 2.0,
        before.sqrt()
    ))
}

/// The verdict in words: the best significant candidate at a plausible size is named; a
/// significant one whose size is outside the library's plausible range is reported as such,
/// not named.
fn verdict(c: &[Candidate], pairs: &[Indistinguishable], chi2_material: f64) -> String {
    let implausible: Vec<String> = c
        .iter()
        .filter(|t| t.significant && !t.plausible)
        .take(3)
        .map(|t| {
            format!(
                "{} ({:+.3}{})",
                t.effect,
                t.estimate,
                super::wording::unit_suffix(&t.unit)
            )
        })
        .collect();
    let Some(top) = c.iter().find(|t| t.significant && t.plausible) else {
        if implausible.is_empty() {
            return format!(
                "No effect of the library explains the residual left after the material \
                 re-fit (χ² = {chi2_material:.1}) significantly: nothing is named."
            );
        }
        return format!(
            "No effect of the library explains the residual at a plausible size: the \
             significant ones would need sizes outside their ranges ({}), so nothing is \
             named (the residual left after the material re-fit, χ² = {chi2_material:.1}, \
             is larger than one effect of the library can make).",
            implausible.join(", ")
        );
    };
    if top.model_error {
        let next = c
            .iter()
            .find(|t| t.significant && t.plausible && !t.model_error)
            .map_or(String::new(), |t| {
                format!(
                    "; of the effects, {} would explain {:.0} % ({:+.3}{})",
                    t.effect,
                    100.0 * t.explained,
                    t.estimate,
                    super::wording::unit_suffix(&t.unit)
                )
            });
        return format!(
            "The residual left after the material re-fit looks most like the diagnosing \
             model's own discretisation error ({} explains {:.0} %, size {:+.2} ± {:.2} {}, \
             F = {:.1}, p = {:.2e}){next}: no physics is named. Refine the model's mesh (or \
             diagnose with the finer model) before reading the residual as missing physics.",
            top.effect,
            100.0 * top.explained,
            top.estimate,
            top.std_error,
            top.unit,
            top.f,
            top.p_value,
        );
    }
    let mut s = format!(
        "{} explains {:.0} % of the residual left after the material re-fit (size {:+.3} ± \
         {:.3}{}, F = {:.1}, p = {:.2e})",
        top.effect,
        100.0 * top.explained,
        top.estimate,
        top.std_error,
        super::wording::unit_suffix(&top.unit),
        top.f,
        top.p_value,
    );
    let twins: Vec<&str> = pairs
        .iter()
        .filter_map(|p| {
            if p.a == top.effect {
                Some(p.b.as_str())
            } else if p.b == top.effect {
                Some(p.a.as_str())
            } else {
                None
            }
        })
        .collect();
    if !twins.is_empty() {
        s.push_str(&format!(
            "; on these recordings it cannot be told apart from {}",
            twins.join(", ")
        ));
    }
    let runners_up: Vec<String> = c
        .iter()
        .filter(|t| t.significant && t.plausible && !t.model_error && t.effect != top.effect)
        .take(2)
        .map(|t| {
            format!(
                "{} ({:.0} %, {:+.3}{})",
                t.effect,
                100.0 * t.explained,
                t.estimate,
                super::wording::unit_suffix(&t.unit)
            )
        })
        .collect();
    if !runners_up.is_empty() {
        s.push_str(&format!(
            "; also significant at a plausible size, explaining less: {}",
            runners_up.join(", ")
        ));
    }
    if !implausible.is_empty() {
        s.push_str(&format!(
            "; significant but at implausible sizes: {}",
            implausible.join(", ")
        ));
    }
    s.push('.');
    s
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    use super::*;
    use crate::calibrate::baseline::{DesignSensitivities, SWEEP_SENSITIVITY_FORMAT};
    use crate::calibrate::objective::Output;
    use crate::fe::effects::{Effect, Effects};
    use crate::fe::material::Material;
    use crate::fe::mesh::{MeshLevel, MeshOptions};
    use crate::fe::sensitivity::{
        Outputs, ParameterInfo, Sensitivities, SensitivityCost, StepSensitivities,
    };
    use crate::fe::simulate::Mode;

    const DESIGNS: [(usize, f64); 9] = [
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

    fn random_outputs(rng: &mut Xoshiro256PlusPlus) -> Outputs {
        let mut g = || rng.gen_range(-1.0..1.0);
        Outputs {
            tip_uz_mm: g(),
            tip_uy_mm: g(),
            angle_deg: g(),
            markers: (0..9).map(|_| [g(), g()]).collect(),
            force_n: None,
        }
    }

    /// A bending sweep with random signatures for every parameter.
    fn sweep(seed: u64) -> SweepSensitivities {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let parameters: Vec<ParameterInfo> = Parameter::all()
            .into_iter()
            .map(|p| ParameterInfo {
                parameter: p,
                unit: p.unit().into(),
                value: 0.0,
                step: 1e-6,
                how: String::new(),
            })
            .collect();
        let designs = DESIGNS
            .iter()
            .map(|&(n, t)| DesignSensitivities {
                n_bellows: n,
                wall_thickness_mm: t,
                mode: Mode::Bending,
                sensitivities: Sensitivities {
                    format: String::new(),
                    version: 1,
                    mode: Mode::Bending,
                    parameters: parameters.clone(),
                    steps: [0.0, 1.0, 2.0, 3.0]
                        .iter()
                        .map(|&p| StepSensitivities {
                            pressure_bar: p,
                            values: random_outputs(&mut rng),
                            // the force rig's own effects move nothing in bending
                            derivatives: parameters
                                .iter()
                                .map(|i| {
                                    let mut o = random_outputs(&mut rng);
                                    if let Parameter::Effect(
                                        Effect::PlateOffset
                                        | Effect::PlateCompliance
                                        | Effect::ForceScale,
                                    ) = i.parameter
                                    {
                                        o = Outputs {
                                            tip_uz_mm: 0.0,
                                            tip_uy_mm: 0.0,
                                            angle_deg: 0.0,
                                            markers: vec![[0.0; 2]; 9],
                                            force_n: None,
                                        };
                                    }
                                    o
                                })
                                .collect(),
                        })
                        .collect(),
                    cost: SensitivityCost::default(),
                },
            })
            .collect();
        SweepSensitivities {
            format: SWEEP_SENSITIVITY_FORMAT.into(),
            version: 1,
            material: Material::from_spec("ogden_002", 1000.0).unwrap(),
            mesh: MeshOptions::level(MeshLevel::Coarse),
            effects: Effects::neutral(),
            designs,
            missing: Vec::new(),
        }
    }

    /// Cells (tip Uz, tip Uy, angle at 1, 2, 3 bar, σ = 1) of recordings made by the sweep's
    /// linear model with the material off by `material` and `planted` effects, plus noise.
    fn cells(sens: &SweepSensitivities, planted: &[(Effect, f64)], seed: u64) -> Vec<Cell> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let params = &sens.designs[0].sensitivities.parameters;
        let at = |p: Parameter| params.iter().position(|i| i.parameter == p).unwrap();
        let material = [0.3, -0.2, 0.1, 0.25];
        let mut out = Vec::new();
        for d in &sens.designs {
            for st in &d.sensitivities.steps[1..] {
                for output in [Output::TipUz, Output::TipUy, Output::Angle] {
                    let mut delta = 0.0;
                    for (k, m) in OgdenParameter::ALL.iter().zip(material) {
                        delta +=
                            m * derivative_of(&st.derivatives[at(Parameter::Material(*k))], output)
                                .unwrap();
                    }
                    for &(e, v) in planted {
                        delta +=
                            v * derivative_of(&st.derivatives[at(Parameter::Effect(e))], output)
                                .unwrap();
                    }
                    // the actuator has the offsets the model lacks: z = (model − actuator)/σ
                    let z = -delta + 0.05 * rng.gen_range(-1.0..1.0);
                    out.push(Cell::unit(
                        d.n_bellows as u32,
                        d.wall_thickness_mm,
                        st.pressure_bar,
                        output,
                        z,
                    ));
                }
            }
        }
        out
    }

    #[test]
    fn a_planted_effect_is_named_with_its_size() {
        let sens = sweep(1);
        let n = name(
            &cells(&sens, &[(Effect::WallBias, 0.12)], 2),
            &sens,
            &NameSettings::default(),
        )
        .unwrap();
        let top = &n.candidates[0];
        assert_eq!(top.effect, "wall_bias", "{:#?}", n.candidates[..3].to_vec());
        assert!(top.significant && top.plausible);
        assert!(
            (top.estimate - 0.12).abs() < 3.0 * top.std_error && top.std_error < 0.02,
            "{} ± {}",
            top.estimate,
            top.std_error
        );
        assert!(n.verdict.starts_with("wall_bias explains"), "{}", n.verdict);
        // the material's offsets were projected out, not blamed on an effect
        assert!(n.candidates[1..].iter().all(|c| !c.significant));
        // force-rig effects move nothing a bending recording holds
        assert!(n.untestable.iter().any(|u| u.effect == "plate_offset"));
    }

    #[test]
    fn a_second_effect_is_reported_beside_the_named_one() {
        let sens = sweep(1);
        let planted = [(Effect::WallBias, 0.12), (Effect::Density, 0.25)];
        let n = name(&cells(&sens, &planted, 2), &sens, &NameSettings::default()).unwrap();
        let (first, second) = (&n.candidates[0], &n.candidates[1]);
        let names = [first.effect.as_str(), second.effect.as_str()];
        assert!(
            names.contains(&"wall_bias") && names.contains(&"density"),
            "{:#?}",
            n.candidates[..3].to_vec()
        );
        assert!(second.significant && second.plausible, "{second:#?}");
        assert!(
            n.verdict.starts_with(&format!("{} explains", first.effect))
                && n.verdict.contains(&format!(
                    "also significant at a plausible size, explaining less: {} (",
                    second.effect
                )),
            "{}",
            n.verdict
        );
    }

    /// A random model-error direction over `cells` (unit of each output).
    fn direction(cells: &[Cell], seed: u64) -> ErrorDirection {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        ErrorDirection {
            name: "model_mesh".into(),
            per_cell: cells
                .iter()
                .map(|_| Some(rng.gen_range(-1.0..1.0)))
                .collect(),
        }
    }

    #[test]
    fn the_models_own_error_is_told_from_physics() {
        let sens = sweep(11);
        let clean = cells(&sens, &[], 12);
        let d = direction(&clean, 13);
        // the model misses the actuator by 0.8 of its mesh error: that, not physics, is said
        let mut off = clean.clone();
        for (i, c) in off.iter_mut().enumerate() {
            c.standardised -= 0.8 * d.at(i);
        }
        let s = NameSettings {
            model_errors: vec![d.clone()],
            ..NameSettings::default()
        };
        let n = name(&off, &sens, &s).unwrap();
        let me = n
            .model_error()
            .expect("the mesh error explains the residual");
        assert_eq!(me.effect, "model_mesh");
        assert!(me.model_error && n.named().is_none(), "{}", n.verdict);
        assert!(
            (me.estimate - 0.8).abs() < 3.0 * me.std_error,
            "{}",
            me.estimate
        );
        assert!(n.verdict.contains("discretisation error"), "{}", n.verdict);
        // a planted effect still wins over the model's error when the error is not there
        let planted = cells(&sens, &[(Effect::WallBias, 0.12)], 12);
        let n = name(&planted, &sens, &s).unwrap();
        assert_eq!(n.named().map(|c| c.effect.as_str()), Some("wall_bias"));
        assert!(n.candidates.iter().any(|c| c.model_error && !c.significant));
        // a direction of another table is refused, naming it
        let short = ErrorDirection {
            per_cell: vec![Some(1.0); 3],
            ..d
        };
        let err = name(
            &off,
            &sens,
            &NameSettings {
                model_errors: vec![short],
                ..NameSettings::default()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("model_mesh (3 values)"), "{err}");
    }

    #[test]
    fn a_model_error_weighed_by_its_covariance_is_not_named_as_physics() {
        let sens = sweep(21);
        let params = &sens.designs[0].sensitivities.parameters;
        let j = params
            .iter()
            .position(|p| p.parameter == Parameter::Effect(Effect::FreeLengthBias))
            .unwrap();
        // the model's own error lies along free_length_bias's signature (as if the actuator
        // were 1.5 mm longer); the recordings' noise is 1 σ
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(22);
        let base = cells(&sens, &[], 23);
        let e: Vec<f64> = base
            .iter()
            .map(|c| -1.5 * derivs_of(&sens, c).unwrap()[j])
            .collect();
        let noisy: Vec<Cell> = base
            .iter()
            .zip(&e)
            .map(|(c, ei)| {
                let mut c = c.clone();
                c.standardised += ei + 1.7 * rng.gen_range(-1.0..1.0);
                c
            })
            .collect();
        let plain = name(&noisy, &sens, &NameSettings::default()).unwrap();
        assert_eq!(
            plain.named().map(|c| c.effect.as_str()),
            Some("free_length_bias"),
            "{}",
            plain.verdict
        );
        // samples of the model's error at three materials: +e, −e, 0 (covariance e eᵀ)
        let spread = ErrorSpread {
            sources: vec!["a".into(), "b".into(), "c".into()],
            deviations: vec![
                e.iter().map(|v| v / 2f64.sqrt()).collect(),
                e.iter().map(|v| -v / 2f64.sqrt()).collect(),
                vec![0.0; e.len()],
            ],
        };
        let s = NameSettings {
            error_spread: Some(spread.clone()),
            ..NameSettings::default()
        };
        let weighed = name(&noisy, &sens, &s).unwrap();
        assert!(weighed.named().is_none(), "{}", weighed.verdict);
        // an effect the model's error does not resemble is still named beside that error,
        // with its size (recordings of little noise)
        let planted: Vec<Cell> = cells(&sens, &[(Effect::WallBias, 0.3)], 23)
            .into_iter()
            .zip(&e)
            .map(|(mut c, ei)| {
                c.standardised += ei;
                c
            })
            .collect();
        let n = name(&planted, &sens, &s).unwrap();
        let top = n.named().unwrap_or_else(|| panic!("{}", n.verdict));
        assert_eq!(top.effect, "wall_bias", "{}", n.verdict);
        assert!(
            (top.estimate - 0.3).abs() < 3.0 * top.std_error,
            "{} ± {}",
            top.estimate,
            top.std_error
        );
        // a spread of another table is refused
        let short = ErrorSpread {
            deviations: vec![vec![0.0; 3]; 3],
            ..spread
        };
        let err = name(
            &noisy,
            &sens,
            &NameSettings {
                error_spread: Some(short),
                ..NameSettings::default()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("3 values per sample"), "{err}");
    }

    /// The separation test on vectors made by hand: two signatures 0.8 apart in cosine, a
    /// residual along the first with unit noise elsewhere.
    #[test]
    fn a_pair_is_tied_unless_the_better_one_adds_significantly_beyond_the_other() {
        let n = 60;
        let e = |k: usize| DVector::from_fn(n, |i, _| if i == k { 1.0 } else { 0.0 });
        let sa = e(0);
        let sb = e(0) * 0.8 + e(1) * 0.6;
        // unit noise on the other 58 numbers: χ² per degree of freedom about 1
        let noise = DVector::from_fn(n, |i, _| {
            if i < 2 {
                0.0
            } else if i % 2 == 0 {
                1.0
            } else {
                -1.0
            }
        });
        // the fit of a residual that holds everything the material left
        fn pair_fit(r: &DVector<f64>) -> PairFit<'_> {
            PairFit {
                residual: r,
                chi2_material: r.norm_squared(),
                dof: r.len() as f64 - 5.0,
                alpha: 0.05,
                collinear: 0.95,
            }
        }
        let fit = |size: f64| pair_fit(&(&sa * size + &noise)).p_separation(&sa, &sb);
        // a strong residual along `sa`: b explains 64 % of it, a all of it, 36 % beyond b
        // is 0.36 × 100 = 36 χ² units, far beyond the noise
        assert!(fit(10.0) < 1e-6, "{}", fit(10.0));
        // a weak one: 0.36 × 4 = 1.44 beyond b, within the noise
        assert!(fit(2.0) > 0.05, "{}", fit(2.0));
        // the order of the two does not matter
        let r = &sa * 2.0 + &noise;
        let f = pair_fit(&r);
        assert!((f.p_separation(&sa, &sb) - f.p_separation(&sb, &sa)).abs() < 1e-12);
        // Vuong: antisymmetric, and decided only by a strong residual
        assert!((f.vuong_z(&sa, &sb) + f.vuong_z(&sb, &sa)).abs() < 1e-12);
        assert!(f.tied(f.p_separation(&sa, &sb), f.vuong_z(&sa, &sb)));
        let r = &sa * 10.0 + &noise;
        let strong = pair_fit(&r);
        // D = 100 − 64, |ŷ_a − ŷ_b| = |3.6, −4.8| = 6: z ≈ 36 / 12 = 3, told apart
        let z = strong.vuong_z(&sa, &sb);
        assert!((z - 3.0).abs() < 0.2, "{z}");
        assert!(!strong.tied(strong.p_separation(&sa, &sb), z));
        assert_eq!(strong.vuong_z(&sa, &sa), 0.0);
    }

    #[test]
    fn a_derivative_spike_is_reported() {
        let mut sens = sweep(17);
        // tip Uz at N = 9, T = 1.6, 2 bar: density's derivative 1000 times the others'
        let j = sens.designs[0]
            .sensitivities
            .parameters
            .iter()
            .position(|p| p.parameter == Parameter::Effect(Effect::Density))
            .unwrap();
        let steps = &mut sens.designs[0].sensitivities.steps;
        for st in steps.iter_mut() {
            st.derivatives[j].tip_uz_mm = 0.01;
        }
        steps[2].derivatives[j].tip_uz_mm = 10.0;
        let cells = cells(&sens, &[], 18);
        let n = name(&cells, &sens, &NameSettings::default()).unwrap();
        assert!(
            n.spikes.iter().any(|s| s.starts_with(
                "N = 9, T = 1.6 mm, 2 bar, tip_uz_mm: its FE derivative by density is 1000 times"
            )),
            "{:?}",
            n.spikes
        );
        assert!(!n
            .spikes
            .iter()
            .any(|s| s
                .starts_with("N = 9, T = 1.6 mm, 1 bar, tip_uz_mm: its FE derivative by density")));
    }

    #[test]
    fn material_offsets_and_noise_alone_name_nothing() {
        let sens = sweep(3);
        let n = name(&cells(&sens, &[], 4), &sens, &NameSettings::default()).unwrap();
        assert!(n.candidates.iter().all(|c| !c.significant), "{}", n.verdict);
        assert!(n.verdict.starts_with("No effect"), "{}", n.verdict);
        // the material took its offsets: what is left is the noise (σ_noise² = 0.05²/3)
        assert!(
            n.chi2_material < 0.05 * n.chi2,
            "{} of {}",
            n.chi2_material,
            n.chi2
        );
    }

    #[test]
    fn collinear_candidates_are_reported_as_indistinguishable() {
        let mut sens = sweep(5);
        // gap_bias moves every output as wall_bias does, twice as much, plus a trace
        let params = sens.designs[0].sensitivities.parameters.clone();
        let at = |p: Effect| {
            params
                .iter()
                .position(|i| i.parameter == Parameter::Effect(p))
                .unwrap()
        };
        let (w, g) = (at(Effect::WallBias), at(Effect::GapBias));
        for d in &mut sens.designs {
            for st in &mut d.sensitivities.steps {
                let mut copy = st.derivatives[w].clone();
                copy.tip_uz_mm = 2.0 * copy.tip_uz_mm + 1e-3;
                copy.tip_uy_mm *= 2.0;
                copy.angle_deg *= 2.0;
                // the markers (not recorded) tell them apart
                copy.markers.iter_mut().for_each(|m| m[1] += 1.0);
                st.derivatives[g] = copy;
            }
        }
        let n = name(
            &cells(&sens, &[(Effect::WallBias, 0.12)], 6),
            &sens,
            &NameSettings::default(),
        )
        .unwrap();
        let pair = n
            .indistinguishable
            .iter()
            .find(|p| [&p.a, &p.b].contains(&&"gap_bias".to_string()))
            .unwrap_or_else(|| panic!("{:#?}", n.indistinguishable));
        assert!(pair.cosine > 0.99);
        assert!(
            pair.separated_by
                .as_deref()
                .is_some_and(|s| s.starts_with('m') && s.contains("_uy_mm at N = ")),
            "{pair:?}"
        );
        assert!(n.verdict.contains("cannot be told apart"), "{}", n.verdict);
    }

    #[test]
    fn a_sweep_without_the_material_is_refused() {
        let mut sens = sweep(7);
        for d in &mut sens.designs {
            d.sensitivities
                .parameters
                .retain(|p| matches!(p.parameter, Parameter::Effect(_)));
        }
        let e = name(&cells(&sweep(7), &[], 1), &sens, &NameSettings::default()).unwrap_err();
        assert!(e.to_string().contains("mu1"), "{e}");
    }
}
