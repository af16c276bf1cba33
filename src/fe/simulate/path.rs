//! The path driver: a case's model taken along its load path, each output level measured.
//!
//! The stages, in the order [`run_warm`] takes them:
//!
//! 1. **Self-weight.** Gravity alone (load level 0); the state reported at P = 0 when the
//!    requested list starts at 0 bar.
//! 2. **Plate** ([`Mode::Force`](super::Mode::Force)). The force plate goes
//!    [`PLATE_OFFSET`] (plus the plate-offset effect) below the tip of the hanging actuator.
//! 3. **Pressure ramp.** The pressure rises through the requested levels, each the effective
//!    pressure of the case's effects, in MPa (`p · BAR`), gravity kept on. A level with a
//!    matching state of a neighbouring case ([`crate::fe::warm_start`]) is solved by Newton
//!    from it; the others by load stepping from the previous level.
//!
//! **Compliant plate.** With the plate-compliance effect `c` (mm/N) the plate sits on a
//! spring: at each level its position solves the fixed point
//!
//! ```text
//!   g(y) = y − (y0 − c · F(y)) = 0,
//! ```
//!
//! `F` the blocked force of the whole actuator with the plate at `y`. The level is solved with
//! the plate where it is, the plate moved by a secant step on `g`
//! (`y ← y − g · (y − y') / (g − g')`, the first step `y ← y0 − c · F`), and the level
//! solved again from the converged state, until `|g| <` [`PLATE_SETTLE_MM`]. The fixed point
//! is unique and the iteration contracts while `c` times the tip's stiffness against the
//! plate is below 1 (about 0.3 N/mm × 1 mm/N at the library's largest compliance).

use std::time::Instant;

use super::case::{Case, BAR};
use super::measure::{measure, Response, StepResult};
use super::model::ActuatorModel;
use super::SimulateError;
use crate::fe::assembly::terms::barrier::IpcBarrier;
use crate::fe::assembly::{LoadFactor, LoadLevel};
use crate::fe::geometry::Design;
use crate::fe::solver::{
    solve_path_from, solve_path_guided, LevelGuess, PathState, SolverError, SolverKind,
    SolverSettings, StepReport,
};
use crate::fe::warm_start::{ConvergedState, WarmStart};

/// Distance of the force plate below the tip of the unpressurised actuator (mm, SPEC).
pub const PLATE_OFFSET: f64 = 5.0;
/// Tolerance on the compliant plate's position `|y − (y0 − c·F)|` (mm).
pub const PLATE_SETTLE_MM: f64 = 1e-4;
/// Re-solves allowed per load level for the compliant plate to settle.
pub const PLATE_SETTLE_ITERATIONS: usize = 30;

/// Runs one case.
///
/// # Errors
/// See [`simulate_with_progress`].
pub fn simulate(case: &Case) -> Result<Response, SimulateError> {
    simulate_with_progress(case, |_, _| {})
}

/// Runs one case, calling `progress(step, total)` after each converged output step.
///
/// # Errors
/// Invalid pressures, degenerate mesh, or a solver that did not converge (carrying the
/// reports of the steps that did).
pub fn simulate_with_progress(
    case: &Case,
    progress: impl FnMut(usize, usize),
) -> Result<Response, SimulateError> {
    simulate_with(case, progress, |_, _, _| {})
}

/// Runs one case, calling `progress(step, total)` after each converged load level and
/// `on_result(model, result, u)` with the full displacement vector of every reported step
/// (e.g. to write VTK files).
///
/// # Errors
/// See [`simulate_with_progress`].
pub fn simulate_with(
    case: &Case,
    progress: impl FnMut(usize, usize),
    on_result: impl FnMut(&ActuatorModel, &StepResult, &[f64]),
) -> Result<Response, SimulateError> {
    Ok(run(case, progress, on_result, false)?.response)
}

/// A finished ramp with its model and converged states ([`run`]).
pub struct Ran {
    /// The results.
    pub response: Response,
    /// The model, as the ramp left it (the plate placed, the last contact shifts).
    pub model: ActuatorModel,
    /// The design as printed.
    pub design: Design,
    /// The self-weight state first, then one per pressure level of the ramp (empty unless
    /// asked for).
    pub states: Vec<ConvergedState>,
}

/// [`simulate_with`], returning the model and, if `keep_states`, every converged state.
///
/// # Errors
/// See [`simulate_with_progress`].
pub fn run(
    case: &Case,
    progress: impl FnMut(usize, usize),
    on_result: impl FnMut(&ActuatorModel, &StepResult, &[f64]),
    keep_states: bool,
) -> Result<Ran, SimulateError> {
    run_warm(case, None, progress, on_result, keep_states)
}

/// [`run`], each output level started from the matching state of `warm` (a neighbouring
/// case on the same mesh, [`crate::fe::warm_start`]) where there is one: same answers to the
/// solver's tolerance, fewer Newton iterations. Levels without a matching state, a warm start
/// of another mesh, the compliant plate's ramp and the minimisation solver take the load path
/// as [`run`] does; [`StepResult::warm_start`] says which levels started warm.
///
/// # Errors
/// See [`simulate_with_progress`].
pub fn run_warm(
    case: &Case,
    warm: Option<&WarmStart>,
    progress: impl FnMut(usize, usize),
    on_result: impl FnMut(&ActuatorModel, &StepResult, &[f64]),
    keep_states: bool,
) -> Result<Ran, SimulateError> {
    let start = Instant::now();
    let (design, mut model) = build(case)?;
    let path = LoadPath::of(case);
    let guesses = warm.map_or_else(Vec::new, |w| w.guesses(path.ramp_bar));
    let guess = |i: usize| guesses.get(i).and_then(Option::as_ref);
    let mut record = Record {
        case,
        path: &path,
        lf: design.free_length(),
        keep_states,
        progress,
        on_result,
        steps: Vec::new(),
        states: Vec::new(),
    };
    let mut state = PathState::new(&model.fe);
    // Stage 1: self-weight (the state reported at P = 0).
    let reports = solve_path_guided(
        &model.fe,
        case.solver.clone(),
        &mut state,
        &path.levels[..1],
        &[guess(0)],
        |_, state, rep| record.self_weight(&model, state, rep),
    )?;
    record.keep(0.0, &model, &state, path.first_is_zero);
    // Stage 2 (blocked force): the plate goes 5 mm below the hanging tip.
    place_plate(&mut model, &state, case);
    // Stage 3: the pressure ramp.
    let ramp_guesses: Vec<_> = (1..path.levels.len()).map(guess).collect();
    let ramp = pressure_ramp(
        &mut model,
        case,
        (&path, &ramp_guesses),
        &mut state,
        &mut |i, model, state, rep| record.pressure_level(i, model, state, rep),
    )?;
    let reports = join_ramp(reports, ramp)?;
    Ok(Ran {
        response: response(record.steps, &model, &reports, start),
        model,
        design,
        states: record.states,
    })
}

/// The model of a case, checked first: its design and material as printed, and the
/// minimisation solver's barrier contact law when that solver is chosen.
fn build(case: &Case) -> Result<(Design, ActuatorModel), SimulateError> {
    case.validate()?;
    let design = case.printed_design()?;
    let material = case.effects.printed_material(&case.material)?;
    let mut model = ActuatorModel::with_effects(
        &design,
        &material,
        &case.mesh,
        case.mode,
        &case.contact,
        &case.effects,
    )?;
    if let SolverKind::Minimise(m) = case.solver.kind {
        model.fe.barrier = Some(IpcBarrier::new(m.dhat_mm, m.barrier_pressure)?);
    }
    Ok((design, model))
}

/// The load levels of a case: the self-weight first, then one per requested pressure above
/// the self-weight state.
struct LoadPath<'c> {
    /// Self-weight, then the ramp's levels.
    levels: Vec<LoadLevel>,
    /// The requested list starts at 0 bar, which the self-weight state reports.
    first_is_zero: bool,
    /// The requested pressures of the ramp's levels (bar).
    ramp_bar: &'c [f64],
}

impl<'c> LoadPath<'c> {
    fn of(case: &'c Case) -> Self {
        let g = if case.gravity { 1.0 } else { 0.0 };
        let first_is_zero = case.pressures_bar[0] == 0.0;
        let ramp_bar = &case.pressures_bar[usize::from(first_is_zero)..];
        let weight = LoadLevel::ZERO.with(LoadFactor::GRAVITY, g);
        let mut levels = vec![weight];
        levels.extend(ramp_bar.iter().map(|&p| {
            weight.with(
                LoadFactor::PRESSURE,
                case.effects.effective_pressure_bar(p) * BAR,
            )
        }));
        Self {
            levels,
            first_is_zero,
            ramp_bar,
        }
    }
}

/// What the driver records at each converged output level: the step measured, handed to the
/// caller's callbacks and, if asked, its state kept.
struct Record<'c, P, R> {
    case: &'c Case,
    path: &'c LoadPath<'c>,
    /// Free length of the printed design (mm).
    lf: f64,
    keep_states: bool,
    progress: P,
    on_result: R,
    steps: Vec<StepResult>,
    states: Vec<ConvergedState>,
}

impl<P, R> Record<'_, P, R>
where
    P: FnMut(usize, usize),
    R: FnMut(&ActuatorModel, &StepResult, &[f64]),
{
    /// The self-weight state: progress, and the step at 0 bar when the list starts there.
    fn self_weight(&mut self, model: &ActuatorModel, state: &PathState, rep: &StepReport) {
        (self.progress)(1, self.path.levels.len());
        if self.path.first_is_zero {
            let result = measure(model, state, rep, self.lf, 0.0);
            (self.on_result)(model, &result, &state.u_full);
            self.steps.push(result);
        }
    }

    /// Level `i` of the ramp: measured at its requested pressure, the blocked force scaled by
    /// the load cell's effect.
    fn pressure_level(
        &mut self,
        i: usize,
        model: &ActuatorModel,
        state: &PathState,
        rep: &StepReport,
    ) {
        (self.progress)(i + 2, self.path.levels.len());
        let mut result = measure(model, state, rep, self.lf, self.path.ramp_bar[i]);
        if let Some(f) = result.force_n.as_mut() {
            let scale = self.case.effects.force_scale();
            if scale != 1.0 {
                *f *= scale;
            }
        }
        (self.on_result)(model, &result, &state.u_full);
        self.keep(result.pressure_bar, model, state, true);
        self.steps.push(result);
    }

    /// Keeps a converged state, if asked: displacement, contact gap shifts, plate position.
    fn keep(
        &mut self,
        pressure_bar: f64,
        model: &ActuatorModel,
        state: &PathState,
        reported: bool,
    ) {
        if self.keep_states {
            self.states.push(ConvergedState {
                pressure_bar,
                level: state.level,
                u: state.u_full.clone(),
                shifts: model.fe.contact_shifts(),
                plate_y: model.plate.map(|p| model.fe.planes[p].point[1]),
                reported,
            });
        }
    }
}

/// Puts the force plate, if any, [`PLATE_OFFSET`] (plus the plate-offset effect) below the
/// tip of the actuator hanging under its own weight.
fn place_plate(model: &mut ActuatorModel, state: &PathState, case: &Case) {
    if let Some(plate) = model.plate {
        let tip = model.marker_displacement(8, &state.u_full);
        let offset = PLATE_OFFSET + case.effects.plate_offset_mm();
        model.fe.planes[plate].point = [0.0, tip[1] - offset, 0.0];
    }
}

/// The ramp's levels from the self-weight state: against the compliant plate when there is
/// one, along the load path (each level from its guess where it has one) otherwise. The
/// outer `Result` is the plate's own failure, the inner one the solver's.
fn pressure_ramp(
    model: &mut ActuatorModel,
    case: &Case,
    (path, guesses): (&LoadPath, &[Option<&LevelGuess>]),
    state: &mut PathState,
    observe: &mut impl FnMut(usize, &ActuatorModel, &PathState, &StepReport),
) -> Result<Result<Vec<StepReport>, SolverError>, SimulateError> {
    let compliance = case.effects.plate_compliance_mm_per_n();
    let levels = (&path.levels[1..], path.ramp_bar);
    if model.plate.is_some() && compliance > 0.0 {
        return compliant_plate_ramp(model, &case.solver, state, levels, compliance, observe);
    }
    let model = &*model;
    Ok(solve_path_guided(
        &model.fe,
        case.solver.clone(),
        state,
        levels.0,
        guesses,
        |i, state, rep| observe(i, model, state, rep),
    ))
}

/// The self-weight's reports followed by the ramp's; a ramp that stopped carries them all,
/// `completed` counting the self-weight level too.
fn join_ramp(
    mut reports: Vec<StepReport>,
    ramp: Result<Vec<StepReport>, SolverError>,
) -> Result<Vec<StepReport>, SolverError> {
    match ramp {
        Ok(r) => {
            reports.extend(r);
            Ok(reports)
        }
        Err(SolverError::NotConverged {
            target,
            reached,
            cutbacks,
            residual,
            completed,
            reports: r,
        }) => {
            reports.extend(r);
            Err(SolverError::NotConverged {
                target,
                reached,
                cutbacks,
                residual,
                completed: completed + 1,
                reports,
            })
        }
        Err(e) => Err(e),
    }
}

/// The response of a finished ramp: its steps, the model's size, and the time spent.
fn response(
    steps: Vec<StepResult>,
    model: &ActuatorModel,
    reports: &[StepReport],
    start: Instant,
) -> Response {
    Response {
        steps,
        nodes: model.fe.mesh.n_nodes(),
        elements: model.fe.mesh.n_elements(),
        dofs: model.fe.dofs.n_free,
        wall_time_s: start.elapsed().as_secs_f64(),
        factor_time_s: reports.iter().map(|r| r.factor_seconds).sum(),
        assembly_time_s: reports.iter().map(|r| r.assembly_seconds).sum(),
        factorizations: reports.iter().map(|r| r.factorizations).sum(),
    }
}

/// The pressure ramp against a plate on a spring of compliance `c` (mm/N): each level solved
/// until the plate settles at `y = y0 − c·F(y)` (the module's fixed point), its reports
/// adding up the level's re-solves.
///
/// The outer `Result` is the plate's own failure; the inner one the solver's, as
/// [`solve_path_from`] returns it (with `completed` counting the levels before the failure).
fn compliant_plate_ramp(
    model: &mut ActuatorModel,
    settings: &SolverSettings,
    state: &mut PathState,
    (levels, pressures_bar): (&[LoadLevel], &[f64]),
    compliance: f64,
    observe: &mut impl FnMut(usize, &ActuatorModel, &PathState, &StepReport),
) -> Result<Result<Vec<StepReport>, SolverError>, SimulateError> {
    let plate = model.plate.expect("a compliant plate needs the plate");
    let y0 = model.fe.planes[plate].point[1];
    let mut reports: Vec<StepReport> = Vec::with_capacity(levels.len());
    let mut r = vec![0.0; state.u_full.len()];
    for (i, level) in levels.iter().enumerate() {
        let mut sum: Option<StepReport> = None;
        let mut previous: Option<(f64, f64)> = None;
        for iteration in 1..=PLATE_SETTLE_ITERATIONS {
            let solved = solve_path_from(
                &model.fe,
                settings.clone(),
                state,
                std::slice::from_ref(level),
                |_, _, _| {},
            );
            let rep = match solved {
                Ok(mut r) => r.remove(0),
                Err(e) => return Ok(Err(e.after(reports))),
            };
            sum = Some(match sum {
                None => rep,
                Some(s) => add_resolve(s, rep),
            });
            let info = model
                .fe
                .assemble(&state.u_full, &state.level, &mut r, None)?;
            // ×2: the model is a half
            let force = 2.0 * info.plane_forces[plate];
            let y = model.fe.planes[plate].point[1];
            let mismatch = y - (y0 - compliance * force);
            if mismatch.abs() < PLATE_SETTLE_MM {
                break;
            }
            if iteration == PLATE_SETTLE_ITERATIONS {
                return Err(SimulateError::PlateNotSettled {
                    pressure_bar: pressures_bar[i],
                    iterations: iteration,
                    mismatch_mm: mismatch.abs(),
                });
            }
            let next = match previous {
                Some((yp, gp)) if (mismatch - gp).abs() > f64::EPSILON * y.abs().max(1.0) => {
                    y - mismatch * (y - yp) / (mismatch - gp)
                }
                _ => y0 - compliance * force,
            };
            previous = Some((y, mismatch));
            model.fe.planes[plate].point[1] = next;
        }
        let rep = sum.expect("at least one solve per level");
        observe(i, model, state, &rep);
        reports.push(rep);
    }
    Ok(Ok(reports))
}

/// The report of a level so far with one more re-solve added: counts and times summed, the
/// last solve's residual, update, level and convergence.
fn add_resolve(mut sum: StepReport, rep: StepReport) -> StepReport {
    sum.level = rep.level;
    sum.newton_iterations += rep.newton_iterations;
    sum.substeps += rep.substeps;
    sum.cutbacks += rep.cutbacks;
    sum.residual = rep.residual;
    sum.update = rep.update;
    sum.converged = rep.converged;
    sum.factor_seconds += rep.factor_seconds;
    sum.assembly_seconds += rep.assembly_seconds;
    sum.augmented_updates += rep.augmented_updates;
    sum.augmented_failed |= rep.augmented_failed;
    sum.factorizations += rep.factorizations;
    sum.stabilized |= rep.stabilized;
    sum
}
