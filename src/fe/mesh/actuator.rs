//! The half-model mesh of an actuator design: grid lines at the design's features, node and
//! face sets (support, symmetry, cavities, gaps, markers), and the mesh moved onto a nearby
//! design.

use std::collections::BTreeMap;

use thiserror::Error;

use super::grid::{GridMesh, TensorGrid};
use super::hex::{Face, Mesh};
use super::options::MeshOptions;
use crate::fe::geometry::{Design, Region};

/// The pressurised surfaces a face can belong to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum PressureSurface {
    /// Cavity of bellow `i`.
    Cavity(usize),
    /// The air duct.
    Duct,
}

/// Which side of a gap a contact face is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum GapSide {
    /// Back wall (z = (i+1)p − g/2, normal +z) of bellow `i` facing gap `i`.
    Back(usize),
    /// Front wall (normal −z) of bellow `i + 1` facing gap `i`.
    Front(usize),
    /// Front wall of the first bellow facing the clamp block.
    Clamp,
}

/// A marker: where it sits in the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkerLocation {
    /// Reference position.
    pub position: [f64; 3],
    /// Element containing it.
    pub element: usize,
    /// Local coordinates in that element.
    pub xi: [f64; 3],
}

/// Why a mesh cannot be moved onto another design ([`ActuatorMesh::moved`]).
#[derive(Debug, Error, PartialEq)]
pub enum MeshMoveError {
    /// The designs' features differ in number or order along an axis.
    #[error("the designs' features along axis {axis} differ in number or order: expected the same design up to small changes of its dimensions")]
    Features {
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
    },
    /// A moved cell lies in another region.
    #[error("a cell of the moved mesh lies in another region of the design: expected the same design up to small changes of its dimensions")]
    Regions,
}

/// The feature positions of a design along each axis, where the mesh must have grid lines,
/// and the wall intervals that get at least the wall's element count.
struct Breaks {
    at: [Vec<f64>; 3],
    walls: [Vec<(f64, f64)>; 3],
    thickest_wall: f64,
}

impl Breaks {
    fn of(design: &Design) -> Self {
        let p = design.params();
        // bellow walls (facing the gaps) and outer skin: both T unless a printed thickness
        // differs ([`Design::bellow_wall`], [`Design::skin`])
        let (t, ts, tx) = (design.bellow_wall(), design.skin(), design.side_wall());
        let w2 = p.width / 2.0;
        let duct = design.duct();
        // x: walls resolved with `wall_div` elements, the rest by size.
        let mut xb = vec![0.0, tx, w2];
        if let Some(d) = duct {
            xb.push(d.lo[0]);
        }
        let mut yb = vec![0.0, p.base_thickness, p.height - ts, p.height];
        if design.gap_floor() > 0.0 {
            yb.push(p.base_thickness + design.gap_floor());
        }
        let fillet = design.cavity_fillet();
        if fillet > 0.0 {
            yb.push(p.base_thickness + fillet);
        }
        if duct.is_some() {
            yb.extend([p.duct_bottom, p.duct_top]);
        }
        let mut zb = vec![0.0, p.free_length];
        let mut walls = Vec::new();
        for i in 0..p.n_bellows {
            let b = design.bellow(i);
            zb.extend([b.lo[2], b.lo[2] + t, b.hi[2] - t, b.hi[2]]);
            walls.push((b.lo[2], b.lo[2] + t));
            walls.push((b.hi[2] - t, b.hi[2]));
            let c = design.cavity(i);
            if fillet > 0.0 && c.hi[2] - c.lo[2] > 2.0 * fillet {
                zb.extend([c.lo[2] + fillet, c.hi[2] - fillet]);
            }
        }
        if let Some(d) = duct {
            zb.push(d.hi[2]);
        }
        Self {
            at: [xb, yb, zb],
            walls: [vec![(0.0, tx)], vec![(p.height - ts, p.height)], walls],
            thickest_wall: t.max(ts).max(tx),
        }
    }
}

/// Sorted, with values closer than 1e-9 merged (as [`TensorGrid::subdivide`] does).
fn dedup_sorted(v: &[f64]) -> Vec<f64> {
    let mut b = v.to_vec();
    b.sort_by(f64::total_cmp);
    b.dedup_by(|a, c| (*a - *c).abs() < 1e-9);
    b
}

/// The feature positions of a design along x, y and z (walls, cavities, gaps, duct, free
/// length: where its meshes have grid lines), each sorted with values closer than 1e-9
/// merged. Two designs of the same layout (the same `N`, a duct in both or neither) have the
/// same number of features in the same order; the piecewise-linear map between their lists
/// ([`piecewise_linear`]) is the map [`ActuatorMesh::moved`] moves grid lines by.
pub fn feature_positions(design: &Design) -> [Vec<f64>; 3] {
    let breaks = Breaks::of(design);
    std::array::from_fn(|a| dedup_sorted(&breaks.at[a]))
}

/// The piecewise-linear map with `from[i] ↦ to[i]` at `x` (constant slope beyond the ends).
/// `from` is sorted and has at least one entry (`to` as many).
pub(crate) fn piecewise_linear(from: &[f64], to: &[f64], x: f64) -> f64 {
    let i = from
        .partition_point(|&v| v <= x)
        .saturating_sub(1)
        .min(from.len().saturating_sub(2));
    if from.len() < 2 {
        return x - from[0] + to[0];
    }
    let s = (x - from[i]) / (from[i + 1] - from[i]);
    to[i] + s * (to[i + 1] - to[i])
}

/// The half-model mesh of an actuator design, with its node and face sets.
#[derive(Clone, Debug)]
pub struct ActuatorMesh {
    /// The grid mesh.
    pub grid: GridMesh<Region>,
    /// Nodes fixed in all directions (base face z = 0).
    pub support: Vec<usize>,
    /// Nodes on the symmetry plane x = W/2 (u_x = 0).
    pub symmetry: Vec<usize>,
    /// Pressurised faces grouped by surface.
    pub pressure_faces: BTreeMap<PressureSurface, Vec<Face>>,
    /// Faces bounding a gap between bellows (or the clamp gap).
    pub gap_faces: BTreeMap<GapSide, Vec<Face>>,
    /// The 9 markers; the last one is the tip.
    pub markers: Vec<MarkerLocation>,
    /// The support point (W/2, 0, 0).
    pub support_point: [f64; 3],
}

impl ActuatorMesh {
    /// Meshes the half model x ∈ [0, W/2] of a design.
    pub fn new(design: &Design, options: &MeshOptions) -> Self {
        let (h, wall_div) = options.sizing();
        let breaks = Breaks::of(design);
        let wall_div = wall_div.max((breaks.thickest_wall / h - 1e-9).ceil() as usize);
        let [xs, ys, zs] = std::array::from_fn(|a| {
            TensorGrid::subdivide(&breaks.at[a], &breaks.walls[a], h, wall_div)
        });
        let grid = TensorGrid {
            lines: [xs, ys, zs],
        };
        Self::on_grid(design, grid)
    }

    /// The mesh of `design` with the elements of this mesh (of `reference`): every grid line
    /// moved by the piecewise-linear map that takes `reference`'s feature positions (walls,
    /// cavities, duct, free length) to `design`'s. The node numbering, the connectivity and
    /// every node and face set stay those of this mesh; only coordinates (and the markers'
    /// local coordinates) change. This is how a dimension of the design is differentiated:
    /// the derivative of the discrete model along a smooth motion of its nodes.
    ///
    /// # Errors
    /// [`MeshMoveError`] if the two designs do not have the same features in the same order
    /// (a different `N`, a duct in one only, features swapping places), or if a cell of the
    /// moved grid falls in a different region of `design` than it did of `reference`.
    pub fn moved(&self, reference: &Design, design: &Design) -> Result<Self, MeshMoveError> {
        let (from, to) = (Breaks::of(reference), Breaks::of(design));
        let mut lines: [Vec<f64>; 3] = Default::default();
        for (a, line) in lines.iter_mut().enumerate() {
            let (f, t) = (dedup_sorted(&from.at[a]), dedup_sorted(&to.at[a]));
            if f.len() != t.len() || t.windows(2).any(|w| w[1] <= w[0]) {
                return Err(MeshMoveError::Features { axis: a });
            }
            *line = self.grid.grid.lines[a]
                .iter()
                .map(|&x| piecewise_linear(&f, &t, x))
                .collect();
        }
        let moved = Self::on_grid(design, TensorGrid { lines });
        if moved.grid.cell_kinds != self.grid.cell_kinds
            || moved.mesh().elements != self.mesh().elements
        {
            return Err(MeshMoveError::Regions);
        }
        Ok(moved)
    }

    /// The mesh of `design` on a given grid.
    fn on_grid(design: &Design, grid: TensorGrid) -> Self {
        let p = design.params();
        let w2 = p.width / 2.0;
        let gm = GridMesh::new(grid, |c| design.region(c), |r| r == Region::Solid);
        let support = gm.nodes_on_plane(2, 0.0);
        let symmetry = gm.nodes_on_plane(0, w2);
        let mut pressure_faces: BTreeMap<PressureSurface, Vec<Face>> = BTreeMap::new();
        let mut gap_faces: BTreeMap<GapSide, Vec<Face>> = BTreeMap::new();
        for (face, kind) in gm.boundary_faces(|k| k.is_some_and(|k| k != Region::Solid)) {
            match kind {
                Some(Region::Cavity(i)) => pressure_faces
                    .entry(PressureSurface::Cavity(i))
                    .or_default()
                    .push(face),
                Some(Region::Duct) => pressure_faces
                    .entry(PressureSurface::Duct)
                    .or_default()
                    .push(face),
                Some(Region::Gap(i)) if face.axis == 2 => {
                    let side = if face.positive {
                        GapSide::Back(i)
                    } else {
                        GapSide::Front(i)
                    };
                    gap_faces.entry(side).or_default().push(face);
                }
                Some(Region::ClampGap) if face.axis == 2 => {
                    gap_faces.entry(GapSide::Clamp).or_default().push(face)
                }
                _ => {}
            }
        }
        let markers = design
            .markers()
            .iter()
            .map(|&m| {
                let (element, xi) = gm
                    .locate(m)
                    .expect("markers lie on the bottom face of the base, which is always solid"); // ok: geometry invariant
                MarkerLocation {
                    position: m,
                    element,
                    xi,
                }
            })
            .collect();
        Self {
            grid: gm,
            support,
            symmetry,
            pressure_faces,
            gap_faces,
            markers,
            support_point: design.support_point(),
        }
    }

    /// The finite-element mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.grid.mesh
    }

    /// The clamped face: the outer faces in the plane z = 0 (where the support nodes are),
    /// on which a compliant clamp's springs act.
    pub fn clamped_faces(&self) -> Vec<Face> {
        let nodes = &self.mesh().nodes;
        self.grid
            .boundary_faces(|k| matches!(k, None | Some(Region::Exterior)))
            .into_iter()
            .map(|(f, _)| f)
            .filter(|f| f.axis == 2 && !f.positive)
            .filter(|f| f.nodes.iter().all(|&n| nodes[n][2] == 0.0))
            .collect()
    }
}
