//! Running a ramp with its sensitivities, and the differentiation itself: at every
//! differentiated converged state the tangent is assembled and factorised once; per parameter
//! `−∂R/∂θ` at fixed `u` comes from the residuals at the parameter's perturbed points (the
//! plate moved with the sagged tip in the force rig, the clamped face along the rigid clamp's
//! limit), one solve with the factor gives `du/dθ`, and the outputs' slope along `(du/dθ, θ)`
//! their derivatives. About an augmented-Lagrangian state the contact of the linearisation is
//! [`CONTACT_STIFFENING`] times stiffer. The method is described in the
//! [parent module](super).

use std::time::Instant;

use super::clamp;
use super::{
    perturbations, How, Outputs, Parameter, ParameterInfo, Perturbation, Sensitivities,
    SensitivityCost, SensitivityError, StepSensitivities, CONTACT_STIFFENING, SENSITIVITY_FORMAT,
    SENSITIVITY_FORMAT_VERSION,
};
use crate::fe::assembly::{LoadFactor, LoadLevel};
use crate::fe::effects::{Differentiation, Target};
use crate::fe::material::Material;
use crate::fe::simulate::{
    run, run_warm, ActuatorModel, Case, ConvergedState, Mode, Ran, Response, StepResult, BAR,
};
use crate::fe::solver::{LinearSolver, NonlinearProblem};
use crate::fe::warm_start::{FieldSensitivities, WarmStart, WarmStartError};

/// Runs `case` and differentiates every reported step's outputs with respect to
/// `parameters`; `progress(step, total)` follows the ramp.
///
/// # Errors
/// Before any FE work: a material parameter of a non-Ogden material, a derivative at a
/// compliant plate. Then the ramp's errors, a dimension the mesh cannot follow, or a failed
/// factorisation.
pub fn simulate_with_sensitivities(
    case: &Case,
    parameters: &[Parameter],
    progress: impl FnMut(usize, usize),
) -> Result<(Response, Sensitivities), SensitivityError> {
    sensitivities_with(case, parameters, progress, |_, _, _| {})
}

/// [`simulate_with_sensitivities`] calling `on_result(model, result, u)` with every reported
/// step of the ramp, as [`simulate_with`](crate::fe::simulate::simulate_with) does (e.g. to
/// write VTK files).
///
/// # Errors
/// See [`simulate_with_sensitivities`].
pub fn sensitivities_with(
    case: &Case,
    parameters: &[Parameter],
    progress: impl FnMut(usize, usize),
    on_result: impl FnMut(&ActuatorModel, &StepResult, &[f64]),
) -> Result<(Response, Sensitivities), SensitivityError> {
    check(case, parameters)?;
    let ran = run(case, progress, on_result, true)?;
    let response = ran.response.clone();
    let (sens, _) = differentiate(case, ran, parameters, false)?;
    Ok((response, sens))
}

/// A ramp with its sensitivities, its converged states and their displacement sensitivities:
/// what a neighbouring case needs to start from ([`WarmStart::moved`]).
pub struct WithFields {
    /// The results.
    pub response: Response,
    /// The outputs' sensitivities.
    pub sensitivities: Sensitivities,
    /// The converged states (self-weight first, then one per pressure level).
    pub states: Vec<ConvergedState>,
    /// `∂u/∂θ` of every differentiated state, the parameters in the order asked for.
    pub fields: FieldSensitivities,
}

impl WithFields {
    /// A warm start for the same design at parameters moved by `delta` (in the order of the
    /// parameters asked for): these states moved by their first-order sensitivities.
    ///
    /// # Errors
    /// A step per parameter of the wrong length, or not finite.
    pub fn warm_start(&self, delta: &[f64]) -> Result<WarmStart, WarmStartError> {
        WarmStart::moved(self.states.clone(), &self.fields, delta)
    }
}

/// [`sensitivities_with`] started from `warm` ([`run_warm`]), keeping the converged states
/// and their displacement sensitivities for the next case.
///
/// # Errors
/// See [`simulate_with_sensitivities`].
pub fn sensitivities_with_fields(
    case: &Case,
    parameters: &[Parameter],
    warm: Option<&WarmStart>,
    progress: impl FnMut(usize, usize),
    on_result: impl FnMut(&ActuatorModel, &StepResult, &[f64]),
) -> Result<WithFields, SensitivityError> {
    check(case, parameters)?;
    let ran = run_warm(case, warm, progress, on_result, true)?;
    let response = ran.response.clone();
    let (sensitivities, kept) = differentiate(case, ran, parameters, true)?;
    let (states, fields) = kept.unwrap_or_default();
    Ok(WithFields {
        response,
        sensitivities,
        states,
        fields,
    })
}

/// Refuses what cannot be differentiated, before the ramp.
fn check(case: &Case, parameters: &[Parameter]) -> Result<(), SensitivityError> {
    for p in parameters {
        match p {
            Parameter::Material(_) if case.material.ogden_set().is_none() => {
                return Err(SensitivityError::Unsupported {
                    parameter: p.name(),
                    why: "the material is not a second-order Ogden law".into(),
                })
            }
            Parameter::Effect(e) if e.differentiation() == Differentiation::Unsupported => {
                return Err(super::not_differentiated(*e))
            }
            _ => {}
        }
    }
    if case.mode == Mode::Force && case.effects.plate_compliance_mm_per_n() > 0.0 {
        return Err(SensitivityError::Unsupported {
            parameter: "plate_compliance",
            why: format!(
                "derivatives at a compliant plate ({} mm/N) are not supported: differentiate \
                 at plate_compliance = 0",
                case.effects.plate_compliance_mm_per_n()
            ),
        });
    }
    Ok(())
}

/// The outputs of `model` at `u` (free length `lf`, the force scaled by `scale`).
fn outputs(model: &ActuatorModel, u: &[f64], lf: f64, scale: f64) -> Outputs {
    let markers: Vec<[f64; 2]> = (0..model.mesh.markers.len())
        .map(|k| {
            let d = model.marker_displacement(k, u);
            [-d[2], d[1]]
        })
        .collect();
    let tip = markers[markers.len() - 1];
    let (z_tip, y_tip) = (lf - tip[0], tip[1]);
    Outputs {
        tip_uz_mm: tip[0],
        tip_uy_mm: tip[1],
        angle_deg: (-y_tip).atan2(z_tip).to_degrees(),
        markers,
        // ×2: the model is a half
        force_n: model
            .plate
            .map(|p| 2.0 * model.fe.plane_force(u, p) * scale),
    }
}

/// The sensitivities of a finished ramp; with `keep_fields`, also its states and their
/// displacement sensitivities.
#[allow(clippy::type_complexity)]
fn differentiate(
    case: &Case,
    ran: Ran,
    parameters: &[Parameter],
    keep_fields: bool,
) -> Result<
    (
        Sensitivities,
        Option<(Vec<ConvergedState>, FieldSensitivities)>,
    ),
    SensitivityError,
> {
    let start = Instant::now();
    let Ran {
        response,
        model: mut base,
        design,
        states,
    } = ran;
    let mut perturbed = perturbations(case, &base, &design, parameters)?;
    let clamp = perturbed
        .iter()
        .flat_map(|p| &p.points)
        .any(|q| matches!(q.how, How::RigidClamp(_)))
        .then(|| clamp::ClampFace::new(&base));
    let setup_s = start.elapsed().as_secs_f64();
    let mut cost = SensitivityCost {
        ramp_s: response.wall_time_s,
        setup_s,
        ..Default::default()
    };
    let mut ws = Workspace::new(&base)?;
    let ramp = RampSetup {
        clamp,
        scale: case.effects.force_scale(),
        lf: design.free_length(),
        force_rig: case.mode == Mode::Force,
        // the augmented Lagrangian holds touching points at their gap: linearise with stiff
        // contact (the plain penalty, `augmented_updates = 0`, and the barrier stay as they
        // are)
        stiffen: case.solver.augmented_updates > 0 && base.fe.barrier.is_none(),
    };
    if ramp.stiffen {
        stiffen_contact(&mut base, &mut perturbed);
    }
    let mut steps = Vec::new();
    let mut fields = keep_fields.then(|| FieldSensitivities {
        parameters: parameters.iter().map(|p| p.name().to_string()).collect(),
        du: vec![Vec::new(); states.len()],
    });
    for (si, st) in states.iter().enumerate() {
        let self_weight = si == 0;
        if !(st.reported || ramp.force_rig && self_weight) {
            continue;
        }
        let du_fields = fields.as_mut().map(|f| {
            f.du[si] = vec![Vec::new(); perturbed.len()];
            &mut f.du[si]
        });
        let at = StateAt { st, self_weight };
        let (y0, derivatives) = differentiate_state(
            &ramp,
            &mut base,
            &mut perturbed,
            &at,
            &mut ws,
            &mut cost,
            du_fields,
        )?;
        if st.reported {
            steps.push(StepSensitivities {
                pressure_bar: st.pressure_bar,
                values: y0,
                derivatives,
            });
        }
    }
    cost.sensitivity_s = start.elapsed().as_secs_f64();
    cost.overhead = cost.sensitivity_s / cost.ramp_s.max(f64::MIN_POSITIVE);
    let sens = sensitivities_of(case, &perturbed, steps, cost);
    Ok((sens, fields.map(|f| (states, f))))
}

/// What every state of a ramp's differentiation shares.
struct RampSetup {
    /// The clamped face, where a parameter takes the rigid clamp's limit.
    clamp: Option<clamp::ClampFace>,
    /// The reported force's scale.
    scale: f64,
    /// Free length of the design (mm).
    lf: f64,
    /// Whether the ramp is in the force rig.
    force_rig: bool,
    /// Whether the contact of the linearisation is [`CONTACT_STIFFENING`] times stiffer.
    stiffen: bool,
}

/// The tangent's factor and the full- and free-size vectors of a differentiation, reused
/// from state to state.
struct Workspace {
    lin: LinearSolver,
    /// The tangent's values.
    k: Vec<f64>,
    /// The residual at the state.
    r0: Vec<f64>,
    /// The residual at a point.
    rp: Vec<f64>,
    /// `−∂R/∂θ` at fixed `u`.
    acc: Vec<f64>,
    /// The clamped face's motion per unit of the parameter (zero without one).
    du_s: Vec<f64>,
    /// `du/dθ`.
    du: Vec<f64>,
    /// A displaced state.
    u2: Vec<f64>,
    /// A right-hand side on the free unknowns.
    rhs: Vec<f64>,
    /// `∂R/∂y_plate` at the state.
    dr_plate: Vec<f64>,
}

impl Workspace {
    /// The symbolic analysis of `base`'s tangent and zeroed vectors of its sizes.
    fn new(base: &ActuatorModel) -> Result<Self, SensitivityError> {
        let n_full = base.fe.n_full();
        Ok(Workspace {
            lin: LinearSolver::new(&base.fe)?,
            k: vec![0.0; base.fe.pattern.nnz()],
            r0: vec![0.0; n_full],
            rp: vec![0.0; n_full],
            acc: vec![0.0; n_full],
            du_s: vec![0.0; n_full],
            du: vec![0.0; n_full],
            u2: vec![0.0; n_full],
            rhs: vec![0.0; base.fe.n_free()],
            dr_plate: vec![0.0; n_full],
        })
    }
}

/// A converged state being differentiated.
struct StateAt<'a> {
    st: &'a ConvergedState,
    /// The first state (`P = 0`, the plate's reference).
    self_weight: bool,
}

/// What the derivatives at one state share once its tangent is factorised.
struct StateTerms<'a> {
    at: &'a StateAt<'a>,
    /// The contact's gap shifts of the linearisation.
    shifts: &'a [f64],
    /// Whether the plate's motion enters `−∂R/∂θ` (through `Workspace::dr_plate`).
    plate_term: bool,
    /// The force without its scale (N).
    raw_force: f64,
    /// The outputs at the state.
    y0: &'a Outputs,
}

/// Makes the contact of the base model and of every perturbed model
/// [`CONTACT_STIFFENING`] times stiffer.
fn stiffen_contact(base: &mut ActuatorModel, perturbed: &mut [Perturbation]) {
    base.fe.scale_contact(CONTACT_STIFFENING);
    for q in perturbed.iter_mut().flat_map(|p| &mut p.points) {
        if let How::Model(m) = &mut q.how {
            m.fe.scale_contact(CONTACT_STIFFENING);
        }
    }
}

/// The outputs at one state and their derivatives with respect to every parameter; records
/// each parameter's plate shift at the self-weight state of the force rig, and `du/dθ` into
/// `du_fields` when given.
fn differentiate_state(
    ramp: &RampSetup,
    base: &mut ActuatorModel,
    perturbed: &mut [Perturbation],
    at: &StateAt,
    ws: &mut Workspace,
    cost: &mut SensitivityCost,
    mut du_fields: Option<&mut Vec<Vec<f64>>>,
) -> Result<(Outputs, Vec<Outputs>), SensitivityError> {
    let st = at.st;
    set_plate(base, st, 0.0);
    let shifts = if ramp.stiffen {
        base.fe
            .stiffened_shifts(&st.u, &st.shifts, CONTACT_STIFFENING)
    } else {
        st.shifts.clone()
    };
    base.fe.set_contact_shifts(&shifts);
    base.fe
        .assemble(&st.u, &st.level, &mut ws.r0, Some(&mut ws.k))?;
    ws.rhs.iter_mut().for_each(|v| *v = 0.0);
    ws.lin.solve(&ws.k, &mut ws.rhs)?;
    cost.factorizations += 1;
    cost.residual_evaluations += 1;
    // ∂R/∂y_plate at the state, exact: the plate's motion enters −∂R/∂θ through it
    // rather than through the residual differences (see
    // `FeModel::plane_height_derivative`)
    let plate_term = match base.plate {
        Some(plate) if ramp.force_rig && !at.self_weight => {
            ws.dr_plate.iter_mut().for_each(|v| *v = 0.0);
            base.fe
                .plane_height_derivative(&st.u, plate, &mut ws.dr_plate);
            true
        }
        _ => false,
    };
    let y0 = outputs(base, &st.u, ramp.lf, ramp.scale);
    let raw_force = y0.force_n.map_or(0.0, |f| f / ramp.scale);
    let terms = StateTerms {
        at,
        shifts: &shifts,
        plate_term,
        raw_force,
        y0: &y0,
    };
    let mut derivatives = Vec::with_capacity(perturbed.len());
    for (pj, p) in perturbed.iter_mut().enumerate() {
        let d = match p.points.first().map(|q| &q.how) {
            None => Outputs::zero(&y0),
            // dF/ds = F/s
            Some(How::ForceScale) => Outputs {
                force_n: y0.force_n.map(|f| f / p.value),
                ..Outputs::zero(&y0)
            },
            Some(_) => {
                let du_field = du_fields.as_mut().map(|f| &mut f[pj]);
                parameter_derivative(ramp, base, p, &terms, ws, cost, du_field)?
            }
        };
        if at.self_weight && ramp.force_rig {
            p.plate_shift = d.tip_uy_mm
                - if p.acts_on(Target::PlateOffset) {
                    1.0
                } else {
                    0.0
                };
        }
        derivatives.push(d);
    }
    Ok((y0, derivatives))
}

/// The derivatives of the outputs at a state with respect to a parameter that perturbs the
/// model: `du/dθ` from `K du/dθ = −∂R/∂θ` with the state's factor (copied into `du_field`
/// when given), then the outputs along `(du/dθ, θ)`.
fn parameter_derivative(
    ramp: &RampSetup,
    base: &mut ActuatorModel,
    p: &mut Perturbation,
    terms: &StateTerms,
    ws: &mut Workspace,
    cost: &mut SensitivityCost,
    du_field: Option<&mut Vec<f64>>,
) -> Result<Outputs, SensitivityError> {
    // the plate follows the sagged tip (and the spring), not at P = 0
    let shift = if terms.at.self_weight {
        0.0
    } else if p.acts_on(Target::PlateCompliance) {
        p.plate_shift - terms.raw_force
    } else {
        p.plate_shift
    };
    clamp_face_motion(ramp, base, p, ws)?;
    residual_derivative(base, p, terms, shift, ws, cost)?;
    base.fe.restrict(&ws.acc, &mut ws.rhs);
    ws.lin.solve_factored(&mut ws.rhs)?;
    cost.solves += 1;
    base.fe.expand_increment(&ws.rhs, 1.0, &mut ws.du);
    for (d, s) in ws.du.iter_mut().zip(&ws.du_s) {
        *d += s;
    }
    if let Some(f) = du_field {
        f.clone_from(&ws.du);
    }
    Ok(outputs_along(ramp, base, p, terms, shift, ws))
}

/// The clamped face's motion per unit of `p` into `ws.du_s`: the rigid clamp's limit where
/// `p` takes it, zero otherwise.
fn clamp_face_motion(
    ramp: &RampSetup,
    base: &ActuatorModel,
    p: &Perturbation,
    ws: &mut Workspace,
) -> Result<(), SensitivityError> {
    if let (Some(How::RigidClamp(dirs)), Some(face)) =
        (p.points.first().map(|q| &q.how), &ramp.clamp)
    {
        face.face_motion(base, &ws.r0, *dirs, &mut ws.du_s)
            .map_err(|e| SensitivityError::Unsupported {
                parameter: p.parameter.name(),
                why: format!(
                    "the clamped face's mass matrix ({} nodes) did not solve in \
                     {} conjugate-gradient iterations",
                    e.nodes, e.iterations
                ),
            })?;
    } else {
        ws.du_s.iter_mut().for_each(|v| *v = 0.0);
    }
    Ok(())
}

/// `−∂R/∂θ` at fixed `u` into `ws.acc`, from the residuals at `p`'s points (the clamped face
/// moved along `ws.du_s`) and the plate moved by `shift`.
fn residual_derivative(
    base: &mut ActuatorModel,
    p: &mut Perturbation,
    terms: &StateTerms,
    shift: f64,
    ws: &mut Workspace,
    cost: &mut SensitivityCost,
) -> Result<(), SensitivityError> {
    let st = terms.at.st;
    for (a, r) in ws.acc.iter_mut().zip(&ws.r0) {
        *a = -p.weight0 * r;
    }
    if terms.plate_term {
        for (a, d) in ws.acc.iter_mut().zip(&ws.dr_plate) {
            *a -= shift * d;
        }
    }
    for q in &mut p.points {
        let (model, level, saved) = configure(base, &mut q.how, st, terms.shifts, 0.0);
        // the clamped face moved along its own motion (zero otherwise)
        for ((a, &u), &s) in ws.u2.iter_mut().zip(&st.u).zip(&ws.du_s) {
            *a = u + q.offset * s;
        }
        let assembled = model.fe.assemble(&ws.u2, &level, &mut ws.rp, None);
        restore(model, st, saved);
        assembled?;
        cost.residual_evaluations += 1;
        for (a, r) in ws.acc.iter_mut().zip(&ws.rp) {
            *a -= q.weight * r;
        }
    }
    Ok(())
}

/// The derivatives of the outputs: their slope along `(du/dθ, θ)` (`ws.du`) to `p`'s first
/// point, the plate moved along by `shift`.
fn outputs_along(
    ramp: &RampSetup,
    base: &mut ActuatorModel,
    p: &mut Perturbation,
    terms: &StateTerms,
    shift: f64,
    ws: &mut Workspace,
) -> Outputs {
    let st = terms.at.st;
    let q = &mut p.points[0];
    for ((a, &u), &d) in ws.u2.iter_mut().zip(&st.u).zip(&ws.du) {
        *a = u + q.offset * d;
    }
    let (model, _, saved) = configure(base, &mut q.how, st, terms.shifts, q.offset * shift);
    let y = outputs(model, &ws.u2, q.lf, ramp.scale);
    restore(model, st, saved);
    y.slope(terms.y0, q.offset)
}

/// The sensitivities of the differentiated parameters, their reported steps and the cost.
fn sensitivities_of(
    case: &Case,
    perturbed: &[Perturbation],
    steps: Vec<StepSensitivities>,
    cost: SensitivityCost,
) -> Sensitivities {
    let parameters = perturbed
        .iter()
        .map(|p| ParameterInfo {
            parameter: p.parameter,
            unit: p.parameter.unit().to_string(),
            value: p.value,
            step: p.h,
            how: p.describe().to_string(),
        })
        .collect();
    Sensitivities {
        format: SENSITIVITY_FORMAT.to_string(),
        version: SENSITIVITY_FORMAT_VERSION,
        mode: case.mode,
        parameters,
        steps,
        cost,
    }
}

/// The model of a point at state `st` (gap shifts `shifts`, plate moved by `plate_dy`) and
/// its load level; the base model's material is swapped in if the point has its own, and
/// returned for [`restore`].
fn configure<'a>(
    base: &'a mut ActuatorModel,
    how: &'a mut How,
    st: &ConvergedState,
    shifts: &[f64],
    plate_dy: f64,
) -> (&'a mut ActuatorModel, LoadLevel, Option<Material>) {
    let mut level = st.level;
    match how {
        How::Pressure(e) => {
            level[LoadFactor::PRESSURE] = BAR * e.effective_pressure_bar(st.pressure_bar)
        }
        How::Gravity(f) => level[LoadFactor::GRAVITY] *= *f,
        _ => {}
    }
    let (model, saved) = match how {
        How::Model(m) => {
            m.fe.set_contact_shifts(shifts);
            (&mut **m, None)
        }
        How::Material(mat) => {
            let old = std::mem::replace(&mut base.fe.material, mat.clone());
            (base, Some(old))
        }
        _ => (base, None),
    };
    set_plate(model, st, plate_dy);
    (model, level, saved)
}

/// Undoes [`configure`]: the material back, the plate where the state had it.
fn restore(model: &mut ActuatorModel, st: &ConvergedState, saved: Option<Material>) {
    if let Some(old) = saved {
        model.fe.material = old;
    }
    set_plate(model, st, 0.0);
}

/// Puts the plate of `model` where state `st` had it, moved by `dy` (mm).
fn set_plate(model: &mut ActuatorModel, st: &ConvergedState, dy: f64) {
    if let (Some(p), Some(y)) = (model.plate, st.plate_y) {
        model.fe.planes[p].point[1] = y + dy;
    }
}
