//! Building the actuator's FE model from a case: the mesh of the printed design, its
//! constraints, loads and obstacles.
//!
//! The model is the symmetric half `x ≤ W/2` of the actuator:
//!
//! - **Support.** The clamped face `z = 0` is fixed, `u = 0`, in every direction without a
//!   clamp spring; with the clamp-compliance effects it rests on a Winkler foundation of
//!   stiffness `k = 1/c` per unit area in those directions instead.
//! - **Symmetry.** `u_x = 0` on the plane `x = W/2`.
//! - **Pressure.** A follower pressure on every cavity face. The cavities are closed by the
//!   symmetry plane and the duct by the clamped face, both through the origin
//!   `(W/2, 0, 0)`, so the pressure potential taken about it is exact.
//! - **Self-weight.** The body force `b = −ρ g e_y` (scaled by the density effect).
//! - **Contact.** Facing walls of neighbouring bellows are paired face to face, nodes matched
//!   by reference position `(x, y)`; the first bellow meets the clamp block, the rigid plane
//!   `z = 0`. In [`Mode::Force`] the force plate, a rigid plane `y = const` with normal
//!   `+e_y`, meets every outer face of the tip region, reference `z ≥ Lf − 25` mm
//!   ([`PLATE_REACH`]); it is built far below and placed by the path driver once the
//!   self-weight is applied.

use super::case::{ContactSettings, Mode};
use super::SimulateError;
use crate::fe::assembly::terms::foundation::Foundation;
use crate::fe::assembly::{pair_couplings, Constraint, FeModel};
use crate::fe::contact::{pair_orientation, FacePair, PairSettings, RigidPlane};
use crate::fe::effects::Effects;
use crate::fe::geometry::{Design, Region};
use crate::fe::material::Material;
use crate::fe::mesh::{ActuatorMesh, Face, GapSide, MeshOptions};

/// TPU density (t/mm³).
pub const DENSITY: f64 = 1.19e-9;
/// Gravitational acceleration (mm/s²), acting along −y.
pub const GRAVITY: f64 = 9810.0;
/// The plate lies under z ∈ [Lf − 25, Lf + 5] (mm, SPEC).
pub const PLATE_REACH: (f64, f64) = (25.0, 5.0);

/// Revision of the blocked-force model, part of the key of cached force ramps
/// ([`crate::calibrate::baseline`]): 2 = the plate meets every outer face of the tip region
/// (1: the bottom layer only, which let a tip turned past vertical pass through the plate).
pub const FORCE_MODEL_REVISION: u32 = 2;

/// The actuator's FE model with its mesh bookkeeping. Its measurements (markers, gaps) are
/// in [`super::measure`].
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
    /// (pass [`Case::printed_design`](super::Case::printed_design)); pressure and force-rig
    /// effects act in [`simulate_with`](super::simulate_with).
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
        Self::on_mesh(mesh, design, material, (mode, contact), effects, None)
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
            (mode, contact),
            effects,
            Some(self.fe.pairs.clone()),
        )?;
        model.fe.barrier = self.fe.barrier;
        Ok(model)
    }

    /// Constraints, loads and obstacles on a given mesh of `design`; the face pairs found
    /// from the mesh unless given. The obstacles are added in a fixed order (clamp block,
    /// then force plate), which fixes their indices in `fe.planes`.
    fn on_mesh(
        mesh: ActuatorMesh,
        design: &Design,
        material: &Material,
        (mode, contact): (Mode, &ContactSettings),
        effects: &Effects,
        pairs: Option<Vec<FacePair>>,
    ) -> Result<Self, SimulateError> {
        contact.validate()?;
        let springs = effects.clamp_springs();
        let pairs = match pairs {
            Some(p) => p,
            None if contact.enabled => face_pairs(&mesh),
            None => Vec::new(),
        };
        let mut fe = FeModel::new(
            mesh.mesh().clone(),
            material.clone(),
            &constraints(&mesh, springs),
            &pressure_faces(&mesh),
            &pair_couplings(&pairs),
        )?;
        if design.params().part_stiffness.is_some() {
            fe.set_stiffness(|x| design.stiffness_at(x));
        }
        fe.set_face_pairs(
            pairs,
            PairSettings {
                stiffness: contact.stiffness,
                smoothing: contact.smoothing,
                closest_point: contact.closest_point,
            },
        )?;
        let clamp = if contact.enabled {
            add_clamp_block(&mut fe, &mesh, contact)?
        } else {
            None
        };
        let plate = match mode {
            Mode::Force => Some(add_force_plate(&mut fe, &mesh, design, contact)?),
            Mode::Bending => None,
        };
        add_clamp_springs(&mut fe, &mesh, springs);
        set_dead_loads(&mut fe, design, effects.gravity_scale());
        Ok(Self {
            mesh,
            fe,
            clamp,
            plate,
        })
    }
}

/// The Dirichlet conditions: the support nodes fixed in every direction without a clamp
/// spring, the symmetry nodes in x.
fn constraints(mesh: &ActuatorMesh, springs: [Option<f64>; 3]) -> Vec<Constraint> {
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
    constraints
}

/// Every cavity face, at unit pressure.
fn pressure_faces(mesh: &ActuatorMesh) -> Vec<(Face, f64)> {
    mesh.pressure_faces
        .values()
        .flat_map(|fs| fs.iter().map(|f| (*f, 1.0)))
        .collect()
}

/// The clamp block, the rigid plane `z = 0` the first bellow's front wall meets; its index in
/// `fe.planes`, or `None` when the mesh has no clamp gap.
fn add_clamp_block(
    fe: &mut FeModel,
    mesh: &ActuatorMesh,
    contact: &ContactSettings,
) -> Result<Option<usize>, SimulateError> {
    let Some(faces) = mesh.gap_faces.get(&GapSide::Clamp) else {
        return Ok(None);
    };
    let block = RigidPlane::new(
        [0.0; 3],
        [0.0, 0.0, 1.0],
        contact.stiffness,
        contact.smoothing,
    )?;
    Ok(Some(fe.add_plane_contact(block, faces)?))
}

/// The force plate, built far below (`y = −1e6` mm) and placed under the hanging actuator by
/// the path driver once its self-weight is applied; its index in `fe.planes`.
fn add_force_plate(
    fe: &mut FeModel,
    mesh: &ActuatorMesh,
    design: &Design,
    contact: &ContactSettings,
) -> Result<usize, SimulateError> {
    let faces = plate_faces(mesh, design);
    let far = RigidPlane::new(
        [0.0, -1e6, 0.0],
        [0.0, 1.0, 0.0],
        contact.stiffness,
        contact.smoothing,
    )?;
    Ok(fe.add_plane_contact(far, &faces)?)
}

/// Every outer face of the tip region (reference `z ≥ Lf − 25` mm): the bottom layer that
/// meets the plate first, and the end cap and bellow flanks that reach it once the tip has
/// turned past vertical. The symmetry plane `x = W/2` is not a surface.
fn plate_faces(mesh: &ActuatorMesh, design: &Design) -> Vec<Face> {
    let lf = design.free_length();
    let half_width = design.width() / 2.0;
    let x = |n: usize| mesh.mesh().nodes[n];
    mesh.grid
        .boundary_faces(|k| matches!(k, None | Some(Region::Exterior)))
        .into_iter()
        .map(|(f, _)| f)
        .filter(|f| {
            f.nodes
                .iter()
                .all(|&n| x(n)[2] >= lf - PLATE_REACH.0 - 1e-9)
                && !f.nodes.iter().all(|&n| (x(n)[0] - half_width).abs() < 1e-9)
        })
        .collect()
}

/// The compliant clamp: the clamped faces on a foundation of the springs' stiffness in the
/// directions that have one (none when the clamp is rigid).
fn add_clamp_springs(fe: &mut FeModel, mesh: &ActuatorMesh, springs: [Option<f64>; 3]) {
    if springs.iter().any(Option::is_some) {
        let faces = mesh.clamped_faces();
        let k = springs.map(|k| k.unwrap_or(0.0));
        fe.add_element_term(Box::new(Foundation::new(
            mesh.mesh().n_elements(),
            &faces,
            k,
        )));
    }
}

/// Self-weight `−ρ g · scale · e_y` and the origin of the pressure potential.
fn set_dead_loads(fe: &mut FeModel, design: &Design, gravity: f64) {
    if gravity == 1.0 {
        fe.set_body_force([0.0, -DENSITY * GRAVITY, 0.0]);
    } else {
        fe.set_body_force([0.0, -DENSITY * GRAVITY * gravity, 0.0]);
    }
    // the cavities are closed by the symmetry plane x = W/2 and the duct by the clamped
    // face z = 0: both pass through this origin, so the pressure potential is exact
    fe.pressure_origin = [design.width() / 2.0, 0.0, 0.0];
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

/// A reference position `(x, y)` rounded to 1 nm, to match the nodes of facing walls.
pub(super) fn key(x: f64, y: f64) -> (i64, i64) {
    ((x * 1e6).round() as i64, (y * 1e6).round() as i64)
}
