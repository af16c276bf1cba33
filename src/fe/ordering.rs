//! Fill-reducing orderings for the sparse LDLᵀ: nested dissection (METIS) on the node graph.
//!
//! faer orders with approximate minimum degree (AMD) by default. On the actuator, the contact
//! pairs couple the facing walls of neighbouring bellows over their whole area, so a cut across
//! the actuator must contain a wall: AMD then fills the factor far more than the mesh alone
//! would. Nested dissection finds those separators.
//!
//! [`super::solver::LinearSolver::new`] computes both symbolic factorisations once per model
//! and keeps the smaller factor: nested dissection on the standard mesh, AMD on the coarse
//! one. METIS runs with a fixed seed on one thread: the ordering, and hence every result,
//! does not depend on the number of threads. The fill and factorisation times of both
//! orderings are in `docs/SOLVER_MEASUREMENTS.md`.

use super::assembly::{DofMap, Pattern};

/// METIS's random seed (METIS is deterministic for a given seed).
const METIS_SEED: i32 = 7;

/// METIS keeps its random-number state in globals (GKlib's Mersenne twister), so two calls on
/// different threads at once interleave their draws and give different orderings. Every call
/// holds this lock: the ordering is the same whatever else runs.
static METIS_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Nested-dissection ordering of the free equations, computed by METIS on the graph of the
/// nodes that carry free equations (each node's equations stay together, in their order).
///
/// Returns `perm` with `perm[new] = old` (free equation numbers), or `None` if METIS fails or
/// the graph is too small to need it (fewer than 2 nodes).
pub fn nested_dissection(pattern: &Pattern, dofs: &DofMap) -> Option<Vec<usize>> {
    let n = dofs.n_free;
    let n_nodes = dofs.free.len() / 3;
    let mut eq_node = vec![0usize; n];
    for (d, &f) in dofs.free.iter().enumerate() {
        if f != u32::MAX {
            eq_node[f as usize] = d / 3;
        }
    }
    // vertices: nodes with a free equation, numbered by their first equation
    let mut vertex = vec![usize::MAX; n_nodes];
    let mut eqs: Vec<Vec<usize>> = Vec::new();
    for (e, &nd) in eq_node.iter().enumerate() {
        if vertex[nd] == usize::MAX {
            vertex[nd] = eqs.len();
            eqs.push(Vec::with_capacity(3));
        }
        eqs[vertex[nd]].push(e);
    }
    let nv = eqs.len();
    if nv < 2 {
        return None;
    }
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nv];
    for c in 0..n {
        let b = vertex[eq_node[c]];
        for &r in &pattern.row_idx[pattern.col_ptr[c]..pattern.col_ptr[c + 1]] {
            let a = vertex[eq_node[r]];
            if a != b {
                adj[a].push(b);
                adj[b].push(a);
            }
        }
    }
    let mut xadj = Vec::with_capacity(nv + 1);
    xadj.push(0i32);
    let mut adjncy = Vec::new();
    for list in &mut adj {
        list.sort_unstable();
        list.dedup();
        adjncy.extend(list.iter().map(|&v| i32::try_from(v).ok()));
        xadj.push(i32::try_from(adjncy.len()).ok()?);
    }
    let mut adjncy: Vec<i32> = adjncy.into_iter().collect::<Option<_>>()?;
    let node_perm = metis_node_nd(&mut xadj, &mut adjncy)?;
    let mut perm = Vec::with_capacity(n);
    for v in node_perm {
        perm.extend_from_slice(&eqs[v]);
    }
    Some(perm)
}

/// `METIS_NodeND` on a graph in CSR form (symmetric, no self loops); `perm[new] = old`.
fn metis_node_nd(xadj: &mut [i32], adjncy: &mut [i32]) -> Option<Vec<usize>> {
    let mut nv = i32::try_from(xadj.len() - 1).ok()?;
    let mut options = [0i32; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0i32; xadj.len() - 1];
    let mut iperm = vec![0i32; xadj.len() - 1];
    // SAFETY: `options` has METIS_NOPTIONS entries, as METIS_SetDefaultOptions requires.
    unsafe { metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr()) };
    options[metis_sys::moptions_et_METIS_OPTION_SEED as usize] = METIS_SEED;
    // a poisoned lock only means another call panicked; METIS's state is reseeded below
    let _serial = METIS_LOCK
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    // SAFETY: `xadj` has nv + 1 entries, `adjncy` xadj[nv] entries, all in 0..nv (built by
    // the caller from a symmetric adjacency); `perm` and `iperm` have nv entries; a null
    // vertex-weight pointer means unit weights. METIS writes only `perm` and `iperm`.
    let status = unsafe {
        metis_sys::METIS_NodeND(
            &mut nv,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return None;
    }
    perm.into_iter().map(|p| usize::try_from(p).ok()).collect()
}
