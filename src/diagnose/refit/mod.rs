//! Model and show: the material refitted together with the chosen effect(s), the effect's
//! size with its confidence interval, the fit before and after, and the gain on designs the
//! fit did not see.
//!
//! Every cell of the residual table that the FE sweep has sensitivities for takes part, each
//! with weight 1 and its own `σ` (the Name stage's cells: the outputs the calibration's
//! objective left out count here, or a force-rig effect could not be estimated). The
//! prediction of cell `i` with the material at unit-box point `u` and effect sizes `θ` (from
//! the sweep's values: neutral, unless the sweep fixed an effect as the model's training
//! cases did, [`SweepSensitivities::base`]) is
//!
//! ```text
//!   ŷᵢ(u, θ) = surrogateᵢ(u) + Σₖ θₖ ∂yᵢ/∂θₖ + cᵢ
//! ```
//!
//! the effect linearised with the FE sensitivities of the sweep (at about the calibrated
//! material), `cᵢ` a correction that the FE confirmation sets (zero before it: see
//! [`confirm_with_fe`]). Both fits are bounded Levenberg–Marquardt on the surrogate's
//! analytic Jacobian: the material inside the surrogate's training box, each effect's value
//! (the sweep's plus `θ`) inside its library range; a bound that stops a fit is reported.
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

mod confirm;
mod fit;
mod held_out;
mod outcome;
mod problem;
mod quality;
mod rank;
mod rows;
mod verdict;

use nalgebra::DMatrix;

use crate::calibrate::baseline::SweepSensitivities;
use crate::calibrate::objective::Evaluator;
use crate::calibrate::ParamSpace;
use crate::case::OgdenSet;
use crate::diagnose::cells::Cell;
use crate::diagnose::signature::{sensitivity_step, LocalMaterial};
use crate::diagnose::DiagnoseError;
use crate::rom::Surrogate;
use problem::Problem;

pub use confirm::{confirm_with_fe, FeConfirmSettings, FeEvaluation, FeModel};
pub use rank::{
    rank_with_fe, ranked_candidates, vuong_z, FeRankSettings, FeRanked, FeRanking, Picked,
};
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub use rank::rank_confirmed;
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub use confirm::confirm_with;
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub use fit::fit_rows;
// public for the tests in tests/diagnose/
pub use outcome::{
    EffectSize, FeRound, FitSummary, HeldOut, HeldOutDesign, Quality, Refit, RefitSettings,
};
#[doc(hidden)]
pub use rows::Rows;

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
        base: Vec::new(),
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
            .ogden_set()
            .map_or("a non-Ogden material".to_string(), |m| format!(
                "Ogden ({}, {}, {}, {})",
                m.mu1_mpa, m.alpha1, m.mu2_mpa, m.alpha2
            )),
        sens.mesh.level.name()
    );
    Ok(r)
}
