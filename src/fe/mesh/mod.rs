//! Structured 27-node (triquadratic) hexahedral meshes.
//!
//! A mesh is generated on a non-uniform tensor grid of cells, some of which are void; the
//! actuator is a union of boxes, so its cells are classified by [`Design::region`] at their
//! centres. Node numbering inside an element is the tensor order
//! `local = i + 3 j + 9 k`, `i, j, k ∈ {0, 1, 2}` along (ξ, η, ζ).
//!
//! Test geometries (Cook's membrane, cylinders) are made the same way in a parameter space and
//! mapped node by node with [`GridMesh::map_nodes`].
//!
//! By concern:
//! - `hex`: the mesh of triquadratic hexahedra, node order and faces ([`Mesh`], [`Face`],
//!   [`face_local_nodes`]);
//! - `grid`: a mesh generated on a tensor grid of cells ([`TensorGrid`], [`GridMesh`]);
//! - `options`: refinement levels and their overrides ([`MeshLevel`], [`MeshOptions`]);
//! - `actuator`: the mesh of an actuator design with its node and face sets
//!   ([`ActuatorMesh`]).
//!
//! [`Design::region`]: crate::fe::geometry::Design::region

mod actuator;
mod grid;
mod hex;
mod options;

pub(crate) use actuator::piecewise_linear;
pub use actuator::{
    feature_positions, ActuatorMesh, GapSide, MarkerLocation, MeshMoveError, PressureSurface,
};
pub use grid::{GridMesh, TensorGrid};
pub use hex::{face_local_nodes, local_index, Face, Mesh, NODES_PER_ELEMENT};
pub use options::{MeshLevel, MeshOptions};
