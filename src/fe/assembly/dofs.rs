//! Degrees of freedom and the sparse pattern: which displacement components are unknowns
//! ([`DofMap`]) and where each element's (and each contact pair's) entries sit in the
//! lower-triangular CSC tangent ([`Pattern`]).

// Index loops mirror the local (row, column) layout of the element matrices.
#![allow(clippy::needless_range_loop)]

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::fe::contact::FacePair;
use crate::fe::element::DOFS;
use crate::fe::mesh::Mesh;

/// A prescribed displacement component: `u[node][comp] = λ_u · value`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Constraint {
    /// Node id.
    pub node: usize,
    /// Component 0..3.
    pub comp: usize,
    /// Prescribed value at full load.
    pub value: f64,
}

/// Map from global dofs (3·node + comp) to free equation numbers.
#[derive(Clone, Debug)]
pub struct DofMap {
    /// Free equation number of each dof (`u32::MAX` if constrained).
    pub free: Vec<u32>,
    /// Number of free equations.
    pub n_free: usize,
    /// Constrained dofs with their full-load values.
    pub constrained: Vec<(usize, f64)>,
}

impl DofMap {
    /// Numbers the free dofs node by node.
    pub fn new(n_nodes: usize, constraints: &[Constraint]) -> Self {
        let mut value = vec![None; 3 * n_nodes];
        for c in constraints {
            value[3 * c.node + c.comp] = Some(c.value);
        }
        let mut free = vec![u32::MAX; 3 * n_nodes];
        let mut n_free = 0;
        let mut constrained = Vec::new();
        for (d, v) in value.iter().enumerate() {
            match v {
                None => {
                    free[d] = n_free as u32;
                    n_free += 1;
                }
                Some(v) => constrained.push((d, *v)),
            }
        }
        Self {
            free,
            n_free,
            constrained,
        }
    }
    /// Free equation of dof `d`, if free.
    #[inline]
    pub fn eq(&self, d: usize) -> Option<usize> {
        let f = self.free[d];
        (f != u32::MAX).then_some(f as usize)
    }
}

/// Lower-triangular CSC pattern of the free equations with per-element scatter maps.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// Column pointers.
    pub col_ptr: Vec<usize>,
    /// Row indices (sorted within each column, rows ≥ column).
    pub row_idx: Vec<usize>,
    /// For each element, position in the value array of local entry (r, c) (row-major 81×81),
    /// `u32::MAX` if not stored (constrained, or above the diagonal).
    pub element_map: Vec<Vec<u32>>,
}

impl Pattern {
    /// Builds the pattern of a mesh plus extra node couplings (e.g. contact pairs).
    pub fn new(mesh: &Mesh, dofs: &DofMap, extra: &[(usize, usize)]) -> Self {
        let n_nodes = mesh.n_nodes();
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n_nodes];
        for conn in &mesh.elements {
            for &a in conn {
                adj[a].extend_from_slice(conn);
            }
        }
        for &(a, b) in extra {
            adj[a].push(b);
            adj[b].push(a);
        }
        for l in adj.iter_mut() {
            l.sort_unstable();
            l.dedup();
        }
        let mut col_ptr = vec![0usize; dofs.n_free + 1];
        let mut row_idx = Vec::new();
        // columns in increasing free order: free numbering is node-major, so iterate nodes.
        let mut rows = Vec::new();
        for n in 0..n_nodes {
            for c in 0..3 {
                let Some(col) = dofs.eq(3 * n + c) else {
                    continue;
                };
                rows.clear();
                for &m in &adj[n] {
                    for k in 0..3 {
                        if let Some(r) = dofs.eq(3 * m + k) {
                            if r >= col {
                                rows.push(r);
                            }
                        }
                    }
                }
                rows.sort_unstable();
                row_idx.extend_from_slice(&rows);
                col_ptr[col + 1] = row_idx.len();
            }
        }
        let mut pat = Self {
            col_ptr,
            row_idx,
            element_map: Vec::new(),
        };
        pat.element_map = mesh
            .elements
            .par_iter()
            .map(|conn| {
                let mut map = vec![u32::MAX; DOFS * DOFS];
                for (r, slot_row) in map.chunks_mut(DOFS).enumerate() {
                    let Some(gr) = dofs.eq(3 * conn[r / 3] + r % 3) else {
                        continue;
                    };
                    for (c, slot) in slot_row.iter_mut().enumerate() {
                        let Some(gc) = dofs.eq(3 * conn[c / 3] + c % 3) else {
                            continue;
                        };
                        if gr >= gc {
                            *slot = pat.position(gr, gc).unwrap_or(u32::MAX as usize) as u32;
                        }
                    }
                }
                map
            })
            .collect();
        pat
    }

    /// Position of entry (row, col) (row ≥ col) in the value array.
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let (s, e) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[s..e].binary_search(&row).ok().map(|p| s + p)
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }
}

/// Node couplings that a list of face pairs adds to the sparse pattern.
pub fn pair_couplings(pairs: &[FacePair]) -> Vec<(usize, usize)> {
    let mut out = Vec::with_capacity(pairs.len() * 81);
    for p in pairs {
        for &a in &p.back {
            for &b in &p.front {
                out.push((a, b));
            }
        }
    }
    out
}
