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

mod candidates;
mod naming;
mod projection;
mod table;
mod ties;
mod verdict;
mod whiten;

use crate::calibrate::baseline::SweepSensitivities;
use crate::diagnose::cells::Cell;
use crate::diagnose::measurements;
use crate::diagnose::signature::LocalMaterial;
use crate::diagnose::DiagnoseError;
use crate::fe::sensitivity::{OgdenParameter, Parameter};
use projection::PastMaterial;
use table::UsedCells;
use ties::pairs;
use verdict::verdict;
use whiten::Whitening;

pub use naming::{Candidate, Indistinguishable, NameSettings, Naming, Untestable};
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub use table::derivs_of;
pub(crate) use whiten::whitening;
// public for the tests in tests/diagnose/
pub(crate) use ties::two_sided_z;
#[doc(hidden)]
pub use ties::PairFit;

pub use crate::diagnose::sweep::MIN_NAME_CELLS;

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
/// [`crate::diagnose::refit`] does), and the residual and the material directions projected out are
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
    start: &crate::case::OgdenSet,
    s: &NameSettings,
) -> Result<Naming, DiagnoseError> {
    let (local, material) = crate::diagnose::refit::material_refit(cells, sens, model, start)?;
    let mut n = name_inner(cells, sens, Some(&local), s)?;
    n.refitted_material = Some(material);
    Ok(n)
}

/// The Name stage, from the cells with sensitivities to the verdict: the residual and every
/// candidate's signature past the material (linearised, or the nonlinear re-fit's `local`
/// residual and directions), each candidate's F test under Holm, the tied pairs.
fn name_inner(
    cells: &[Cell],
    sens: &SweepSensitivities,
    local: Option<&LocalMaterial>,
    s: &NameSettings,
) -> Result<Naming, DiagnoseError> {
    check_settings(s)?;
    let params = sweep_parameters(sens);
    let material = material_parameters(&params, local.is_some())?;
    let used = UsedCells::of(cells, sens, local)?;
    let whiten = Whitening::of(s.error_spread.as_ref(), cells, &used.rows, &used.row_cell)?;
    let fit = PastMaterial::fit(&used, &material, local.is_some(), &whiten);
    candidates::check_model_errors(&s.model_errors, cells.len())?;
    let tested = candidates::columns(sens, &params, &used, &s.model_errors);
    let tests = candidates::test_all(tested, &fit, &whiten, s.alpha);
    // what separates a tied pair: the sweep's unrecorded outputs, the material refitted
    let effects: Vec<Parameter> = params
        .iter()
        .copied()
        .filter(|p| matches!(p, Parameter::Effect(_)))
        .collect();
    let items = measurements::candidates(cells, sens, &params);
    let design = measurements::discrimination(
        &fit.z,
        |p| {
            params
                .iter()
                .position(|q| *q == p)
                .map(|j| whiten.vector(used.column(j)))
        },
        &params,
        &effects,
        &items,
    );
    let pair_fit = PairFit {
        residual: &fit.residual,
        chi2_material: fit.chi2_material,
        dof: fit.dof(),
        alpha: s.alpha,
        collinear: s.collinear,
    };
    let separating = design
        .as_ref()
        .map(|d| (d, effects.as_slice(), items.as_slice()));
    let indistinguishable = pairs(&tests.projected, &tests.candidates, separating, &pair_fit);
    let verdict = verdict(&tests.candidates, &indistinguishable, fit.chi2_material);
    Ok(Naming {
        refitted_material: None,
        n_cells: used.len(),
        unmatched: used.unmatched,
        spikes: used.spikes,
        chi2: fit.chi2,
        chi2_material: fit.chi2_material,
        candidates: tests.candidates,
        indistinguishable,
        untestable: tests.untestable,
        verdict,
    })
}

/// The level and the collinearity threshold, each in (0, 1).
fn check_settings(s: &NameSettings) -> Result<(), DiagnoseError> {
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
    Ok(())
}

/// The sweep's parameters, in the order of its derivatives.
pub(crate) fn sweep_parameters(sens: &SweepSensitivities) -> Vec<Parameter> {
    sens.designs
        .first()
        .map(|d| {
            d.sensitivities
                .parameters
                .iter()
                .map(|p| p.parameter)
                .collect()
        })
        .unwrap_or_default()
}

/// The positions of the four material parameters among `params`.
///
/// # Errors
/// [`DiagnoseError::Input`] if the sweep lacks one and the material is not `refitted`
/// (the linearised re-fit needs all four).
fn material_parameters(params: &[Parameter], refitted: bool) -> Result<Vec<usize>, DiagnoseError> {
    let material: Vec<usize> = OgdenParameter::ALL
        .iter()
        .filter_map(|k| params.iter().position(|p| *p == Parameter::Material(*k)))
        .collect();
    if material.len() != 4 && !refitted {
        return Err(DiagnoseError::input(
            "sensitivities",
            "without mu1, alpha1, mu2, alpha2",
            "a sweep with the four material parameters (validate --sensitivities all)",
        ));
    }
    Ok(material)
}
