//! Sensitivities of the measured outputs to the material and to every effect, by direct
//! differentiation of the converged equilibrium (not by re-running the ramp).
//!
//! At a converged state the free unknowns satisfy `R(u; θ) = 0`. Along a parameter `θ`:
//!
//! ```text
//!   K du/dθ = −∂R/∂θ|_u          K = ∂R/∂u, the consistent tangent at the state
//!   dy/dθ   = ∂y/∂u · du/dθ + ∂y/∂θ|_u
//! ```
//!
//! Per reported state: one tangent assembly and one factorisation. Per parameter: `∂R/∂θ`
//! from the residuals at fixed `u` at two nearby values of `θ` (semi-analytic), one solve
//! with the factor, and `dy/dθ` as the difference of the outputs along `(du/dθ, θ)` (markers
//! are linear in `u`; the angle and the blocked force are evaluated, the force from the
//! plate's contact faces alone). The residual differences are central,
//! `(R(θ + h) − R(θ − h))/2h`, or one-sided of second order where `θ − h` leaves the range
//! (`(−3R(θ) + 4R(θ + h) − R(θ + 2h))/2h`); `h = 10⁻⁶ |θ|` for the material and `10⁻⁶`
//! times the width of an effect's range. Second order matters: `∂R/∂θ` of a dimension is
//! mostly self-equilibrated wall stress (norm ≈ 4·10³ N/mm on the coarse N = 9 actuator)
//! whose small unbalanced part bends an actuator that is soft in bending (`K`'s smallest
//! eigenvalues ≈ 10⁻⁶ of its largest), and a forward difference's relative error of 10⁻⁷
//! already moved `d tip/d wall_bias_bellows` by 12 %.
//!
//! How each parameter enters `R`:
//!
//! | parameter | perturbed |
//! |---|---|
//! | `mu1`, `alpha1`, `mu2`, `alpha2` | the material (`κ` follows `μ0` at the material's bulk ratio; an `anisotropy` fibre keeps `k = a·μ0`) |
//! | `wall_bias`, `wall_bias_bellows`, `wall_bias_skin`, `gap_bias`, `base_bias`, `duct_bias`, `free_length_bias` | the mesh, moved onto the perturbed design ([`ActuatorMesh::moved`](crate::fe::mesh::ActuatorMesh::moved)): the derivative of the discrete model along a smooth motion of its nodes; the markers' local coordinates and the free length of the angle move with it |
//! | `pressure_loss`, `pressure_offset` | the effective pressure of the level |
//! | `density` | the gravity factor of the level |
//! | `anisotropy` | the fibre term of the material |
//! | `clamp_compliance`, `clamp_shear_compliance` | at `c > 0` the springs' stiffness `1/c`; at `c = 0` (rigid, the neutral value) the rigid-clamp limit (module `clamp`): the clamped face moves by `−M⁻¹R_s` per unit `c` |
//! | `plate_offset`, `plate_compliance` | the plate's height only |
//! | `force_scale` | the reported force only: `dF/ds = F/s` |
//!
//! **The blocked-force plate.** The plate is placed at `y_p = y_tip(P = 0) − 5 − offset`
//! under the sagged tip, and (on a spring) moves by `−c·F`. Every parameter that moves the
//! sagged tip therefore moves the plate: the self-weight state (`P = 0`) is differentiated
//! first, and at every pressure the plate is moved by
//! `dy_p/dθ = dy_tip(P = 0)/dθ − ∂offset/∂θ − F ∂c/∂θ` along with the parameter.
//! Derivatives at a compliant plate (`plate_compliance > 0`) are not supported (the plate's
//! own fixed point would have to be differentiated too); ask for them at `c = 0`.
//!
//! **Contact.** The augmented-Lagrangian solver converges to states where every touching
//! point sits at zero gap with whatever pressure that takes; a perturbation keeps it there.
//! Linearising the penalty with the state's multipliers held fixed would instead let it sink
//! into a spring of `ε` = 20 MPa/mm per unit area, not stiff against a bellow wall or the
//! tip on the plate. The linearisation therefore uses the contact law
//! [`CONTACT_STIFFENING`] times stiffer with its shifts moved so that every contact force at
//! the state is unchanged
//! ([`FeModel::scale_contact`](crate::fe::assembly::FeModel::scale_contact),
//! [`FeModel::stiffened_shifts`](crate::fe::assembly::FeModel::stiffened_shifts)): touching
//! points are held, open ones stay open. The plain penalty (`augmented_updates = 0`) and the
//! minimisation solver's barrier are the models themselves and are linearised as they are.
//!
//! ```no_run
//! use surrogate::fe::sensitivity::{simulate_with_sensitivities, Parameter};
//! # fn case() -> surrogate::fe::simulate::Case { unimplemented!() }
//! let case = case();
//! let (response, sens) =
//!     simulate_with_sensitivities(&case, &Parameter::parse_list("mu1,wall_bias")?, |_, _| {})?;
//! let d = sens.derivative(response.steps.len() - 1, Parameter::parse_list("wall_bias")?[0]);
//! println!("d tip Uy / d wall_bias = {:.3} mm/mm", d.unwrap().tip_uy_mm);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod clamp;
mod params;

use std::time::Instant;

use serde::{Deserialize, Serialize};
use thiserror::Error;

pub use params::{OgdenParameter, Parameter};

use crate::fe::assembly::LoadLevel;
use crate::fe::effects::{Effect, EffectError, Effects};
use crate::fe::element::ElementError;
use crate::fe::geometry::{Design, GeometryError};
use crate::fe::material::{Material, MaterialError, MaterialLaw, Ogden2};
use crate::fe::mesh::MeshMoveError;
use crate::fe::simulate::{
    marker_list, run, run_warm, ActuatorModel, Case, ConvergedState, Mode, Ran, Response,
    SimulateError, StepResult, BAR,
};
use crate::fe::solver::{LinearSolver, NonlinearProblem, SolverError};
use crate::fe::warm_start::{FieldSensitivities, WarmStart, WarmStartError};

/// Format name of the sensitivity file ([`Sensitivities`]).
pub const SENSITIVITY_FORMAT: &str = "surrogate-sensitivities";

/// Version of the sensitivity file ([`Sensitivities`]).
pub const SENSITIVITY_FORMAT_VERSION: u32 = 1;

/// Relative step of the residual differences.
pub const RELATIVE_STEP: f64 = 1e-6;

/// Factor on the contact stiffness of the linearisation about an augmented-Lagrangian state
/// ([`FeModel::scale_contact`](crate::fe::assembly::FeModel::scale_contact)).
///
/// Chosen against central finite differences of full augmented-Lagrangian runs on the coarse
/// N = 11, T = 1.6 actuator in the force rig at 1, 2 and 3 bar (`density` ±0.1, `anisotropy`
/// ±0.05, `clamp_compliance` 0.005/0.01; `fe_reference/sensitivities/README.md`): the blocked
/// force's derivatives are within 2.2 % at 10, up to 19 % off at 10² (`d F/d density` −0.164
/// against −0.138 at 3 bar) and up to 46 % off with the plain penalty (factor 1). The tip
/// agrees within 0.5 % at every factor. Stiffer than 10 the law's smoothing `δ/factor`
/// narrows and its slopes `∝ factor` hold the points at the rim of a contact patch, which the
/// augmented Lagrangian lets lift off.
pub const CONTACT_STIFFENING: f64 = 10.0;

/// Revision of the differentiation method: part of the cache key of a ramp with
/// sensitivities, so that cached sensitivities of an older method are recomputed.
/// 2: the force plate's motion enters `∂R/∂θ` exactly
/// ([`FeModel::plane_height_derivative`](crate::fe::assembly::FeModel::plane_height_derivative)),
/// and [`CONTACT_STIFFENING`] 10 (was 10²): the old method's `d F/d density` at N = 11,
/// T = 1.6, 1 bar was −24.6 N against −0.112 N from full runs.
pub const SENSITIVITY_METHOD: u32 = 2;

/// Errors of the sensitivities.
#[derive(Debug, Error)]
pub enum SensitivityError {
    /// The ramp itself.
    #[error(transparent)]
    Simulate(#[from] SimulateError),
    /// A name that is not a parameter.
    #[error("unknown parameter '{name}': expected all, or a comma-separated list of {known}")]
    Unknown {
        /// The name given.
        name: String,
        /// The names there are.
        known: String,
    },
    /// A parameter listed twice.
    #[error("parameter '{name}' is listed twice")]
    Duplicate {
        /// The name.
        name: String,
    },
    /// A parameter that cannot be differentiated for this case.
    #[error("{parameter}: {why}")]
    Unsupported {
        /// The parameter.
        parameter: &'static str,
        /// Why.
        why: String,
    },
    /// A dimension the mesh cannot follow.
    #[error("{parameter}: the mesh cannot be moved onto the perturbed design: {source}")]
    Move {
        /// The parameter.
        parameter: &'static str,
        /// Why.
        source: MeshMoveError,
    },
    /// The linear solve.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// An element at the state.
    #[error(transparent)]
    Element(#[from] ElementError),
    /// A perturbed material.
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// A perturbed effect.
    #[error(transparent)]
    Effect(#[from] EffectError),
    /// A perturbed design.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
}

/// The measured outputs of a state, or their derivatives with respect to one parameter
/// (then each field is per unit of the parameter: mm/unit, deg/unit, N/unit).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outputs {
    /// Tip `Uz = −Δz` (mm).
    pub tip_uz_mm: f64,
    /// Tip `Uy = Δy` (mm).
    pub tip_uy_mm: f64,
    /// Bending angle (deg).
    pub angle_deg: f64,
    /// Markers 1..9, `[Uz, Uy]` (mm), written as `{"uz_mm", "uy_mm"}`.
    #[serde(with = "marker_list")]
    pub markers: Vec<[f64; 2]>,
    /// Blocked force (N, whole actuator), in [`Mode::Force`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_n: Option<f64>,
}

impl Outputs {
    /// `(self − base)/h`.
    fn slope(&self, base: &Outputs, h: f64) -> Outputs {
        Outputs {
            tip_uz_mm: (self.tip_uz_mm - base.tip_uz_mm) / h,
            tip_uy_mm: (self.tip_uy_mm - base.tip_uy_mm) / h,
            angle_deg: (self.angle_deg - base.angle_deg) / h,
            markers: self
                .markers
                .iter()
                .zip(&base.markers)
                .map(|(a, b)| [(a[0] - b[0]) / h, (a[1] - b[1]) / h])
                .collect(),
            force_n: self.force_n.zip(base.force_n).map(|(a, b)| (a - b) / h),
        }
    }

    /// All zero, shaped like `like`.
    fn zero(like: &Outputs) -> Outputs {
        Outputs {
            tip_uz_mm: 0.0,
            tip_uy_mm: 0.0,
            angle_deg: 0.0,
            markers: vec![[0.0; 2]; like.markers.len()],
            force_n: like.force_n.map(|_| 0.0),
        }
    }

    /// The outputs as one flat list, named (`tip_uz_mm`, …, `marker9_uy_mm`, `force_n`).
    pub fn named(&self) -> Vec<(String, f64)> {
        let mut v = vec![
            ("tip_uz_mm".to_string(), self.tip_uz_mm),
            ("tip_uy_mm".to_string(), self.tip_uy_mm),
            ("angle_deg".to_string(), self.angle_deg),
        ];
        for (k, m) in self.markers.iter().enumerate() {
            v.push((format!("marker{}_uz_mm", k + 1), m[0]));
            v.push((format!("marker{}_uy_mm", k + 1), m[1]));
        }
        if let Some(f) = self.force_n {
            v.push(("force_n".to_string(), f));
        }
        v
    }
}

/// A parameter as it was differentiated.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ParameterInfo {
    /// The parameter (written as its name).
    pub parameter: Parameter,
    /// Its unit.
    pub unit: String,
    /// Its value in the case.
    pub value: f64,
    /// The residual's difference step `h` (negative: backwards).
    pub step: f64,
    /// How it enters the model.
    pub how: String,
}

/// The outputs of one reported state and their derivatives.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct StepSensitivities {
    /// Gauge pressure (bar).
    pub pressure_bar: f64,
    /// The outputs.
    pub values: Outputs,
    /// Their derivatives, one per parameter in the order of [`Sensitivities::parameters`].
    pub derivatives: Vec<Outputs>,
}

/// What the sensitivities cost next to the ramp.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct SensitivityCost {
    /// The ramp's wall time (s).
    pub ramp_s: f64,
    /// The sensitivities' wall time (s), setting up the perturbed models included.
    pub sensitivity_s: f64,
    /// Of which: building the perturbed models (moved meshes, other clamps) (s).
    pub setup_s: f64,
    /// `sensitivity_s / ramp_s`.
    pub overhead: f64,
    /// Tangent factorisations of the sensitivities (one per differentiated state).
    pub factorizations: usize,
    /// Residual evaluations of the sensitivities.
    pub residual_evaluations: usize,
    /// Solves with an existing factor.
    pub solves: usize,
}

/// The sensitivities of a ramp.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Sensitivities {
    /// `surrogate-sensitivities`.
    pub format: String,
    /// [`SENSITIVITY_FORMAT_VERSION`].
    pub version: u32,
    /// The rig.
    pub mode: Mode,
    /// The parameters.
    pub parameters: Vec<ParameterInfo>,
    /// One per reported step of the ramp.
    pub steps: Vec<StepSensitivities>,
    /// The cost.
    pub cost: SensitivityCost,
}

impl Sensitivities {
    /// The derivatives at reported step `step` with respect to `parameter`.
    pub fn derivative(&self, step: usize, parameter: Parameter) -> Option<&Outputs> {
        let j = self
            .parameters
            .iter()
            .position(|p| p.parameter == parameter)?;
        self.steps.get(step).map(|s| &s.derivatives[j])
    }
}

/// How a parameter perturbs the model.
enum How {
    /// The base model with this material.
    Material(Material),
    /// A model of its own (a moved mesh, other clamp springs).
    Model(Box<ActuatorModel>),
    /// The level's effective pressure from these effects.
    Pressure(Effects),
    /// The level's gravity factor scaled by this.
    Gravity(f64),
    /// The rigid clamp's limit in these directions: the clamped face moved by `a·du_s/dc`
    /// at the point's offset `a`.
    RigidClamp([bool; 3]),
    /// The plate's height only.
    Plate,
    /// The reported force only.
    ForceScale,
}

impl How {
    fn describe(&self) -> &'static str {
        match self {
            How::Material(_) => "material",
            How::Model(_) => "perturbed model (moved mesh or clamp springs)",
            How::Pressure(_) => "effective pressure",
            How::Gravity(_) => "gravity factor",
            How::RigidClamp(_) => "rigid-clamp limit: clamped face moved by -M^-1 R_s",
            How::Plate => "plate height",
            How::ForceScale => "reported force",
        }
    }
}

/// The model at one offset `θ + a` of a parameter.
struct Point {
    /// The offset `a`.
    offset: f64,
    /// Its weight in `∂R/∂θ ≈ Σ wᵢ R(θ + aᵢ) + w₀ R(θ)`.
    weight: f64,
    /// How the model is perturbed there.
    how: How,
    /// Free length of the design there (mm).
    lf: f64,
}

/// One parameter, ready to be differentiated.
struct Perturbation {
    parameter: Parameter,
    value: f64,
    h: f64,
    /// Two points: `θ ± h` (central) or `θ + h, θ + 2h` (one-sided, second order, where
    /// `θ − h` leaves the range; mirrored at the top).
    points: Vec<Point>,
    /// `w₀`: the weight of the state's own residual.
    weight0: f64,
    /// `dy_p/dθ` of the plate from the self-weight state (mm/unit), once known.
    plate_shift: f64,
}

impl Perturbation {
    fn describe(&self) -> &'static str {
        self.points
            .first()
            .map_or("no effect on this rig", |p| p.how.describe())
    }
}

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
            Parameter::Material(_) if case.material.ogden_params().is_none() => {
                return Err(SensitivityError::Unsupported {
                    parameter: p.name(),
                    why: "the material is not a second-order Ogden law".into(),
                })
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

/// The material of the case with Ogden parameter `k` set to `value`, as printed.
fn material_with(case: &Case, k: OgdenParameter, value: f64) -> Result<Material, SensitivityError> {
    let m = &case.material;
    let mut p = m.ogden_params().ok_or(SensitivityError::Unsupported {
        parameter: "material",
        why: "the material is not a second-order Ogden law".into(),
    })?;
    p[k.index()] = value;
    let ratio = m.kappa / m.mu0();
    let law = MaterialLaw::Ogden(Ogden2::new(p[0], p[1], p[2], p[3])?);
    let nominal = Material::new(law, ratio)?;
    Ok(case.effects.printed_material(&nominal)?)
}

/// Sets up how each parameter perturbs the model.
fn perturbations(
    case: &Case,
    base: &ActuatorModel,
    design: &Design,
    parameters: &[Parameter],
) -> Result<Vec<Perturbation>, SensitivityError> {
    let material = case.effects.printed_material(&case.material)?;
    let mut out = Vec::with_capacity(parameters.len());
    for &parameter in parameters {
        let (value, h, range) = match parameter {
            Parameter::Material(k) => {
                let value = case.material.ogden_params().map_or(0.0, |p| p[k.index()]);
                let h = RELATIVE_STEP * value.abs().max(1e-3);
                (value, h, (f64::NEG_INFINITY, f64::INFINITY))
            }
            Parameter::Effect(e) => {
                let info = e.info();
                let value = case.effects.get(e);
                (
                    value,
                    RELATIVE_STEP * (info.range.1 - info.range.0),
                    info.range,
                )
            }
        };
        // central where θ ± h stay in the range, else one-sided of second order
        let (offsets, weights, weight0) = if value - h < range.0 {
            ([h, 2.0 * h], [2.0 / h, -0.5 / h], -1.5 / h)
        } else if value + h > range.1 {
            ([-h, -2.0 * h], [-2.0 / h, 0.5 / h], 1.5 / h)
        } else {
            ([h, -h], [0.5 / h, -0.5 / h], 0.0)
        };
        let mut points = Vec::with_capacity(2);
        for (offset, weight) in offsets.into_iter().zip(weights) {
            let Some((how, lf)) = point(case, base, design, &material, parameter, value + offset)?
            else {
                break;
            };
            points.push(Point {
                offset,
                weight,
                how,
                lf,
            });
        }
        out.push(Perturbation {
            parameter,
            value,
            h,
            points,
            weight0,
            plate_shift: 0.0,
        });
    }
    Ok(out)
}

/// How the model changes when `parameter` takes `at`, and the free length there; `None` for
/// a parameter that changes nothing this rig measures.
fn point(
    case: &Case,
    base: &ActuatorModel,
    design: &Design,
    material: &Material,
    parameter: Parameter,
    at: f64,
) -> Result<Option<(How, f64)>, SensitivityError> {
    let lf = design.free_length();
    let e = match parameter {
        Parameter::Material(k) => {
            return Ok(Some((How::Material(material_with(case, k, at)?), lf)))
        }
        Parameter::Effect(e) => e,
    };
    let info = e.info();
    let value = case.effects.get(e);
    let effects = case.effects.clone().with(e, at)?;
    let other_model = |mesh, design: &Design| -> Result<How, SensitivityError> {
        Ok(How::Model(Box::new(base.variant(
            mesh,
            design,
            material,
            (case.mode, &case.contact),
            &effects,
        )?)))
    };
    let how = match e {
        Effect::WallBias
        | Effect::WallBiasBellows
        | Effect::WallBiasSkin
        | Effect::WallBiasSide
        | Effect::GapBias
        | Effect::BaseBias
        | Effect::DuctBias
        | Effect::FreeLengthBias => {
            let moved: Design = effects.printed_design(case.design.params()).validate()?;
            let mesh =
                base.mesh
                    .moved(design, &moved)
                    .map_err(|source| SensitivityError::Move {
                        parameter: info.name,
                        source,
                    })?;
            return Ok(Some((other_model(mesh, &moved)?, moved.free_length())));
        }
        Effect::ClampCompliance | Effect::ClampShearCompliance if value == 0.0 => {
            let normal = e == Effect::ClampCompliance;
            How::RigidClamp([!normal, !normal, normal])
        }
        Effect::ClampCompliance | Effect::ClampShearCompliance => {
            other_model(base.mesh.clone(), design)?
        }
        Effect::PressureLoss | Effect::PressureOffset => How::Pressure(effects),
        Effect::Density => How::Gravity(at / value),
        Effect::Anisotropy => How::Material(effects.printed_material(&case.material)?),
        Effect::PlateOffset | Effect::PlateCompliance if case.mode == Mode::Force => How::Plate,
        Effect::ForceScale if case.mode == Mode::Force => How::ForceScale,
        Effect::PlateOffset | Effect::PlateCompliance | Effect::ForceScale => return Ok(None),
    };
    Ok(Some((how, lf)))
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
            Some(How::ForceScale) => Outputs {
                force_n: Some(raw_force),
                ..Outputs::zero(&y0)
            },
            Some(_) => {
                let du_field = du_fields.as_mut().map(|f| &mut f[pj]);
                parameter_derivative(ramp, base, p, &terms, ws, cost, du_field)?
            }
        };
        if at.self_weight && ramp.force_rig {
            p.plate_shift = d.tip_uy_mm
                - if p.parameter == Parameter::Effect(Effect::PlateOffset) {
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
    } else if p.parameter == Parameter::Effect(Effect::PlateCompliance) {
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
        How::Pressure(e) => level.pressure = BAR * e.effective_pressure_bar(st.pressure_bar),
        How::Gravity(f) => level.gravity *= *f,
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
