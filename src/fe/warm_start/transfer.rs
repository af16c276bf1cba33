//! A converged state carried onto the mesh of another design of the same layout.
//!
//! Two designs with the same number of bellows `N` (another wall thickness `T`, say) have the
//! same features (walls, cavities, gaps, duct, free length) in the same order along each
//! axis, at other positions ([`feature_positions`]). Per axis, the piecewise-linear map
//! `ψ` taking design B's feature positions to design A's pairs every point of B with a
//! material point of A: walls with walls, cavities with cavities. A displacement field `u_A`
//! of A's mesh is carried onto B's mesh node by node,
//!
//! ```text
//! u_B(X_B) = Σₐ Nₐ(ξ) u_A,a      with  (e, ξ) = locate_A(ψ(X_B)),
//! ```
//!
//! the triquadratic shape functions `Nₐ` ([`crate::fe::element::shape`]) of the element `e`
//! of A's mesh containing `ψ(X_B)`, at its local coordinates `ξ`, summed over its 27 nodes
//! `a`. The elements are axis-aligned boxes with their mid-side nodes at the middle, so the
//! interpolation reproduces any polynomial field up to degree two per axis: an affine field
//! `u_A(X_A) = c + G X_A` arrives as `c + G ψ(X_B)`, and on the same design (`ψ` the identity,
//! the same mesh) every node gets its own value.
//!
//! **Contact gap shifts** (the augmented-Lagrangian multipliers, one per contact face and
//! quadrature point) are carried as they are only when the two meshes have the same cells, of
//! the same kinds, and the same elements: then every contact face of B is the face of A in
//! the same place of the list (moved with the features), and the shift vectors have the same
//! order. Otherwise the state is given no shifts (an empty vector), and a warm start from it
//! starts each level from the model's own shifts at that point, the ones the cold load path
//! starts the level from (zeros at the self-weight level, then those of the level before;
//! [`LevelGuess::shifts`](crate::fe::solver::LevelGuess::shifts)).

use thiserror::Error;

use super::ConvergedState;
use crate::fe::element::shape;
use crate::fe::geometry::Design;
use crate::fe::mesh::{feature_positions, piecewise_linear, ActuatorMesh, NODES_PER_ELEMENT};

/// How far (mm) outside a solid cell of A's mesh a mapped node may lie (rounding of the
/// piecewise-linear map) and still be located in it.
const LOCATE_TOL: f64 = 1e-9;

/// Local coordinates this close to a node's (−1, 0 or 1) are taken as the node's, so that a
/// node of B on a node of A gets A's value exactly (not within rounding of the map).
const SNAP_TOL: f64 = 1e-12;

/// `xi` snapped to the nearest of −1, 0, 1 within [`SNAP_TOL`].
fn snap(xi: f64) -> f64 {
    let node = xi.round();
    if (xi - node).abs() < SNAP_TOL {
        node
    } else {
        xi
    }
}

/// Why a state cannot be carried onto another design's mesh.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum TransferError {
    /// The designs have different numbers of bellows.
    #[error(
        "the target design has N = {to} bellows, the state's design N = {from}: expected the \
         same number of bellows"
    )]
    Bellows {
        /// `N` of the state's design.
        from: usize,
        /// `N` of the target design.
        to: usize,
    },
    /// The designs' features along an axis differ in number or order.
    #[error(
        "the designs have {from} and {to} feature positions along axis {axis}: expected the \
         same features in the same order (the same N, a duct in both or neither)"
    )]
    Features {
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
        /// Features of the state's design.
        from: usize,
        /// Features of the target design.
        to: usize,
    },
    /// A node of the target mesh maps to no solid element of the state's mesh.
    #[error(
        "node {node} of the target mesh at {position:?} maps to {material_point:?}, in no \
         solid element of the state's mesh: expected every solid point of one design to map \
         into the solid of the other"
    )]
    NotLocated {
        /// Node of the target mesh.
        node: usize,
        /// Its reference position.
        position: [f64; 3],
        /// The material point of the state's design it maps to.
        material_point: [f64; 3],
    },
    /// A state's displacement does not belong to the state's mesh.
    #[error(
        "state {state} has {len} displacement entries: expected {expected} (3 per node of \
         the state's mesh)"
    )]
    Length {
        /// Index of the state.
        state: usize,
        /// Its number of entries.
        len: usize,
        /// Three per node of the state's mesh.
        expected: usize,
    },
}

/// The interpolation from the mesh of design A onto the mesh of design B (same layout):
/// for each node of B, the 27 nodes of A's element containing its material point and their
/// shape functions there.
#[derive(Clone, Debug)]
pub struct Transfer {
    /// Per node of B: A's element nodes and their weights.
    weights: Vec<([usize; NODES_PER_ELEMENT], [f64; NODES_PER_ELEMENT])>,
    /// Nodes of A's mesh.
    from_nodes: usize,
    /// Whether the meshes have the same cells and elements (the contact gap shifts carry over).
    same_topology: bool,
}

impl Transfer {
    /// The interpolation from `mesh_a` (of `design_a`) onto `mesh_b` (of `design_b`).
    ///
    /// # Errors
    /// [`TransferError::Bellows`] or [`TransferError::Features`] for designs of different
    /// layouts; [`TransferError::NotLocated`] if a node of B maps outside A's solid.
    pub fn new(
        mesh_a: &ActuatorMesh,
        design_a: &Design,
        mesh_b: &ActuatorMesh,
        design_b: &Design,
    ) -> Result<Self, TransferError> {
        let map = material_map(design_a, design_b)?;
        let weights = mesh_b
            .mesh()
            .nodes
            .iter()
            .enumerate()
            .map(|(node, &position)| {
                let material_point = map(position);
                let (e, xi) = mesh_a
                    .grid
                    .locate_within(material_point, LOCATE_TOL)
                    .ok_or(TransferError::NotLocated {
                        node,
                        position,
                        material_point,
                    })?;
                Ok((mesh_a.mesh().elements[e], shape(xi.map(snap)).0))
            })
            .collect::<Result<Vec<_>, TransferError>>()?;
        let same_topology = mesh_a.grid.grid.cells() == mesh_b.grid.grid.cells()
            && mesh_a.grid.cell_kinds == mesh_b.grid.cell_kinds
            && mesh_a.mesh().elements == mesh_b.mesh().elements;
        Ok(Self {
            weights,
            from_nodes: mesh_a.mesh().n_nodes(),
            same_topology,
        })
    }

    /// Whether the two meshes have the same cells and elements, so that contact gap shifts
    /// carry over as they are.
    pub fn same_topology(&self) -> bool {
        self.same_topology
    }

    /// The length of a displacement vector of A's mesh (3 per node).
    pub fn source_len(&self) -> usize {
        3 * self.from_nodes
    }

    /// A displacement vector of A's mesh (3 per node) interpolated onto B's nodes, or `None`
    /// if `u_a` is not 3 per node of A's mesh.
    pub fn displacement(&self, u_a: &[f64]) -> Option<Vec<f64>> {
        if u_a.len() != 3 * self.from_nodes {
            return None;
        }
        let mut u_b = vec![0.0; 3 * self.weights.len()];
        for (out, (nodes, w)) in u_b.chunks_exact_mut(3).zip(&self.weights) {
            for (&n, &wa) in nodes.iter().zip(w) {
                for (c, o) in out.iter_mut().enumerate() {
                    *o += wa * u_a[3 * n + c];
                }
            }
        }
        Some(u_b)
    }

    /// A converged state of A carried onto B: the displacement interpolated, the contact gap
    /// shifts kept where the meshes have the same topology and emptied otherwise (the cold
    /// path's shifts, see the [module docs](self)), the rest as it was. `index` names the
    /// state in errors.
    ///
    /// # Errors
    /// [`TransferError::Length`] if the state's displacement is not 3 per node of A's mesh.
    pub fn state(
        &self,
        index: usize,
        state: &ConvergedState,
    ) -> Result<ConvergedState, TransferError> {
        let u = self.displacement(&state.u).ok_or(TransferError::Length {
            state: index,
            len: state.u.len(),
            expected: 3 * self.from_nodes,
        })?;
        Ok(ConvergedState {
            u,
            shifts: if self.same_topology {
                state.shifts.clone()
            } else {
                Vec::new()
            },
            ..state.clone()
        })
    }
}

/// The map `ψ` from design B's reference points to design A's material points: per axis the
/// piecewise-linear map taking B's feature positions to A's.
///
/// # Errors
/// [`TransferError::Bellows`] or [`TransferError::Features`] for designs of different layouts.
pub fn material_map(
    design_a: &Design,
    design_b: &Design,
) -> Result<impl Fn([f64; 3]) -> [f64; 3], TransferError> {
    let (from, to) = (design_a.n_bellows(), design_b.n_bellows());
    if from != to {
        return Err(TransferError::Bellows { from, to });
    }
    let (fa, fb) = (feature_positions(design_a), feature_positions(design_b));
    for (axis, (a, b)) in fa.iter().zip(&fb).enumerate() {
        let increasing = |v: &[f64]| v.windows(2).all(|w| w[1] > w[0]);
        if a.len() != b.len() || a.is_empty() || !increasing(a) || !increasing(b) {
            return Err(TransferError::Features {
                axis,
                from: a.len(),
                to: b.len(),
            });
        }
    }
    Ok(move |x: [f64; 3]| std::array::from_fn(|a| piecewise_linear(&fb[a], &fa[a], x[a])))
}

/// A converged state of design A (on `mesh_a`) carried onto the mesh of design B of the same
/// layout ([`Transfer`]; for several states build the [`Transfer`] once).
///
/// # Errors
/// See [`Transfer::new`] and [`Transfer::state`].
pub fn transfer(
    state: &ConvergedState,
    mesh_a: &ActuatorMesh,
    design_a: &Design,
    mesh_b: &ActuatorMesh,
    design_b: &Design,
) -> Result<ConvergedState, TransferError> {
    Transfer::new(mesh_a, design_a, mesh_b, design_b)?.state(0, state)
}
