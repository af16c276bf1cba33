//! The material alone and the material with the effect(s) on the same rows: sizes,
//! intervals, the nested F test, the held-out designs and the verdict.

use nalgebra::DMatrix;
use statrs::distribution::{ContinuousCDF, FisherSnedecor, StudentsT};

use super::held_out::held_out;
use super::outcome::{EffectSize, Refit, RefitSettings};
use super::problem::Problem;
use super::quality::{noise_be, summary};
use super::rows::Rows;
use super::verdict::verdict;
use crate::calibrate::ParamSpace;
use crate::case::OgdenSet;
use crate::diagnose::DiagnoseError;
use crate::rom::Surrogate;

/// The refit on `rows`: the material alone, then with `s.effects`, from `start`.
///
/// # Errors
/// Too few rows for the material, the effects and a residual; a surrogate error.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn fit_rows(
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
            let value = rows.value(i, est);
            EffectSize {
                effect: info.name.into(),
                unit: info.unit.into(),
                value,
                estimate: est,
                std_error: se,
                interval: (value - t * se, value + t * se),
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
