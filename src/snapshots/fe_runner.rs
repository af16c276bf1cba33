//! The real case runner: one FE pressure ramp per case.
//!
//! [`fe_runner`] = [`bending_ramp`] (the actuator hanging free, gravity then pressure) +
//! [`blocked_force_ramp`] (the blocked-force test), each a cold ramp of the FE campaign runner
//! ([`cold_ramp`]). A ramp that stops keeps the steps it reached; the outcome carries the
//! solver's error for the rest.

use super::plan::{PlanSettings, PlannedCase};
use super::store::{CaseOutcome, StepOutputs};
use crate::fe::runner::cold_ramp;
use crate::fe::simulate::{Case, Mode, StepResult};

/// The FE case (bending or blocked-force test) of a planned case, built with the plan's
/// geometry preset, with the plan's fixed effects and the case's sampled ones.
///
/// # Errors
/// The design, material or effect error as text (plans are validated on load, so only a
/// hand-built case can fail here).
pub fn fe_case(case: &PlannedCase, settings: &PlanSettings, mode: Mode) -> Result<Case, String> {
    Ok(Case {
        design: case
            .design_with(&settings.geometry())
            .map_err(|e| e.to_string())?,
        material: case
            .material(settings.bulk_ratio)
            .map_err(|e| e.to_string())?,
        pressures_bar: settings.pressures_bar.clone(),
        gravity: settings.gravity,
        mesh: settings.mesh,
        solver: settings.solver.clone(),
        mode,
        contact: settings.contact,
        effects: case.effects_with(settings).map_err(|e| e.to_string())?,
    })
}

/// Outputs of one FE step (force `NaN`: filled in by [`fe_runner`]).
pub fn step_outputs(r: &StepResult) -> StepOutputs {
    StepOutputs {
        tip_uz_mm: r.tip_uz_mm,
        tip_uy_mm: r.tip_uy_mm,
        angle_deg: r.angle_deg,
        force_n: f64::NAN,
        markers: std::array::from_fn(|k| r.markers.get(k).copied().unwrap_or([f64::NAN; 2])),
        newton_iterations: r.newton_iterations,
        substeps: r.substeps,
        cutbacks: r.cutbacks,
        residual: r.residual,
        min_gap_mm: r.min_gap_mm,
        converged: r.converged,
    }
}

/// The bending ramp: the steps the solver reached and its error if it stopped.
pub fn bending_ramp(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    let fe = match fe_case(case, settings, Mode::Bending) {
        Ok(fe) => fe,
        Err(e) => return CaseOutcome::failed(e),
    };
    let ramp = cold_ramp(&fe, &[]);
    CaseOutcome {
        steps: ramp.steps.iter().map(step_outputs).collect(),
        error: ramp.error.map(|e| format!("bending: {e}")),
    }
}

/// The blocked-force ramp: the plate reaction (N) at each plan pressure reached, and the error
/// if the ramp stopped early.
pub fn blocked_force_ramp(
    case: &PlannedCase,
    settings: &PlanSettings,
) -> (Vec<f64>, Option<String>) {
    let fe = match fe_case(case, settings, Mode::Force) {
        Ok(fe) => fe,
        Err(e) => return (Vec::new(), Some(e)),
    };
    let ramp = cold_ramp(&fe, &[]);
    let force = ramp
        .steps
        .iter()
        .map(|r| r.force_n.unwrap_or(f64::NAN))
        .collect();
    (force, ramp.error)
}

/// The real runner: bending ramp and blocked-force ramp, joined per pressure. A row needs
/// both, so the case keeps the steps both ramps reached; the first error is reported.
pub fn fe_runner(case: &PlannedCase, settings: &PlanSettings) -> CaseOutcome {
    let mut outcome = bending_ramp(case, settings);
    let (force, force_error) = blocked_force_ramp(case, settings);
    outcome.steps.truncate(force.len());
    for (step, f) in outcome.steps.iter_mut().zip(force) {
        step.force_n = f;
    }
    if outcome.error.is_none() {
        outcome.error = force_error.map(|e| format!("blocked force: {e}"));
    }
    outcome
}
