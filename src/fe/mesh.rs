//! Structured 27-node (triquadratic) hexahedral meshes.
//!
//! A mesh is generated on a non-uniform tensor grid of cells, some of which are void; the
//! actuator is a union of boxes, so its cells are classified by [`Design::region`] at their
//! centres. Node numbering inside an element is the tensor order
//! `local = i + 3 j + 9 k`, `i, j, k ∈ {0, 1, 2}` along (ξ, η, ζ).
//!
//! Test geometries (Cook's membrane, cylinders) are made the same way in a parameter space and
//! mapped node by node with [`GridMesh::map_nodes`].

use std::collections::BTreeMap;

use super::geometry::{Design, Region};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Nodes per element.
pub const NODES_PER_ELEMENT: usize = 27;

/// A face of an element: 9 nodes in tensor order (s, t) with ∂x/∂s × ∂x/∂t pointing out of the
/// element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// The element the face belongs to.
    pub element: usize,
    /// Local axis normal to the face (0 = ξ, 1 = η, 2 = ζ).
    pub axis: usize,
    /// Whether the face is at +1 (true) or −1 (false) along `axis`.
    pub positive: bool,
    /// Global node ids in face tensor order.
    pub nodes: [usize; 9],
}

/// A mesh of triquadratic hexahedra.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Reference node coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// Element connectivity (tensor order).
    pub elements: Vec<[usize; NODES_PER_ELEMENT]>,
    /// Element colours: no two elements of one colour share a node.
    pub colors: Vec<Vec<usize>>,
}

impl Mesh {
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Greedy element colouring (deterministic: elements in order, smallest free colour).
    pub fn compute_colors(&mut self) {
        let mut node_elems: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (e, conn) in self.elements.iter().enumerate() {
            for &n in conn {
                node_elems[n].push(e);
            }
        }
        let mut color_of = vec![usize::MAX; self.elements.len()];
        let mut colors: Vec<Vec<usize>> = Vec::new();
        let mut used = Vec::new();
        for e in 0..self.elements.len() {
            used.clear();
            for &n in &self.elements[e] {
                for &o in &node_elems[n] {
                    if color_of[o] != usize::MAX {
                        used.push(color_of[o]);
                    }
                }
            }
            let c = (0..).find(|c| !used.contains(c)).unwrap_or(0);
            color_of[e] = c;
            if c == colors.len() {
                colors.push(Vec::new());
            }
            colors[c].push(e);
        }
        self.colors = colors;
    }
}

/// Local node index of tensor position (i, j, k).
#[inline]
pub fn local_index(i: usize, j: usize, k: usize) -> usize {
    i + 3 * j + 9 * k
}

/// The 9 local node indices of a face in outward tensor order.
pub fn face_local_nodes(axis: usize, positive: bool) -> [usize; 9] {
    let d1 = (axis + 1) % 3;
    let d2 = (axis + 2) % 3;
    let fixed = if positive { 2 } else { 0 };
    let mut out = [0; 9];
    for t in 0..3 {
        for s in 0..3 {
            // for the negative face swap s and t so that the normal points outwards
            let (a, b) = if positive { (s, t) } else { (t, s) };
            let mut ijk = [0; 3];
            ijk[axis] = fixed;
            ijk[d1] = a;
            ijk[d2] = b;
            out[s + 3 * t] = local_index(ijk[0], ijk[1], ijk[2]);
        }
    }
    out
}

/// A tensor grid of cells: the element boundaries along each axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TensorGrid {
    /// Cell boundaries along x, y, z (strictly increasing).
    pub lines: [Vec<f64>; 3],
}

impl TensorGrid {
    /// Sorts and deduplicates `breaks`, then subdivides every interval so that no element is
    /// longer than `h`; intervals inside one of `walls` get at least `wall_div` elements.
    pub fn subdivide(breaks: &[f64], walls: &[(f64, f64)], h: f64, wall_div: usize) -> Vec<f64> {
        let mut b: Vec<f64> = breaks.to_vec();
        b.sort_by(f64::total_cmp);
        b.dedup_by(|a, c| (*a - *c).abs() < 1e-9);
        let mut out = vec![b[0]];
        for w in b.windows(2) {
            let len = w[1] - w[0];
            let mid = 0.5 * (w[0] + w[1]);
            let in_wall = walls.iter().any(|&(lo, hi)| mid > lo && mid < hi);
            let min_div = if in_wall { wall_div } else { 1 };
            let n = ((len / h - 1e-9).ceil() as usize).max(min_div).max(1);
            for s in 1..=n {
                out.push(w[0] + len * s as f64 / n as f64);
            }
        }
        out
    }

    /// Number of cells along each axis.
    pub fn cells(&self) -> [usize; 3] {
        [
            self.lines[0].len() - 1,
            self.lines[1].len() - 1,
            self.lines[2].len() - 1,
        ]
    }

    /// Coordinate of grid node `g` (0..=2·cells) along `axis` (odd indices are mid-points).
    pub fn node_coord(&self, axis: usize, g: usize) -> f64 {
        let l = &self.lines[axis];
        if g.is_multiple_of(2) {
            l[g / 2]
        } else {
            0.5 * (l[g / 2] + l[g / 2 + 1])
        }
    }

    /// Centre of cell (i, j, k).
    pub fn cell_center(&self, c: [usize; 3]) -> [f64; 3] {
        std::array::from_fn(|a| 0.5 * (self.lines[a][c[a]] + self.lines[a][c[a] + 1]))
    }
}

/// A mesh generated on a tensor grid, with the bookkeeping to find faces and nodes by position.
#[derive(Clone, Debug)]
pub struct GridMesh<K> {
    /// The mesh.
    pub mesh: Mesh,
    /// The grid in parameter space.
    pub grid: TensorGrid,
    /// Cell kind of every cell (x fastest).
    pub cell_kinds: Vec<K>,
    /// Element id of every cell (None for void cells).
    pub cell_element: Vec<Option<usize>>,
    /// Cell of each element.
    pub element_cell: Vec<[usize; 3]>,
    /// Node id of each grid node (None if no solid cell touches it).
    pub grid_node: Vec<Option<usize>>,
    /// Grid position of each node.
    pub node_grid: Vec<[usize; 3]>,
}

impl<K: Copy + PartialEq> GridMesh<K> {
    /// Builds the mesh of the cells for which `is_solid(kind)` holds.
    pub fn new(
        grid: TensorGrid,
        classify: impl Fn([f64; 3]) -> K,
        is_solid: impl Fn(K) -> bool,
    ) -> Self {
        let [nx, ny, nz] = grid.cells();
        let gdim = [2 * nx + 1, 2 * ny + 1, 2 * nz + 1];
        let gidx = |g: [usize; 3]| g[0] + gdim[0] * (g[1] + gdim[1] * g[2]);
        let mut cell_kinds = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    cell_kinds.push(classify(grid.cell_center([i, j, k])));
                }
            }
        }
        let mut grid_node = vec![None; gdim[0] * gdim[1] * gdim[2]];
        let mut node_grid = Vec::new();
        let mut nodes = Vec::new();
        let mut elements = Vec::new();
        let mut cell_element = vec![None; nx * ny * nz];
        let mut element_cell = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let c = i + nx * (j + ny * k);
                    if !is_solid(cell_kinds[c]) {
                        continue;
                    }
                    let mut conn = [0usize; NODES_PER_ELEMENT];
                    for (l, slot) in conn.iter_mut().enumerate() {
                        let g = [2 * i + l % 3, 2 * j + (l / 3) % 3, 2 * k + l / 9];
                        let id = *grid_node[gidx(g)].get_or_insert_with(|| {
                            nodes.push(std::array::from_fn(|a| grid.node_coord(a, g[a])));
                            node_grid.push(g);
                            nodes.len() - 1
                        });
                        *slot = id;
                    }
                    cell_element[c] = Some(elements.len());
                    elements.push(conn);
                    element_cell.push([i, j, k]);
                }
            }
        }
        let mut mesh = Mesh {
            nodes,
            elements,
            colors: Vec::new(),
        };
        mesh.compute_colors();
        Self {
            mesh,
            grid,
            cell_kinds,
            cell_element,
            element_cell,
            grid_node,
            node_grid,
        }
    }

    /// Kind of cell `c` (None outside the grid).
    pub fn cell_kind(&self, c: [isize; 3]) -> Option<K> {
        let n = self.grid.cells();
        if (0..3).any(|a| c[a] < 0 || c[a] as usize >= n[a]) {
            return None;
        }
        let (i, j, k) = (c[0] as usize, c[1] as usize, c[2] as usize);
        Some(self.cell_kinds[i + n[0] * (j + n[1] * k)])
    }

    /// All element faces whose neighbouring cell (across the face) satisfies `pred`
    /// (`None` = outside the grid). Returns the faces with the neighbour's kind.
    pub fn boundary_faces(&self, pred: impl Fn(Option<K>) -> bool) -> Vec<(Face, Option<K>)> {
        let mut out = Vec::new();
        for (e, cell) in self.element_cell.iter().enumerate() {
            for axis in 0..3 {
                for positive in [false, true] {
                    let mut nb = [cell[0] as isize, cell[1] as isize, cell[2] as isize];
                    nb[axis] += if positive { 1 } else { -1 };
                    let kind = self.cell_kind(nb);
                    if pred(kind) {
                        let local = face_local_nodes(axis, positive);
                        let conn = &self.mesh.elements[e];
                        out.push((
                            Face {
                                element: e,
                                axis,
                                positive,
                                nodes: local.map(|l| conn[l]),
                            },
                            kind,
                        ));
                    }
                }
            }
        }
        out
    }

    /// Nodes whose parameter coordinate along `axis` equals `value`.
    pub fn nodes_on_plane(&self, axis: usize, value: f64) -> Vec<usize> {
        (0..self.mesh.nodes.len())
            .filter(|&n| (self.grid.node_coord(axis, self.node_grid[n][axis]) - value).abs() < 1e-9)
            .collect()
    }

    /// Maps every node from parameter space to physical space.
    pub fn map_nodes(&mut self, f: impl Fn([f64; 3]) -> [f64; 3]) {
        for x in &mut self.mesh.nodes {
            *x = f(*x);
        }
    }

    /// The element containing parameter point `x` and its local coordinates ξ ∈ [−1, 1]³
    /// (None if the point is not in a solid cell).
    pub fn locate(&self, x: [f64; 3]) -> Option<(usize, [f64; 3])> {
        let n = self.grid.cells();
        let mut cell = [0usize; 3];
        let mut xi = [0.0; 3];
        for a in 0..3 {
            let l = &self.grid.lines[a];
            if x[a] < l[0] - 1e-9 || x[a] > l[n[a]] + 1e-9 {
                return None;
            }
            let c = l
                .partition_point(|&v| v <= x[a])
                .saturating_sub(1)
                .min(n[a] - 1);
            cell[a] = c;
            xi[a] = (2.0 * (x[a] - l[c]) / (l[c + 1] - l[c]) - 1.0).clamp(-1.0, 1.0);
        }
        let idx = cell[0] + n[0] * (cell[1] + n[1] * cell[2]);
        self.cell_element[idx].map(|e| (e, xi))
    }
}

/// Mesh refinement levels of the actuator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MeshLevel {
    /// Quick looks, tests and snapshots: h = 6 mm, one element through a wall.
    Coarse,
    /// Production level: h = 3 mm, two elements through a wall.
    Standard,
    /// Convergence studies: h = 2 mm, three elements through a wall.
    Fine,
}

impl MeshLevel {
    /// Target element size h (mm) and minimum number of elements through a wall.
    pub fn sizing(self) -> (f64, usize) {
        match self {
            MeshLevel::Coarse => (6.0, 1),
            MeshLevel::Standard => (3.0, 2),
            MeshLevel::Fine => (2.0, 3),
        }
    }
    /// Name as used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MeshLevel::Coarse => "coarse",
            MeshLevel::Standard => "standard",
            MeshLevel::Fine => "fine",
        }
    }
}

impl std::str::FromStr for MeshLevel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "coarse" => Ok(Self::Coarse),
            "standard" => Ok(Self::Standard),
            "fine" => Ok(Self::Fine),
            _ => Err(format!(
                "unknown mesh level '{s}': expected coarse, standard or fine"
            )),
        }
    }
}

/// Mesh options: a level, optionally overridden by an explicit element size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshOptions {
    /// Refinement level.
    pub level: MeshLevel,
    /// Element size override (mm); through-wall count becomes ceil(T / h).
    pub element_size: Option<f64>,
    /// Override of the minimum number of elements through a wall.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_elements: Option<usize>,
}

impl MeshOptions {
    /// Checks the overrides: an element size in (0.2, 50] mm, 1 to 8 elements through a wall.
    ///
    /// # Errors
    /// [`crate::fe::InvalidSetting`] naming `element_size` or `wall_elements`.
    pub fn validate(&self) -> Result<(), crate::fe::InvalidSetting> {
        if let Some(h) = self.element_size {
            if !(h.is_finite() && h > 0.2 && h <= 50.0) {
                return Err(crate::fe::InvalidSetting::new(
                    "element_size",
                    h,
                    "an element size in (0.2, 50] mm",
                ));
            }
        }
        if let Some(k) = self.wall_elements {
            if !(1..=8).contains(&k) {
                return Err(crate::fe::InvalidSetting::new(
                    "wall_elements",
                    k as f64,
                    "1 to 8 elements through a wall",
                ));
            }
        }
        Ok(())
    }

    /// Options of a level without override.
    pub fn level(level: MeshLevel) -> Self {
        Self {
            level,
            element_size: None,
            wall_elements: None,
        }
    }
    fn sizing(&self) -> (f64, usize) {
        let (h, div) = match self.element_size {
            Some(h) => (h, 1),
            None => self.level.sizing(),
        };
        (h, self.wall_elements.unwrap_or(div).max(1))
    }
}

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

/// The piecewise-linear map with `from[i] ↦ to[i]` at `x` (constant slope beyond the ends).
fn piecewise_linear(from: &[f64], to: &[f64], x: f64) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::geometry::DesignParams;

    #[test]
    fn mesh_options_name_the_bad_override() {
        let mut o = MeshOptions::level(MeshLevel::Coarse);
        o.validate().expect("a level without override");
        o.element_size = Some(0.1);
        assert_eq!(o.validate().unwrap_err().field, "element_size");
        o.element_size = Some(2.0);
        o.wall_elements = Some(0);
        assert_eq!(o.validate().unwrap_err().field, "wall_elements");
        o.wall_elements = Some(3);
        o.validate().expect("valid overrides");
    }

    #[test]
    fn a_moved_mesh_is_the_mesh_of_the_moved_design_when_the_element_counts_agree() {
        let opts = MeshOptions::level(MeshLevel::Coarse);
        let nominal = DesignParams::new(9, 2.0).validate().unwrap();
        let mesh = ActuatorMesh::new(&nominal, &opts);
        let same = mesh.moved(&nominal, &nominal).unwrap();
        assert_eq!(same.mesh().nodes, mesh.mesh().nodes);
        let mut p = nominal.params().clone();
        p.skin_thickness = Some(2.05);
        p.gap += 0.03;
        p.free_length -= 0.2;
        let printed = p.validate().unwrap();
        let moved = mesh.moved(&nominal, &printed).unwrap();
        let fresh = ActuatorMesh::new(&printed, &opts);
        assert_eq!(moved.mesh().elements, fresh.mesh().elements);
        for (a, b) in moved.mesh().nodes.iter().zip(&fresh.mesh().nodes) {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-12, "{a:?} vs {b:?}");
            }
        }
        assert_eq!(moved.markers, fresh.markers);
        // another number of bellows is not a motion
        let other = DesignParams::new(11, 2.0).validate().unwrap();
        assert!(mesh.moved(&nominal, &other).is_err());
    }

    #[test]
    fn face_nodes_are_outward() {
        // reference element node coordinates in tensor order
        let pos = |l: usize| {
            [
                (l % 3) as f64 - 1.0,
                ((l / 3) % 3) as f64 - 1.0,
                (l / 9) as f64 - 1.0,
            ]
        };
        for axis in 0..3 {
            for positive in [false, true] {
                let f = face_local_nodes(axis, positive);
                let x0 = pos(f[0]);
                let xs = pos(f[1]);
                let xt = pos(f[3]);
                let a = [xs[0] - x0[0], xs[1] - x0[1], xs[2] - x0[2]];
                let b = [xt[0] - x0[0], xt[1] - x0[1], xt[2] - x0[2]];
                let n = [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ];
                let sign = if positive { 1.0 } else { -1.0 };
                assert!(n[axis] * sign > 0.0, "axis {axis} positive {positive}");
                assert!(f.iter().all(|&l| pos(l)[axis] == sign));
            }
        }
    }

    #[test]
    fn levels_are_one_refinement_family() {
        let d = DesignParams::new(11, 2.0).validate().unwrap();
        let elements = |o: MeshOptions| ActuatorMesh::new(&d, &o).mesh().n_elements();
        let coarse = elements(MeshOptions::level(MeshLevel::Coarse));
        let standard = elements(MeshOptions::level(MeshLevel::Standard));
        let fine = elements(MeshOptions::level(MeshLevel::Fine));
        // h 6 → 3 → 2 and 1 → 2 → 3 elements through a wall; segments shorter than h (the
        // 1 mm gaps) keep one element, so the counts grow by less than 8 and 27
        assert!(
            (4 * coarse..=8 * coarse).contains(&standard),
            "{coarse} → {standard}"
        );
        assert!(
            (2 * standard..=4 * standard).contains(&fine),
            "{standard} → {fine}"
        );
        // the wall override adds elements through the walls only
        let mut o = MeshOptions::level(MeshLevel::Coarse);
        o.wall_elements = Some(2);
        let w2 = elements(o);
        assert!(w2 > coarse && w2 < standard, "{coarse} → {w2}");
    }

    #[test]
    fn actuator_mesh_has_all_sets() {
        let d = DesignParams::new(11, 2.0).validate().unwrap();
        let m = ActuatorMesh::new(&d, &MeshOptions::level(MeshLevel::Coarse));
        assert_eq!(m.pressure_faces.len(), 12); // 11 cavities + duct
        assert_eq!(m.gap_faces.len(), 21); // 10 gaps × 2 sides + clamp
        assert_eq!(m.markers.len(), 9);
        assert!(!m.support.is_empty() && !m.symmetry.is_empty());
        for c in &m.mesh().colors {
            let mut seen = std::collections::HashSet::new();
            for &e in c {
                for &n in &m.mesh().elements[e] {
                    assert!(seen.insert(n), "colour shares node {n}");
                }
            }
        }
    }
    #[test]
    fn fused_gaps_and_filleted_cavities_are_meshed_on_their_lines() {
        let mut p = DesignParams::new(13, 2.4);
        p.gap_floor = Some(3.0);
        p.cavity_fillet = Some(1.0);
        let d = p.validate().unwrap();
        let m = ActuatorMesh::new(&d, &MeshOptions::level(MeshLevel::Coarse));
        let nodes = &m.mesh().nodes;
        // contact faces of the gaps between bellows lie above the gaps' floor only
        let floor = d.base_thickness() + 3.0;
        for (side, faces) in &m.gap_faces {
            if *side == GapSide::Clamp {
                continue;
            }
            for f in faces {
                let lowest = f
                    .nodes
                    .iter()
                    .map(|&n| nodes[n][1])
                    .fold(f64::MAX, f64::min);
                assert!(
                    lowest >= floor - 1e-9,
                    "{side:?}: a face reaches y = {lowest}"
                );
            }
        }
        // the raised floor of a short cavity is a grid line: its pressurised faces start there
        let c = d.cavity(5);
        let faces = &m.pressure_faces[&PressureSurface::Cavity(5)];
        let lowest = faces
            .iter()
            .flat_map(|f| f.nodes.iter().map(|&n| nodes[n][1]))
            .fold(f64::MAX, f64::min);
        assert!((lowest - (c.lo[1] + 1.0)).abs() < 1e-9, "{lowest}");
        // without them, the gap faces reach the base
        let plain = DesignParams::new(13, 2.4).validate().unwrap();
        let m = ActuatorMesh::new(&plain, &MeshOptions::level(MeshLevel::Coarse));
        let lowest = m.gap_faces[&GapSide::Back(0)]
            .iter()
            .flat_map(|f| f.nodes.iter().map(|&n| m.mesh().nodes[n][1]))
            .fold(f64::MAX, f64::min);
        assert!((lowest - plain.base_thickness()).abs() < 1e-9);
    }
}
