//! Each candidate against the residual past the material: the nested F test of adding its
//! signature to the material re-fit, its size and standard error, `ΔAIC` and `ΔBIC`, and
//! Holm's step-down correction over all of them (the equations are in the
//! [module docs](super)).

use nalgebra::DVector;
use statrs::distribution::{ContinuousCDF, FisherSnedecor};

use super::naming::{Candidate, Untestable};
use super::projection::PastMaterial;
use super::table::UsedCells;
use super::whiten::Whitening;
use crate::calibrate::baseline::SweepSensitivities;
use crate::diagnose::mesh_error::{ErrorDirection, MODEL_ERROR_UNIT, PLAUSIBLE_MODEL_ERROR};
use crate::diagnose::DiagnoseError;
use crate::fe::sensitivity::Parameter;

/// A column tested against the residual: an effect of the sweep or an error of the model.
pub(crate) struct Tested {
    name: String,
    unit: String,
    /// The value the estimate is measured from: the sweep's ([`SweepSensitivities::base`]),
    /// zero for a model error.
    base: f64,
    /// Whether `base` is not the effect's neutral value.
    fixed: bool,
    range: (f64, f64),
    /// `S_j` (σ-scaled), per used cell.
    column: DVector<f64>,
    /// The sweep's parameter (none: a model error).
    parameter: Option<Parameter>,
}

/// A tested candidate's signature past the material, `s̃`: its name, estimated size, `s̃`
/// and the sweep's parameter (none: a model error).
pub(crate) type Projected = (String, f64, DVector<f64>, Option<Parameter>);

/// The candidates tested, largest `Δχ²` first, and those that could not be.
pub(crate) struct Tests {
    /// The candidates, with Holm's correction, largest `Δχ²` first.
    pub(crate) candidates: Vec<Candidate>,
    /// Their signatures past the material, in the order they were tested.
    pub(crate) projected: Vec<Projected>,
    /// Those the recordings cannot test.
    pub(crate) untestable: Vec<Untestable>,
}

/// Every model error must hold one value per cell of the table (`n_cells`).
///
/// # Errors
/// [`DiagnoseError::Input`] naming the first one that does not.
pub(crate) fn check_model_errors(
    model_errors: &[ErrorDirection],
    n_cells: usize,
) -> Result<(), DiagnoseError> {
    for nu in model_errors {
        if nu.per_cell.len() != n_cells {
            return Err(DiagnoseError::input(
                "model error",
                format!("{} ({} values)", nu.name, nu.per_cell.len()),
                &format!("one value per cell of the table ({n_cells})"),
            ));
        }
    }
    Ok(())
}

/// The columns to test: every effect of the sweep (`params`, measured from the sweep's
/// values of `sens`), then the model's own errors.
pub(crate) fn columns(
    sens: &SweepSensitivities,
    params: &[Parameter],
    used: &UsedCells<'_>,
    model_errors: &[ErrorDirection],
) -> Vec<Tested> {
    // the effects of the sweep, then the model's own errors
    let mut tested: Vec<Tested> = Vec::new();
    for (j, p) in params.iter().enumerate() {
        let Parameter::Effect(e) = *p else { continue };
        let info = e.info();
        let base = sens.base(e);
        tested.push(Tested {
            name: e.name().into(),
            unit: info.unit.into(),
            base,
            fixed: base != info.neutral,
            range: info.range,
            column: used.column(j),
            parameter: Some(*p),
        });
    }
    for nu in model_errors {
        tested.push(Tested {
            name: nu.name.clone(),
            unit: MODEL_ERROR_UNIT.into(),
            base: 0.0,
            fixed: false,
            range: PLAUSIBLE_MODEL_ERROR,
            column: DVector::from_iterator(
                used.len(),
                used.row_cell
                    .iter()
                    .zip(&used.rows)
                    .map(|(&ci, (c, _))| nu.at(ci) / c.sigma),
            ),
            parameter: None,
        });
    }
    tested
}

/// Tests every column of `tested` against the residual of `fit`, then corrects the
/// candidates' p-values together at level `alpha` (Holm) and ranks them by `Δχ²`.
pub(crate) fn test_all(
    tested: Vec<Tested>,
    fit: &PastMaterial,
    whiten: &Whitening,
    alpha: f64,
) -> Tests {
    let mut candidates = Vec::new();
    let mut untestable = Vec::new();
    let mut projected = Vec::new();
    for t in tested {
        match test_one(t, fit, whiten) {
            Ok((c, p)) => {
                candidates.push(c);
                projected.push(p);
            }
            Err(u) => untestable.push(u),
        }
    }
    holm(&mut candidates, alpha);
    candidates.sort_by(|a, b| b.delta_chi2.total_cmp(&a.delta_chi2));
    Tests {
        candidates,
        projected,
        untestable,
    }
}

/// The nested F test of one column (`significant` left to [`holm`]), or why it cannot be
/// tested.
fn test_one(
    t: Tested,
    fit: &PastMaterial,
    whiten: &Whitening,
) -> Result<(Candidate, Projected), Untestable> {
    let n = fit.z.len();
    let chi2_material = fit.chi2_material;
    let dof = fit.dof();
    let scale0 = fit.scale0();
    let sj = whiten.vector(t.column);
    let norm = sj.norm();
    if norm == 0.0 {
        return Err(Untestable {
            effect: t.name,
            reason: "moves nothing these recordings hold".into(),
        });
    }
    let st = fit.project(&sj);
    let kept = st.norm();
    if kept <= 1e-3 * norm {
        return Err(Untestable {
            effect: t.name,
            reason: format!(
                "the material absorbs its signature ({:.4} % left)",
                100.0 * kept / norm
            ),
        });
    }
    let proj = st.dot(&fit.residual);
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
    let size = t.base + estimate;
    let candidate = Candidate {
        effect: t.name.clone(),
        unit: t.unit,
        base: t.fixed.then_some(t.base),
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
    };
    Ok((candidate, (t.name, estimate, st, t.parameter)))
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
