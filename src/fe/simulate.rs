//! `simulate(&Case) -> Response`: mesh → model → load path → measurements.
//!
//! The load path: gravity is applied first (the state reported at P = 0), then the pressure is
//! ramped through the requested values. Outputs follow the SPEC's conventions:
//! `Uz = −Δz`, `Uy = Δy` of the tip (marker 9), bending angle `α = atan2(−y_tip, z_tip)`
//! measured from the support point (W/2, 0, 0).

use std::time::Instant;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::assembly::terms::barrier::IpcBarrier;
use super::assembly::terms::foundation::Foundation;
use super::assembly::{pair_couplings, Constraint, FeModel, LoadLevel};
use super::contact::{pair_orientation, ContactError, FacePair, PairSettings, RigidPlane};
use super::effects::{EffectError, Effects};
use super::element::{shape, ElementError};
use super::geometry::{Design, GeometryError, Region};
use super::material::Material;
use super::mesh::{ActuatorMesh, GapSide, MeshOptions};
use super::solver::{
    solve_path_from, solve_path_guided, PathState, SolverError, SolverKind, SolverSettings,
    StepReport,
};
pub use super::warm_start::ConvergedState;
use super::warm_start::WarmStart;

/// TPU density (t/mm³).
pub const DENSITY: f64 = 1.19e-9;
/// Gravitational acceleration (mm/s²), acting along −y.
pub const GRAVITY: f64 = 9810.0;
/// 1 bar in MPa.
pub const BAR: f64 = 0.1;
/// Largest pressure accepted (bar).
pub const MAX_PRESSURE_BAR: f64 = 10.0;
/// Distance of the force plate below the tip of the unpressurised actuator (mm, SPEC).
pub const PLATE_OFFSET: f64 = 5.0;

/// Tolerance on the compliant plate's position `|y − (y0 − c·F)|` (mm).
pub const PLATE_SETTLE_MM: f64 = 1e-4;

/// Re-solves allowed per load level for the compliant plate to settle.
pub const PLATE_SETTLE_ITERATIONS: usize = 30;
/// The plate lies under z ∈ [Lf − 25, Lf + 5] (mm, SPEC).
pub const PLATE_REACH: (f64, f64) = (25.0, 5.0);

/// Revision of the blocked-force model, part of the key of cached force ramps
/// ([`crate::calibrate::baseline`]): 2 = the plate meets every outer face of the tip region
/// (1: the bottom layer only, which let a tip turned past vertical pass through the plate).
pub const FORCE_MODEL_REVISION: u32 = 2;

/// What the rig measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Free bending: markers, tip, angle.
    #[default]
    Bending,
    /// Blocked force: a rigid plate 5 mm below the tip of the actuator hanging unpressurised
    /// under its own weight; the plate's reaction per pressure step. The plate is an infinite
    /// frictionless plane; every outer face of the tip region (reference z ≥ Lf − 25: bottom
    /// layer, end cap, bellow flanks and tops, side wall) is searched against it, so a tip
    /// that turns past vertical rests on its end cap instead of passing through the plate.
    Force,
}

/// Contact settings of a case: bellow-to-bellow, first bellow against the clamp block, and
/// the tip against the force plate (penalty barrier, see [`super::contact`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactSettings {
    /// Contact on/off (bellow-to-bellow and clamp; the plate of [`Mode::Force`] is always on).
    pub enabled: bool,
    /// Penalty stiffness ε (MPa/mm).
    pub stiffness: f64,
    /// Smoothing width δ (mm).
    pub smoothing: f64,
    /// Bellow walls: gap to the closest point of the facing wall (frictionless under any
    /// sliding) instead of between points of equal reference position. Off by default: on the
    /// actuator the two agree to 0.01 % (`fe_reference/contact/README.md`), and the projection
    /// stays on the paired face (its polynomial extended), which suits small sliding only.
    /// Not written when off, so plans written before it keep their hash.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub closest_point: bool,
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            stiffness: 20.0,
            smoothing: 0.05,
            closest_point: false,
        }
    }
}

impl ContactSettings {
    /// Checks the ranges: ε ∈ [1, 1e5] MPa/mm, δ ∈ [0, 0.5] mm.
    ///
    /// # Errors
    /// [`ContactError::OutOfRange`] naming the setting.
    pub fn validate(&self) -> Result<(), ContactError> {
        if !(self.stiffness.is_finite() && (1.0..=1e5).contains(&self.stiffness)) {
            return Err(ContactError::OutOfRange {
                field: "contact stiffness",
                value: self.stiffness,
                expected: "a penalty stiffness in [1, 1e5] MPa/mm".into(),
            });
        }
        if !(self.smoothing.is_finite() && (0.0..=0.5).contains(&self.smoothing)) {
            return Err(ContactError::OutOfRange {
                field: "contact smoothing",
                value: self.smoothing,
                expected: "a smoothing width in [0, 0.5] mm".into(),
            });
        }
        Ok(())
    }
}

/// Errors of a simulation.
#[derive(Debug, Error)]
pub enum SimulateError {
    /// Invalid design.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// A geometry preset that cannot build the design ([`crate::fe::preset`]).
    #[error(transparent)]
    Preset(#[from] crate::fe::preset::PresetError),
    /// Invalid mesh.
    #[error(transparent)]
    Element(#[from] ElementError),
    /// The solver stopped.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// Invalid contact settings.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// An invalid effect.
    #[error(transparent)]
    Effect(#[from] EffectError),
    /// An invalid material (including one an effect makes, e.g. anisotropy).
    #[error(transparent)]
    Material(#[from] crate::fe::material::MaterialError),
    /// The plate on a spring (`plate_compliance`) did not settle at a pressure.
    #[error(
        "the compliant plate did not settle at {pressure_bar} bar: after {iterations} re-solves \
         its position is {mismatch_mm:.2e} mm from c·F (expected below {PLATE_SETTLE_MM} mm)"
    )]
    PlateNotSettled {
        /// The gauge pressure (bar).
        pressure_bar: f64,
        /// Re-solves made.
        iterations: usize,
        /// Last `|y − (y0 − c·F)|` (mm).
        mismatch_mm: f64,
    },
    /// A setting out of range (solver, mesh).
    #[error(transparent)]
    Setting(#[from] crate::fe::InvalidSetting),
    /// Invalid pressure list.
    #[error("pressure {value} bar at position {} of the list is invalid: expected {expected}", .index + 1)]
    Pressure {
        /// Position in the list, from 0 (messages count from 1).
        index: usize,
        /// The value.
        value: f64,
        /// What was expected.
        expected: String,
    },
    /// A pressure list entry that is not a number, or a malformed `max:step`.
    #[error("pressure list {list:?}: {what}")]
    PressureText {
        /// The list as given.
        list: String,
        /// What is wrong, with the position counted from 1.
        what: String,
    },
}

/// One simulation: design, material, pressures and discretisation.
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// The design.
    pub design: Design,
    /// The material.
    pub material: Material,
    /// Pressures (bar) at which results are reported, increasing, ≥ 0.
    pub pressures_bar: Vec<f64>,
    /// Self-weight on/off.
    pub gravity: bool,
    /// Mesh options.
    pub mesh: MeshOptions,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Bending or blocked force.
    pub mode: Mode,
    /// Contact settings.
    pub contact: ContactSettings,
    /// Physics beyond the nominal model ([`super::effects`]); neutral by default, and then
    /// not written.
    #[serde(skip_serializing_if = "Effects::is_neutral")]
    pub effects: Effects,
}

impl Case {
    /// Checks the case before any FE work: pressures ([`validate_pressures`]), mesh options,
    /// solver settings and contact settings. The design and the material validate themselves
    /// when they are built ([`DesignParams::validate`](super::geometry::DesignParams::validate),
    /// [`Material::new`]).
    ///
    /// # Errors
    /// [`SimulateError::Pressure`], [`SimulateError::Setting`] (field `mesh.…` or
    /// `solver.…`) or [`SimulateError::Contact`] for the first invalid entry.
    pub fn validate(&self) -> Result<(), SimulateError> {
        validate_pressures(&self.pressures_bar)?;
        self.mesh.validate().map_err(|e| e.within("mesh."))?;
        self.solver.validate().map_err(|e| e.within("solver."))?;
        self.contact.validate()?;
        self.printed_design()?;
        Ok(())
    }

    /// The design as printed: the nominal design with the effects' biases
    /// ([`Effects::printed_design`]); the nominal design itself when they are neutral.
    ///
    /// # Errors
    /// [`SimulateError::Geometry`] when a bias leaves an invalid design (e.g. no cavity).
    pub fn printed_design(&self) -> Result<Design, SimulateError> {
        if self.effects.is_neutral() {
            return Ok(self.design.clone());
        }
        Ok(self
            .effects
            .printed_design(self.design.params())
            .validate()?)
    }
}

/// A marker's displacement in the tables' convention, as every JSON output writes it:
/// `Uz = −Δz` (positive towards the support), `Uy = Δy` (negative downwards), mm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// `Uz = −Δz`, mm.
    pub uz_mm: f64,
    /// `Uy = Δy`, mm.
    pub uy_mm: f64,
}

impl From<[f64; 2]> for Marker {
    fn from(m: [f64; 2]) -> Self {
        Marker {
            uz_mm: m[0],
            uy_mm: m[1],
        }
    }
}

/// Serde form of a marker list: written as [`Marker`] objects, read from objects or pairs.
pub mod marker_list {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::Marker;

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Either {
        Object(Marker),
        Pair([f64; 2]),
    }

    /// Writes `[{"uz_mm", "uy_mm"}, …]`.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer>(m: &[[f64; 2]], s: S) -> Result<S::Ok, S::Error> {
        let v: Vec<Marker> = m.iter().map(|&p| Marker::from(p)).collect();
        v.serialize(s)
    }

    /// Reads objects `{"uz_mm", "uy_mm"}` or pairs `[Uz, Uy]`.
    ///
    /// # Errors
    /// Neither form.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
        let v: Vec<Either> = Vec::deserialize(d)?;
        Ok(v.into_iter()
            .map(|e| match e {
                Either::Object(m) => [m.uz_mm, m.uy_mm],
                Either::Pair(p) => p,
            })
            .collect())
    }
}

/// Results of one pressure step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepResult {
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Tip Uz = −Δz (mm).
    pub tip_uz_mm: f64,
    /// Tip Uy = Δy (mm).
    pub tip_uy_mm: f64,
    /// Bending angle (deg).
    pub angle_deg: f64,
    /// Markers 1..9: `[Uz, Uy]` (mm); written as `[{"uz_mm": …, "uy_mm": …}, …]`
    /// ([`Marker`], the form `predict` writes too); the older `[[Uz, Uy], …]` is still read.
    #[serde(with = "marker_list")]
    pub markers: Vec<[f64; 2]>,
    /// Newton iterations to reach this step.
    pub newton_iterations: usize,
    /// The step was solved directly from a neighbouring case's state ([`run_warm`]).
    #[serde(default, skip_serializing_if = "is_false")]
    pub warm_start: bool,
    /// Load substeps.
    pub substeps: usize,
    /// Cut-backs.
    pub cutbacks: usize,
    /// Final normalised residual.
    pub residual: f64,
    /// Whether the step converged.
    pub converged: bool,
    /// Smallest deformed gap between neighbouring bellows (mm; negative = interpenetration).
    pub min_gap_mm: f64,
    /// Gap (or clamp gap) where it occurs.
    pub min_gap_at: String,
    /// Blocked force: the plate's vertical reaction (N, full actuator), in [`Mode::Force`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force_n: Option<f64>,
    /// Total normal force between neighbouring bellows (N, full actuator).
    #[serde(default)]
    pub contact_force_n: f64,
    /// Clamp block's reaction on the first bellow (N, full actuator).
    #[serde(default)]
    pub clamp_force_n: f64,
    /// Smallest gap at a contact quadrature point, bellows and clamp (mm; negative =
    /// penetration).
    #[serde(default)]
    pub min_contact_gap_mm: f64,
}

/// Results of a simulation.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Response {
    /// One entry per requested pressure.
    pub steps: Vec<StepResult>,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh elements.
    pub elements: usize,
    /// Free degrees of freedom.
    pub dofs: usize,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Time spent in factorisations (s).
    pub factor_time_s: f64,
    /// Time spent in assembly (s).
    pub assembly_time_s: f64,
    /// Factorisations of the tangent over the whole path.
    #[serde(default)]
    pub factorizations: usize,
}

/// The actuator's FE model with its mesh bookkeeping.
pub struct ActuatorModel {
    /// Mesh with node/face sets.
    pub mesh: ActuatorMesh,
    /// Assembled model.
    pub fe: FeModel,
    /// Index of the clamp block's plane in `fe.planes`.
    pub clamp: Option<usize>,
    /// Index of the force plate's plane in `fe.planes`.
    pub plate: Option<usize>,
}

impl ActuatorModel {
    /// Meshes a design and sets up constraints and loads.
    ///
    /// # Errors
    /// [`SimulateError::Element`] if the mesh is degenerate.
    pub fn new(
        design: &Design,
        material: &Material,
        options: &MeshOptions,
        mode: Mode,
        contact: &ContactSettings,
    ) -> Result<Self, SimulateError> {
        Self::with_effects(
            design,
            material,
            options,
            mode,
            contact,
            &Effects::neutral(),
        )
    }

    /// [`ActuatorModel::new`] with the model-side effects: a compliant clamp
    /// ([`Effects::clamp_springs`]: the support face on springs instead of fixed in the
    /// directions that have one) and the self-weight's scale. The design is taken as given
    /// (pass [`Case::printed_design`]); pressure and force-rig effects act in [`simulate_with`].
    ///
    /// # Errors
    /// See [`ActuatorModel::new`].
    pub fn with_effects(
        design: &Design,
        material: &Material,
        options: &MeshOptions,
        mode: Mode,
        contact: &ContactSettings,
        effects: &Effects,
    ) -> Result<Self, SimulateError> {
        let mesh = ActuatorMesh::new(design, options);
        Self::on_mesh(mesh, design, material, mode, contact, effects, None)
    }

    /// The model of a nearby design on a moved copy of this model's mesh
    /// ([`ActuatorMesh::moved`]) or on this mesh with other effects or material: the same
    /// node numbering, constraints (for the same clamp), face pairs and obstacles, so that a
    /// displacement of this model is one of the variant's. The contact gap shifts start at
    /// zero and the plate where [`ActuatorModel::with_effects`] puts it: the caller copies
    /// both from this model's state.
    ///
    /// # Errors
    /// See [`ActuatorModel::new`].
    pub fn variant(
        &self,
        mesh: ActuatorMesh,
        design: &Design,
        material: &Material,
        (mode, contact): (Mode, &ContactSettings),
        effects: &Effects,
    ) -> Result<Self, SimulateError> {
        let mut model = Self::on_mesh(
            mesh,
            design,
            material,
            mode,
            contact,
            effects,
            Some(self.fe.pairs.clone()),
        )?;
        model.fe.barrier = self.fe.barrier;
        Ok(model)
    }

    /// Constraints, loads and obstacles on a given mesh of `design`; the face pairs found
    /// from the mesh unless given.
    fn on_mesh(
        mesh: ActuatorMesh,
        design: &Design,
        material: &Material,
        mode: Mode,
        contact: &ContactSettings,
        effects: &Effects,
        pairs: Option<Vec<FacePair>>,
    ) -> Result<Self, SimulateError> {
        contact.validate()?;
        let springs = effects.clamp_springs();
        let mut constraints = Vec::new();
        for &n in &mesh.support {
            for (comp, spring) in springs.iter().enumerate() {
                if spring.is_some() {
                    continue;
                }
                constraints.push(Constraint {
                    node: n,
                    comp,
                    value: 0.0,
                });
            }
        }
        for &n in &mesh.symmetry {
            constraints.push(Constraint {
                node: n,
                comp: 0,
                value: 0.0,
            });
        }
        let faces: Vec<_> = mesh
            .pressure_faces
            .values()
            .flat_map(|fs| fs.iter().map(|f| (*f, 1.0)))
            .collect();
        let pairs = match pairs {
            Some(p) => p,
            None if contact.enabled => face_pairs(&mesh),
            None => Vec::new(),
        };
        let mut fe = FeModel::new(
            mesh.mesh().clone(),
            material.clone(),
            &constraints,
            &faces,
            &pair_couplings(&pairs),
        )?;
        fe.set_face_pairs(
            pairs,
            PairSettings {
                stiffness: contact.stiffness,
                smoothing: contact.smoothing,
                closest_point: contact.closest_point,
            },
        )?;
        let mut clamp = None;
        if contact.enabled {
            if let Some(faces) = mesh.gap_faces.get(&GapSide::Clamp) {
                let block = RigidPlane::new(
                    [0.0; 3],
                    [0.0, 0.0, 1.0],
                    contact.stiffness,
                    contact.smoothing,
                )?;
                clamp = Some(fe.add_plane_contact(block, faces)?);
            }
        }
        let mut plate = None;
        if mode == Mode::Force {
            let lf = design.free_length();
            // every outer face of the tip region: the bottom layer that meets the plate first,
            // and the end cap and bellow flanks that reach it once the tip has turned past
            // vertical (the symmetry plane x = W/2 is not a surface)
            let half_width = design.width() / 2.0;
            let faces: Vec<_> = mesh
                .grid
                .boundary_faces(|k| matches!(k, None | Some(Region::Exterior)))
                .into_iter()
                .map(|(f, _)| f)
                .filter(|f| {
                    let x = |n: usize| mesh.mesh().nodes[n];
                    f.nodes
                        .iter()
                        .all(|&n| x(n)[2] >= lf - PLATE_REACH.0 - 1e-9)
                        && !f.nodes.iter().all(|&n| (x(n)[0] - half_width).abs() < 1e-9)
                })
                .collect();
            // placed under the hanging actuator once its self-weight is applied
            let far = RigidPlane::new(
                [0.0, -1e6, 0.0],
                [0.0, 1.0, 0.0],
                contact.stiffness,
                contact.smoothing,
            )?;
            plate = Some(fe.add_plane_contact(far, &faces)?);
        }
        if springs.iter().any(Option::is_some) {
            let faces = mesh.clamped_faces();
            let k = springs.map(|k| k.unwrap_or(0.0));
            fe.add_element_term(Box::new(Foundation::new(
                mesh.mesh().n_elements(),
                &faces,
                k,
            )));
        }
        let gravity = effects.gravity_scale();
        if gravity == 1.0 {
            fe.set_body_force([0.0, -DENSITY * GRAVITY, 0.0]);
        } else {
            fe.set_body_force([0.0, -DENSITY * GRAVITY * gravity, 0.0]);
        }
        // the cavities are closed by the symmetry plane x = W/2 and the duct by the clamped
        // face z = 0: both pass through this origin, so the pressure potential is exact
        fe.pressure_origin = [design.width() / 2.0, 0.0, 0.0];
        Ok(Self {
            mesh,
            fe,
            clamp,
            plate,
        })
    }

    /// Displacement of marker `k` (0-based) in a full displacement vector.
    pub fn marker_displacement(&self, k: usize, u: &[f64]) -> [f64; 3] {
        let m = &self.mesh.markers[k];
        let (n, _) = shape(m.xi);
        let conn = &self.fe.mesh.elements[m.element];
        let mut d = [0.0; 3];
        for (a, &node) in conn.iter().enumerate() {
            for i in 0..3 {
                d[i] += n[a] * u[3 * node + i];
            }
        }
        d
    }

    /// Smallest deformed gap between facing bellow walls (node to node, signed along the back
    /// wall's current normal) and between the first wall and the clamp plane.
    pub fn min_gap(&self, u: &[f64]) -> (f64, String) {
        let pos = |n: usize| {
            let x = self.fe.mesh.nodes[n];
            [x[0] + u[3 * n], x[1] + u[3 * n + 1], x[2] + u[3 * n + 2]]
        };
        let mut best = (f64::INFINITY, String::new());
        for (side, faces) in &self.mesh.gap_faces {
            match side {
                GapSide::Back(i) => {
                    let Some(front) = self.mesh.gap_faces.get(&GapSide::Front(*i)) else {
                        continue;
                    };
                    let mut lookup = std::collections::HashMap::new();
                    for f in front {
                        for &n in &f.nodes {
                            let x = self.fe.mesh.nodes[n];
                            lookup.insert(key(x[0], x[1]), n);
                        }
                    }
                    for f in faces {
                        // the back wall's current normal, oriented into the gap as in the
                        // reference (+z): the sign survives any rotation of the bellow
                        let normal = |p: &dyn Fn(usize) -> [f64; 3]| {
                            let (a, b, c) = (p(f.nodes[0]), p(f.nodes[2]), p(f.nodes[6]));
                            let (s, t) = (sub(b, a), sub(c, a));
                            [
                                s[1] * t[2] - s[2] * t[1],
                                s[2] * t[0] - s[0] * t[2],
                                s[0] * t[1] - s[1] * t[0],
                            ]
                        };
                        let n_ref = normal(&|n| self.fe.mesh.nodes[n]);
                        let n_cur = normal(&pos);
                        let orient = n_ref[2].signum();
                        for &n in &f.nodes {
                            let x = self.fe.mesh.nodes[n];
                            if let Some(&m) = lookup.get(&key(x[0], x[1])) {
                                let d = sub(pos(m), pos(n));
                                let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                                let along =
                                    orient * (d[0] * n_cur[0] + d[1] * n_cur[1] + d[2] * n_cur[2]);
                                let gap = if along >= 0.0 { len } else { -len };
                                if gap < best.0 {
                                    best = (gap, format!("gap {}-{}", i + 1, i + 2));
                                }
                            }
                        }
                    }
                }
                GapSide::Clamp => {
                    for f in faces {
                        for &n in &f.nodes {
                            let z = pos(n)[2];
                            if z < best.0 {
                                best = (z, "clamp".into());
                            }
                        }
                    }
                }
                GapSide::Front(_) => {}
            }
        }
        best
    }
}

/// Facing faces across every gap between neighbouring bellows, nodes matched by reference
/// position (x, y).
fn face_pairs(mesh: &ActuatorMesh) -> Vec<FacePair> {
    let nodes = &mesh.mesh().nodes;
    let mut pairs = Vec::new();
    for (side, backs) in &mesh.gap_faces {
        let GapSide::Back(i) = side else { continue };
        let Some(fronts) = mesh.gap_faces.get(&GapSide::Front(*i)) else {
            continue;
        };
        let mut by_centre = std::collections::HashMap::new();
        for f in fronts {
            let c = nodes[f.nodes[4]];
            by_centre.insert(key(c[0], c[1]), f);
        }
        for b in backs {
            let c = nodes[b.nodes[4]];
            let Some(f) = by_centre.get(&key(c[0], c[1])) else {
                continue;
            };
            let mut front = [0; 9];
            let mut complete = true;
            for (a, &nb) in b.nodes.iter().enumerate() {
                let xb = nodes[nb];
                match f.nodes.iter().find(|&&nf| {
                    let xf = nodes[nf];
                    key(xf[0], xf[1]) == key(xb[0], xb[1])
                }) {
                    Some(&nf) => front[a] = nf,
                    None => complete = false,
                }
            }
            if !complete {
                continue;
            }
            let orientation =
                pair_orientation(&b.nodes.map(|n| nodes[n]), &front.map(|n| nodes[n]));
            pairs.push(FacePair {
                back: b.nodes,
                front,
                orientation,
            });
        }
    }
    pairs
}

fn key(x: f64, y: f64) -> (i64, i64) {
    ((x * 1e6).round() as i64, (y * 1e6).round() as i64)
}

/// Validates a pressure list (bar): finite, ≥ 0, strictly increasing, ≤ [`MAX_PRESSURE_BAR`].
///
/// # Errors
/// [`SimulateError::Pressure`] naming the first bad entry.
pub fn validate_pressures(p: &[f64]) -> Result<(), SimulateError> {
    if p.is_empty() {
        return Err(SimulateError::Pressure {
            index: 0,
            value: f64::NAN,
            expected: "at least one pressure".into(),
        });
    }
    for (i, &v) in p.iter().enumerate() {
        if v < 0.0 {
            return Err(SimulateError::Pressure {
                index: i,
                value: v,
                expected: format!(
                    "a gauge pressure ≥ 0 bar (a negative pressure, below atmospheric, is not \
                     modelled; the range is [0, {MAX_PRESSURE_BAR}] bar)"
                ),
            });
        }
        if !v.is_finite() || !(0.0..=MAX_PRESSURE_BAR).contains(&v) {
            return Err(SimulateError::Pressure {
                index: i,
                value: v,
                expected: format!("a gauge pressure in [0, {MAX_PRESSURE_BAR}] bar"),
            });
        }
        if i > 0 && v <= p[i - 1] {
            return Err(SimulateError::Pressure {
                index: i,
                value: v,
                expected: format!("pressures in increasing order (previous {})", p[i - 1]),
            });
        }
    }
    Ok(())
}

/// Parses a pressure list in bar: comma-separated values (`0,1,2,3`) or `max:step` (`3.5:0.25`:
/// 0, 0.25, …, 3.5; each level rounded to 1e-9 bar so that `3:0.1` gives `0.3`, not
/// `0.30000000000000004`). Positions in messages count from 1. The values are not range
/// checked here ([`validate_pressures`] does).
///
/// # Errors
/// [`SimulateError::PressureText`] naming the entry that is not a number or the malformed
/// `max:step`.
pub fn parse_pressures(s: &str) -> Result<Vec<f64>, SimulateError> {
    let text = |what: String| SimulateError::PressureText {
        list: s.to_string(),
        what,
    };
    if let Some((max, step)) = s.split_once(':') {
        let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let (Some(max), Some(step)) = (num(max), num(step)) else {
            return Err(text(
                "expected max:step, two numbers (e.g. 3.5:0.25)".into(),
            ));
        };
        if !(step > 0.0 && max >= 0.0 && max / step < 1e4) {
            return Err(text(format!(
                "max:step = {max}:{step}: expected max ≥ 0 and step > 0 (at most 10000 levels)"
            )));
        }
        let n = (max / step + 1e-9).floor() as usize;
        return Ok((0..=n)
            .map(|i| (i as f64 * step * 1e9).round() / 1e9)
            .collect());
    }
    s.split(',')
        .enumerate()
        .map(|(i, v)| {
            v.trim().parse::<f64>().map_err(|_| {
                text(format!(
                    "entry {} '{}' is not a number (expected bar values such as 0,1,2,3 or max:step such as 3.5:0.25)",
                    i + 1,
                    v.trim()
                ))
            })
        })
        .collect()
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
/// case on the same mesh, [`super::warm_start`]) where there is one: same answers to the
/// solver's tolerance, fewer Newton iterations. Levels without a matching state, a warm start
/// of another mesh, the compliant plate's ramp and the minimisation solver take the load path
/// as [`run`] does; [`StepResult::warm_start`] says which levels started warm.
///
/// # Errors
/// See [`simulate_with_progress`].
pub fn run_warm(
    case: &Case,
    warm: Option<&WarmStart>,
    mut progress: impl FnMut(usize, usize),
    mut on_result: impl FnMut(&ActuatorModel, &StepResult, &[f64]),
    keep_states: bool,
) -> Result<Ran, SimulateError> {
    let start = Instant::now();
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
        // the minimisation solver's contact law
        model.fe.barrier = Some(IpcBarrier::new(m.dhat_mm, m.barrier_pressure)?);
    }
    let g = if case.gravity { 1.0 } else { 0.0 };
    let mut levels = vec![LoadLevel {
        gravity: g,
        ..Default::default()
    }];
    let first_is_zero = case.pressures_bar[0] == 0.0;
    let skip = usize::from(first_is_zero);
    levels.extend(case.pressures_bar[skip..].iter().map(|&p| LoadLevel {
        pressure: case.effects.effective_pressure_bar(p) * BAR,
        gravity: g,
        ..Default::default()
    }));
    let total = levels.len();
    let guesses = warm.map_or_else(Vec::new, |w| w.guesses(&case.pressures_bar[skip..]));
    let guess = |i: usize| guesses.get(i).and_then(Option::as_ref);
    let lf = design.free_length();
    let mut steps = Vec::new();
    let mut state = PathState::new(&model.fe);
    // Stage 1: self-weight (the state reported at P = 0).
    let mut reports = solve_path_guided(
        &model.fe,
        case.solver.clone(),
        &mut state,
        &levels[..1],
        &[guess(0)],
        |_, state, rep| {
            progress(1, total);
            if first_is_zero {
                let result = measure(&model, state, rep, lf, 0.0);
                on_result(&model, &result, &state.u_full);
                steps.push(result);
            }
        },
    )?;
    let mut states = Vec::new();
    let keep = |pressure_bar: f64, model: &ActuatorModel, state: &PathState, reported: bool| {
        ConvergedState {
            pressure_bar,
            level: state.level,
            u: state.u_full.clone(),
            shifts: model.fe.contact_shifts(),
            plate_y: model.plate.map(|p| model.fe.planes[p].point[1]),
            reported,
        }
    };
    if keep_states {
        states.push(keep(0.0, &model, &state, first_is_zero));
    }
    // Stage 2 (blocked force): the plate goes 5 mm below the hanging tip.
    if let Some(plate) = model.plate {
        let tip = model.marker_displacement(8, &state.u_full);
        let offset = PLATE_OFFSET + case.effects.plate_offset_mm();
        model.fe.planes[plate].point = [0.0, tip[1] - offset, 0.0];
    }
    // Stage 3: the pressure ramp.
    let mut record = |i: usize, model: &ActuatorModel, state: &PathState, rep: &StepReport| {
        progress(i + 2, total);
        let mut result = measure(model, state, rep, lf, case.pressures_bar[skip + i]);
        if let Some(f) = result.force_n.as_mut() {
            let scale = case.effects.force_scale();
            if scale != 1.0 {
                *f *= scale;
            }
        }
        on_result(model, &result, &state.u_full);
        if keep_states {
            states.push(keep(result.pressure_bar, model, state, true));
        }
        steps.push(result);
    };
    let compliance = case.effects.plate_compliance_mm_per_n();
    let ramp = if model.plate.is_some() && compliance > 0.0 {
        let pressures = &case.pressures_bar[skip..];
        compliant_plate_ramp(
            &mut model,
            &case.solver,
            &mut state,
            (&levels[1..], pressures),
            compliance,
            &mut record,
        )?
    } else {
        let ramp_guesses: Vec<_> = (1..levels.len()).map(guess).collect();
        solve_path_guided(
            &model.fe,
            case.solver.clone(),
            &mut state,
            &levels[1..],
            &ramp_guesses,
            |i, state, rep| record(i, &model, state, rep),
        )
    };
    match ramp {
        Ok(r) => reports.extend(r),
        Err(SolverError::NotConverged {
            target,
            reached,
            cutbacks,
            residual,
            completed,
            reports: r,
        }) => {
            reports.extend(r);
            return Err(SolverError::NotConverged {
                target,
                reached,
                cutbacks,
                residual,
                completed: completed + 1,
                reports,
            }
            .into());
        }
        Err(e) => return Err(e.into()),
    }
    let factor_time_s = reports.iter().map(|r| r.factor_seconds).sum();
    let assembly_time_s = reports.iter().map(|r| r.assembly_seconds).sum();
    let factorizations = reports.iter().map(|r| r.factorizations).sum();
    let response = Response {
        steps,
        nodes: model.fe.mesh.n_nodes(),
        elements: model.fe.mesh.n_elements(),
        dofs: model.fe.dofs.n_free,
        wall_time_s: start.elapsed().as_secs_f64(),
        factor_time_s,
        assembly_time_s,
        factorizations,
    };
    Ok(Ran {
        response,
        model,
        design,
        states,
    })
}

/// The pressure ramp against a plate on a spring of compliance `c` (mm/N): at each level the
/// plate sits at `y = y0 − c·F(y)`, `F` the blocked force of the whole actuator there.
///
/// Each level is solved with the plate where it is, then the plate is moved by a secant step
/// on `g(y) = y − (y0 − c·F(y))` and the same level is solved again from the converged state
/// (a few Newton iterations each), until `|g|` is below [`PLATE_SETTLE_MM`]. The fixed point
/// is unique and the iteration contracts while `c` times the tip's stiffness against the
/// plate is below 1 (about 0.3 N/mm × 1 mm/N at the library's largest compliance). The
/// reports of one level add up its re-solves.
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
        let mut settled = None;
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
                Err(SolverError::NotConverged {
                    target,
                    reached,
                    cutbacks,
                    residual,
                    ..
                }) => {
                    return Ok(Err(SolverError::NotConverged {
                        target,
                        reached,
                        cutbacks,
                        residual,
                        completed: i,
                        reports,
                    }))
                }
                Err(e) => return Ok(Err(e)),
            };
            sum = Some(match sum {
                None => rep,
                Some(mut s) => {
                    s.level = rep.level;
                    s.newton_iterations += rep.newton_iterations;
                    s.substeps += rep.substeps;
                    s.cutbacks += rep.cutbacks;
                    s.residual = rep.residual;
                    s.update = rep.update;
                    s.converged = rep.converged;
                    s.factor_seconds += rep.factor_seconds;
                    s.assembly_seconds += rep.assembly_seconds;
                    s.augmented_updates += rep.augmented_updates;
                    s.augmented_failed |= rep.augmented_failed;
                    s.factorizations += rep.factorizations;
                    s.stabilized |= rep.stabilized;
                    s
                }
            });
            let info = model
                .fe
                .assemble(&state.u_full, &state.level, &mut r, None)?;
            // ×2: the model is a half
            let force = 2.0 * info.plane_forces[plate];
            let y = model.fe.planes[plate].point[1];
            let mismatch = y - (y0 - compliance * force);
            if mismatch.abs() < PLATE_SETTLE_MM {
                settled = Some(iteration);
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
        debug_assert!(settled.is_some());
        let rep = sum.expect("at least one solve per level");
        observe(i, model, state, &rep);
        reports.push(rep);
    }
    Ok(Ok(reports))
}

/// Runs one case.
///
/// # Errors
/// See [`simulate_with_progress`].
pub fn simulate(case: &Case) -> Result<Response, SimulateError> {
    simulate_with_progress(case, |_, _| {})
}

/// The measured outputs of a converged state; `pressure_bar` is the requested level, reported
/// as given (not recomputed from the load in MPa, which would print `3.0000000000000004`).
fn measure(
    model: &ActuatorModel,
    state: &PathState,
    rep: &StepReport,
    lf: f64,
    pressure_bar: f64,
) -> StepResult {
    let u = &state.u_full;
    let markers: Vec<[f64; 2]> = (0..9)
        .map(|k| {
            let d = model.marker_displacement(k, u);
            [-d[2], d[1]]
        })
        .collect();
    let tip = markers[8];
    let z_tip = lf - tip[0];
    let y_tip = tip[1];
    let (min_gap_mm, min_gap_at) = model.min_gap(u);
    // reactions of the obstacles at the converged state (×2: the model is a half)
    let mut r = vec![0.0; u.len()];
    let info = model.fe.assemble(u, &state.level, &mut r, None).ok();
    let plane = |i: Option<usize>| {
        i.zip(info.as_ref())
            .map(|(i, info)| (2.0 * info.plane_forces[i], info.plane_min_gaps[i]))
    };
    let force_n = plane(model.plate).map(|(f, _)| f);
    let (clamp_force_n, clamp_gap) = plane(model.clamp).unwrap_or((0.0, f64::INFINITY));
    let (contact_force_n, pair_gap) = info.as_ref().map_or((0.0, f64::INFINITY), |i| {
        (2.0 * i.pair_force, i.pair_min_gap)
    });
    StepResult {
        pressure_bar,
        tip_uz_mm: tip[0],
        tip_uy_mm: tip[1],
        angle_deg: (-y_tip).atan2(z_tip).to_degrees(),
        markers,
        newton_iterations: rep.newton_iterations,
        warm_start: rep.warm_start,
        substeps: rep.substeps,
        cutbacks: rep.cutbacks,
        residual: rep.residual,
        converged: rep.converged,
        min_gap_mm,
        min_gap_at,
        force_n,
        contact_force_n,
        clamp_force_n,
        min_contact_gap_mm: pair_gap.min(clamp_gap),
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn is_false(v: &bool) -> bool {
    !*v
}
