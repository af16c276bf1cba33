//! A mesh generated on a tensor grid of cells, some of them void, with the bookkeeping to find
//! faces and nodes by position.

use serde::{Deserialize, Serialize};

use super::hex::{face_local_nodes, Face, Mesh, NODES_PER_ELEMENT};

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

    /// The element containing parameter point `x`, or touching it within `tol` of its
    /// closed cell, and its local coordinates ξ ∈ [−1, 1]³ (clamped). Unlike [`Self::locate`],
    /// a point on a grid line between a solid and a void cell (or just outside a solid cell,
    /// by rounding) is found in the solid one: every cell within `tol` along each axis is
    /// tried, lowest first. None if no solid cell is that close.
    pub fn locate_within(&self, x: [f64; 3], tol: f64) -> Option<(usize, [f64; 3])> {
        let n = self.grid.cells();
        let mut candidates: [Vec<usize>; 3] = Default::default();
        for (a, cand) in candidates.iter_mut().enumerate() {
            let l = &self.grid.lines[a];
            let lo = l.partition_point(|&v| v < x[a] - tol).saturating_sub(1);
            *cand = (lo..n[a])
                .take_while(|&c| l[c] <= x[a] + tol)
                .filter(|&c| l[c + 1] >= x[a] - tol)
                .collect();
        }
        for &k in &candidates[2] {
            for &j in &candidates[1] {
                for &i in &candidates[0] {
                    let c = [i, j, k];
                    if let Some(e) = self.cell_element[i + n[0] * (j + n[1] * k)] {
                        let xi = std::array::from_fn(|a| {
                            let l = &self.grid.lines[a];
                            let (lo, hi) = (l[c[a]], l[c[a] + 1]);
                            (2.0 * (x[a] - lo) / (hi - lo) - 1.0).clamp(-1.0, 1.0)
                        });
                        return Some((e, xi));
                    }
                }
            }
        }
        None
    }
}
