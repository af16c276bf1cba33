//! The scatter of local systems into the global one: [`GlobalSystem`], and
//! [`ColouredScatter`], which owns the element colouring and the one `unsafe` of the
//! assembly.
//!
//! Elements are assembled colour by colour: two elements of one colour share no node, so
//! their writes never collide, and every global entry receives its contributions in the same
//! order whatever the number of threads (results do not depend on the thread count).

use rayon::prelude::*;

use crate::fe::element::DOFS;

/// The global arrays being assembled.
pub struct GlobalSystem<'a> {
    /// Residual on all degrees of freedom.
    pub residual: &'a mut [f64],
    /// The part of the residual that is external force from the follower pressure (for the
    /// convergence test's force scale).
    pub external: &'a mut [f64],
    /// Values of the tangent's lower triangle on the free unknowns, if wanted.
    pub tangent: Option<&'a mut [f64]>,
}

impl GlobalSystem<'_> {
    /// Adds one local system serially: `residual[3·nodes[l] + c] += r[3l + c]`, and each local
    /// tangent entry `k[i]` at position `map[i]` of the tangent's values (`u32::MAX`: not
    /// stored).
    pub fn add_local(&mut self, nodes: &[usize], r: &[f64], map: &[u32], k: Option<&[f64]>) {
        for (l, &n) in nodes.iter().enumerate() {
            for c in 0..3 {
                self.residual[3 * n + c] += r[3 * l + c];
            }
        }
        if let (Some(values), Some(k)) = (self.tangent.as_deref_mut(), k) {
            for (slot, kv) in map.iter().zip(k) {
                if *slot != u32::MAX {
                    values[*slot as usize] += *kv;
                }
            }
        }
    }
}

/// What an element's local computation leaves for the scatter: residual and external force
/// per local dof (27 nodes × 3), and the row-major 81 × 81 tangent.
pub trait LocalVectors {
    /// Local residual.
    fn residual(&self) -> &[f64];
    /// Local external force (the pressure part of the residual).
    fn external(&self) -> &[f64; DOFS];
    /// Local tangent, row-major.
    fn tangent(&self) -> &[f64];
}

/// The elements of a mesh in colours (no two elements of a colour share a node), with their
/// connectivity and their tangent scatter maps.
pub struct ColouredScatter<'m> {
    /// Element ids by colour.
    pub colors: &'m [Vec<usize>],
    /// Connectivity.
    pub elements: &'m [[usize; 27]],
    /// Per element: position in the tangent's values of local entry (row, col), row-major
    /// 81 × 81 (`u32::MAX` if not stored).
    pub maps: &'m [Vec<u32>],
}

/// A raw pointer into a global array shared by the tasks of one colour.
struct SharedMut(*mut f64);
// SAFETY: used only for writes that are disjoint within one colour (see `ColouredScatter::run`).
unsafe impl Send for SharedMut {}
unsafe impl Sync for SharedMut {}

impl SharedMut {
    /// Adds `v` at offset `i`.
    ///
    /// # Safety
    /// `i` must be in bounds and no other thread may access offset `i` concurrently.
    #[inline]
    unsafe fn add(&self, i: usize, v: f64) {
        *self.0.add(i) += v;
    }
}

impl ColouredScatter<'_> {
    /// For every element, colour by colour, in parallel within a colour: `local(work, e)`
    /// computes the element's local system into `work` (a per-thread scratch made by `init`)
    /// and returns its other outputs, then the local system is added to `global`. `reduce`
    /// receives every element's output, colour by colour in element order (a fixed order);
    /// the first error, in that order, ends the assembly.
    ///
    /// # Errors
    /// The first error of `local` or `reduce`.
    pub fn run<W, T, E>(
        &self,
        global: &mut GlobalSystem<'_>,
        init: impl Fn() -> W + Sync + Send,
        local: impl Fn(&mut W, usize) -> Result<T, E> + Sync + Send,
        mut reduce: impl FnMut(T) -> Result<(), E>,
    ) -> Result<(), E>
    where
        W: LocalVectors,
        T: Send,
        E: Send,
    {
        let n = global.residual.len();
        assert_eq!(
            global.external.len(),
            n,
            "external force has the residual's length"
        );
        let with_k = global.tangent.is_some();
        let n_k = global.tangent.as_deref().map_or(0, <[f64]>::len);
        let r_ptr = SharedMut(global.residual.as_mut_ptr());
        let p_ptr = SharedMut(global.external.as_mut_ptr());
        let k_ptr = SharedMut(
            global
                .tangent
                .as_deref_mut()
                .map_or(std::ptr::null_mut(), <[f64]>::as_mut_ptr),
        );
        for color in self.colors {
            let results: Vec<Result<T, E>> = color
                .par_iter()
                .map_init(&init, |work, &e| {
                    let out = local(work, e)?;
                    let conn = &self.elements[e];
                    let (r, p) = (work.residual(), work.external());
                    debug_assert!(conn.iter().all(|&node| 3 * node + 2 < n));
                    // SAFETY: elements of one colour share no node, so the dofs and matrix
                    // entries written here are written by no other task of this colour; the
                    // offsets are in bounds (dofs of the mesh's nodes, positions of the
                    // pattern's values, checked against the lengths in debug builds).
                    unsafe {
                        for (l, &node) in conn.iter().enumerate() {
                            for i in 0..3 {
                                r_ptr.add(3 * node + i, r[3 * l + i]);
                                p_ptr.add(3 * node + i, p[3 * l + i]);
                            }
                        }
                        if with_k {
                            for (pos, kv) in self.maps[e].iter().zip(work.tangent()) {
                                if *pos != u32::MAX {
                                    debug_assert!((*pos as usize) < n_k);
                                    k_ptr.add(*pos as usize, *kv);
                                }
                            }
                        }
                    }
                    Ok(out)
                })
                .collect();
            for r in results {
                reduce(r?)?;
            }
        }
        Ok(())
    }
}
