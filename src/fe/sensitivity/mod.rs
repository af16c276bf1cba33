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
//! How each parameter enters `R` (an effect declares it,
//! [`CaseEffect::differentiation`](crate::fe::effects::CaseEffect::differentiation); by default
//! its target's, [`Target::differentiation`]; the library's are):
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
mod differentiate;
mod params;

use serde::{Deserialize, Serialize};
use thiserror::Error;

pub use differentiate::{
    sensitivities_with, sensitivities_with_fields, simulate_with_sensitivities, WithFields,
};
pub use params::{OgdenParameter, Parameter};

use crate::fe::effects::{Acts, Differentiation, Effect, EffectError, Effects, Target};
use crate::fe::element::ElementError;
use crate::fe::geometry::{Design, GeometryError};
use crate::fe::material::{Material, MaterialError, MaterialLaw, Ogden2};
use crate::fe::mesh::MeshMoveError;
use crate::fe::simulate::{marker_list, ActuatorModel, Case, Mode, SimulateError};
use crate::fe::solver::SolverError;

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
    /// Whether the parameter is an effect on `target`.
    fn acts_on(&self, target: Target) -> bool {
        matches!(self.parameter, Parameter::Effect(e) if e.target() == target)
    }

    fn describe(&self) -> &'static str {
        self.points
            .first()
            .map_or("no effect on this rig", |p| p.how.describe())
    }
}

/// The material of the case with Ogden parameter `k` set to `value`, as printed.
fn material_with(case: &Case, k: OgdenParameter, value: f64) -> Result<Material, SensitivityError> {
    let m = &case.material;
    let mut p = m
        .ogden_set()
        .ok_or(SensitivityError::Unsupported {
            parameter: "material",
            why: "the material is not a second-order Ogden law".into(),
        })?
        .as_array();
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
                let value = case
                    .material
                    .ogden_set()
                    .map_or(0.0, |p| p.as_array()[k.index()]);
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
    // the force rig's own effects move nothing in bending
    if e.acts_on() == Acts::Force && case.mode != Mode::Force {
        return Ok(None);
    }
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
    let how = match e.differentiation() {
        Differentiation::MovedMesh => {
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
        Differentiation::ClampSprings => match e.target() {
            Target::Clamp(dirs) if rigid_clamp(&case.effects, dirs) => How::RigidClamp(dirs),
            _ => other_model(base.mesh.clone(), design)?,
        },
        Differentiation::LoadLevel if e.target() == Target::Gravity => How::Gravity(at / value),
        Differentiation::LoadLevel => How::Pressure(effects),
        Differentiation::Material => How::Material(effects.printed_material(&case.material)?),
        Differentiation::Plate => How::Plate,
        Differentiation::Reading => How::ForceScale,
        Differentiation::Unsupported => return Err(not_differentiated(e)),
    };
    Ok(Some((how, lf)))
}

/// Whether the clamp is rigid in every direction of `dirs` (no spring there).
fn rigid_clamp(effects: &Effects, dirs: [bool; 3]) -> bool {
    dirs.iter()
        .zip(effects.clamp_springs())
        .all(|(&on, spring)| !on || spring.is_none())
}

/// The error of an effect that declares no differentiation.
fn not_differentiated(e: Effect) -> SensitivityError {
    SensitivityError::Unsupported {
        parameter: e.name(),
        why: "the effect declares no differentiation (Differentiation::Unsupported)".into(),
    }
}
