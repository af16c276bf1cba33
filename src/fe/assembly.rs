//! Global assembly: degrees of freedom, the sparse pattern (lower triangle, CSC) and the
//! parallel, thread-count-independent assembly of residual and tangent.
//!
//! The residual is `r(u) = f_int(u) + f_pressure(u) − λ_g f_gravity − λ_t f_traction`
//! (pressure enters `r` with its follower sign, see [`super::loads`]). Elements are assembled
//! colour by colour: two elements of one colour share no node, so their writes never collide
//! and every matrix entry receives its contributions in the same order whatever the number of
//! threads.

// Index loops mirror the tensor index notation of the equations above (a, b: nodes;
// i, j, k, l: components); iterator chains would hide it.
#![allow(clippy::needless_range_loop)]

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::contact::{self, ContactError, FacePair, PairSettings, RigidPlane, PAIR_DOFS};
use super::element::{self, ElementError, ElementGeometry, ElementWork, DOFS};
use super::loads;
use super::material::Material;
use super::mesh::{face_local_nodes, Face, Mesh};

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

/// A pressurised face attached to its element.
#[derive(Clone, Copy, Debug)]
pub struct PressureFace {
    /// Element-local node indices of the face (outward order).
    pub local: [usize; 9],
    /// Pressure multiplier of this face (1 for the nominal pressure).
    pub scale: f64,
}

/// Load factors of one state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LoadLevel {
    /// Cavity pressure (MPa).
    pub pressure: f64,
    /// Gravity factor (1 = full self-weight).
    pub gravity: f64,
    /// Dead-traction factor.
    pub traction: f64,
    /// Prescribed-displacement factor.
    pub prescribed: f64,
}

impl LoadLevel {
    /// Linear interpolation between two levels.
    pub fn lerp(&self, other: &Self, s: f64) -> Self {
        let l = |a: f64, b: f64| a + s * (b - a);
        Self {
            pressure: l(self.pressure, other.pressure),
            gravity: l(self.gravity, other.gravity),
            traction: l(self.traction, other.traction),
            prescribed: l(self.prescribed, other.prescribed),
        }
    }
}

/// The discretised model: mesh, material, constraints and loads, ready to assemble.
pub struct FeModel {
    /// The mesh.
    pub mesh: Mesh,
    /// Reference data per element.
    pub geometry: Vec<ElementGeometry>,
    /// The material.
    pub material: Material,
    /// Degrees of freedom.
    pub dofs: DofMap,
    /// Sparse pattern.
    pub pattern: Pattern,
    /// Pressure faces per element.
    pub pressure_faces: Vec<Vec<PressureFace>>,
    /// Gravity load vector (all dofs) at factor 1.
    pub f_gravity: Vec<f64>,
    /// Dead-traction load vector (all dofs) at factor 1.
    pub f_traction: Vec<f64>,
    /// Origin of the pressure potential (see [`FeModel::assemble_with_energy`]).
    pub pressure_origin: [f64; 3],
    /// Rigid planes faces may touch (at most [`MAX_PLANES`]).
    pub planes: Vec<RigidPlane>,
    /// Per element: (plane index, element-local face nodes) of its faces in contact search.
    pub contact_faces: Vec<Vec<(usize, [usize; 9])>>,
    /// Facing face pairs of deformable–deformable contact.
    pub pairs: Vec<FacePair>,
    /// Penalty settings of the face pairs.
    pub pair_settings: PairSettings,
    /// Per pair: position in the tangent's value array of local entry (row, col) (row-major
    /// 54 × 54, `u32::MAX` if not stored).
    pair_maps: Vec<Vec<u32>>,
    /// Augmented-Lagrangian gap shifts ([`contact::update_shift`]) of the plane-contact faces,
    /// per element in the order of `contact_faces`, one per quadrature point (f64 bits; set
    /// between Newton solves, read by the parallel assembly).
    plane_shifts: Vec<Vec<[AtomicU64; 9]>>,
    /// Gap shifts of the face pairs.
    pair_shifts: Vec<[AtomicU64; 9]>,
}

fn load_shifts(a: &[AtomicU64; 9]) -> [f64; 9] {
    std::array::from_fn(|q| f64::from_bits(a[q].load(Ordering::Relaxed)))
}

fn zero_shifts() -> [AtomicU64; 9] {
    std::array::from_fn(|_| AtomicU64::new(0.0f64.to_bits()))
}

/// What one Uzawa update of the contact gap shifts did ([`FeModel::update_contact_shifts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShiftUpdate {
    /// Largest change of a contact point's multiplier divided by the penalty stiffness (mm):
    /// how far the penalty's contact surface was from the true one.
    pub max_change: f64,
    /// Contact points carrying pressure.
    pub active_points: usize,
    /// Whether the shifts were changed (the change exceeded the tolerance).
    pub applied: bool,
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

/// Largest number of rigid planes in one model.
pub const MAX_PLANES: usize = 4;

/// Information returned by an assembly.
#[derive(Clone, Copy, Debug, Default)]
pub struct AssemblyInfo {
    /// Total potential (only from [`FeModel::assemble_with_energy`]; 0 otherwise).
    pub energy: f64,
    /// Euclidean norm of the external forces (pressure + dead loads) on the free dofs.
    pub external_norm: f64,
    /// Normal reaction of each rigid plane on the body (N).
    pub plane_forces: [f64; MAX_PLANES],
    /// Smallest gap at a contact quadrature point of each plane (mm).
    pub plane_min_gaps: [f64; MAX_PLANES],
    /// Total normal force transmitted by the face pairs (N).
    pub pair_force: f64,
    /// Smallest gap at a quadrature point of the face pairs (mm).
    pub pair_min_gap: f64,
}

/// Energy, plane forces and smallest plane gaps of one element.
type ElementOutput = (f64, [f64; MAX_PLANES], [f64; MAX_PLANES]);

struct SharedMut(*mut f64);
// SAFETY: used only for writes that are disjoint within one colour (see `assemble`).
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

impl FeModel {
    /// Builds a model.
    ///
    /// # Errors
    /// [`ElementError::Degenerate`] if an element's reference geometry is invalid.
    pub fn new(
        mesh: Mesh,
        material: Material,
        constraints: &[Constraint],
        pressure_faces: &[(Face, f64)],
        extra_couplings: &[(usize, usize)],
    ) -> Result<Self, ElementError> {
        let geometry = mesh
            .elements
            .par_iter()
            .enumerate()
            .map(|(e, conn)| ElementGeometry::new(e, &conn.map(|n| mesh.nodes[n])))
            .collect::<Result<Vec<_>, _>>()?;
        let dofs = DofMap::new(mesh.n_nodes(), constraints);
        let pattern = Pattern::new(&mesh, &dofs, extra_couplings);
        let mut per_elem = vec![Vec::new(); mesh.n_elements()];
        for (f, scale) in pressure_faces {
            per_elem[f.element].push(PressureFace {
                local: face_local_nodes(f.axis, f.positive),
                scale: *scale,
            });
        }
        let n = 3 * mesh.n_nodes();
        Ok(Self {
            geometry,
            material,
            dofs,
            pattern,
            pressure_faces: per_elem,
            f_gravity: vec![0.0; n],
            f_traction: vec![0.0; n],
            pressure_origin: [0.0; 3],
            planes: Vec::new(),
            contact_faces: vec![Vec::new(); mesh.n_elements()],
            plane_shifts: (0..mesh.n_elements()).map(|_| Vec::new()).collect(),
            pair_shifts: Vec::new(),
            pairs: Vec::new(),
            pair_settings: PairSettings {
                stiffness: 0.0,
                smoothing: 0.0,
                closest_point: false,
            },
            pair_maps: Vec::new(),
            mesh,
        })
    }

    /// Sets the face pairs of deformable–deformable contact. Their node couplings
    /// ([`pair_couplings`]) must have been passed to [`Self::new`].
    ///
    /// # Errors
    /// [`ContactError::MissingCoupling`] if the pattern lacks a coupling;
    /// [`ContactError::OutOfRange`] for a non-positive stiffness or negative smoothing.
    pub fn set_face_pairs(
        &mut self,
        pairs: Vec<FacePair>,
        settings: PairSettings,
    ) -> Result<(), ContactError> {
        // validates the settings like a plane's
        RigidPlane::new(
            [0.0; 3],
            [0.0, 0.0, 1.0],
            settings.stiffness,
            settings.smoothing,
        )?;
        let mut maps = Vec::with_capacity(pairs.len());
        for p in &pairs {
            let nodes: Vec<usize> = p.back.iter().chain(&p.front).copied().collect();
            let mut map = vec![u32::MAX; PAIR_DOFS * PAIR_DOFS];
            for r in 0..PAIR_DOFS {
                let Some(gr) = self.dofs.eq(3 * nodes[r / 3] + r % 3) else {
                    continue;
                };
                for c in 0..PAIR_DOFS {
                    let Some(gc) = self.dofs.eq(3 * nodes[c / 3] + c % 3) else {
                        continue;
                    };
                    if gr >= gc {
                        let pos = self
                            .pattern
                            .position(gr, gc)
                            .ok_or(ContactError::MissingCoupling(nodes[r / 3], nodes[c / 3]))?;
                        map[r * PAIR_DOFS + c] = pos as u32;
                    }
                }
            }
            maps.push(map);
        }
        self.pairs = pairs;
        self.pair_settings = settings;
        self.pair_shifts = (0..self.pairs.len()).map(|_| zero_shifts()).collect();
        self.pair_maps = maps;
        Ok(())
    }

    /// Adds a rigid plane that the given faces may touch; returns its index.
    ///
    /// # Errors
    /// [`ContactError::OutOfRange`] if the model already has [`MAX_PLANES`] planes.
    pub fn add_plane_contact(
        &mut self,
        plane: RigidPlane,
        faces: &[Face],
    ) -> Result<usize, ContactError> {
        if self.planes.len() >= MAX_PLANES {
            return Err(ContactError::OutOfRange {
                field: "planes",
                value: (self.planes.len() + 1) as f64,
                expected: format!("at most {MAX_PLANES} rigid planes"),
            });
        }
        let index = self.planes.len();
        self.planes.push(plane);
        for f in faces {
            self.contact_faces[f.element].push((index, face_local_nodes(f.axis, f.positive)));
            self.plane_shifts[f.element].push(zero_shifts());
        }
        Ok(index)
    }

    /// Sets the gravity load from a body force per unit reference volume (ρ·g vector).
    pub fn set_body_force(&mut self, b: [f64; 3]) {
        self.f_gravity.iter_mut().for_each(|v| *v = 0.0);
        for (conn, geo) in self.mesh.elements.iter().zip(&self.geometry) {
            for (a, &n) in conn.iter().enumerate() {
                for i in 0..3 {
                    self.f_gravity[3 * n + i] += geo.node_volume[a] * b[i];
                }
            }
        }
    }

    /// Adds a dead traction `t` (force per reference area) on a face.
    pub fn add_dead_traction(&mut self, face: &Face, t: [f64; 3]) {
        let x: [[f64; 3]; 9] = face.nodes.map(|n| self.mesh.nodes[n]);
        let mut r = [0.0; 27];
        // |x,s × x,t| at the reference state gives dA: reuse the pressure integrator per direction
        let mut area = [0.0; 9];
        for (jt, &tt) in element::GAUSS3.0.iter().enumerate() {
            for (js, &s) in element::GAUSS3.0.iter().enumerate() {
                let w = element::GAUSS3.1[js] * element::GAUSS3.1[jt];
                let (ls, ds) = element::lagrange2(s);
                let (lt, dt) = element::lagrange2(tt);
                let mut xs = [0.0; 3];
                let mut xt = [0.0; 3];
                for j in 0..3 {
                    for i in 0..3 {
                        for c in 0..3 {
                            xs[c] += ds[i] * lt[j] * x[i + 3 * j][c];
                            xt[c] += ls[i] * dt[j] * x[i + 3 * j][c];
                        }
                    }
                }
                let n = [
                    xs[1] * xt[2] - xs[2] * xt[1],
                    xs[2] * xt[0] - xs[0] * xt[2],
                    xs[0] * xt[1] - xs[1] * xt[0],
                ];
                let da = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                for j in 0..3 {
                    for i in 0..3 {
                        area[i + 3 * j] += w * ls[i] * lt[j] * da;
                    }
                }
            }
        }
        for a in 0..9 {
            for c in 0..3 {
                r[3 * a + c] = area[a] * t[c];
            }
        }
        for (a, &n) in face.nodes.iter().enumerate() {
            for c in 0..3 {
                self.f_traction[3 * n + c] += r[3 * a + c];
            }
        }
    }

    /// Full displacement vector from the free unknowns and the prescribed values.
    pub fn expand(&self, free: &[f64], level: &LoadLevel, out: &mut [f64]) {
        for (d, o) in out.iter_mut().enumerate() {
            if let Some(e) = self.dofs.eq(d) {
                *o = free[e];
            }
        }
        for &(d, v) in &self.dofs.constrained {
            out[d] = level.prescribed * v;
        }
    }

    /// Assembles the residual over all dofs (`r_full`, reactions at constrained dofs) and,
    /// if `k_values` is given, the lower-triangular tangent on the free equations.
    ///
    /// # Errors
    /// [`ElementError::Inverted`] of the lowest-numbered inverted element.
    pub fn assemble(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, false, None)
    }

    /// As [`Self::assemble`], with the initial-stress term of each element's tangent evaluated
    /// with the given pressure coefficients (the mixed Newton iteration's pressures, see
    /// [`element::linearised_pressure`]) instead of the consistent ones. The residual is
    /// unchanged.
    ///
    /// # Errors
    /// As [`Self::assemble`].
    pub fn assemble_mixed(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
        tangent_pressure: Option<&[[f64; 4]]>,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, false, tangent_pressure)
    }

    /// One Uzawa update of the augmented-Lagrangian gap shifts at a converged displacement
    /// `u` (all dofs): every contact point in contact gets its shift moved by its gap, every
    /// open point the shift −δ ([`contact::update_shift`]). The shifts are changed only if some
    /// point's multiplier changes by more than `tol` (mm, divided by ε), so that a converged
    /// state stays in equilibrium with the shifts it was solved with.
    pub fn update_contact_shifts(&self, u: &[f64], tol: f64) -> ShiftUpdate {
        let mut out = ShiftUpdate::default();
        let mut new = Vec::with_capacity(self.n_contact_points());
        self.visit_contact_points(u, |e, d, g, c| {
            let (c_new, change) = contact::update_shift(e, d, g, c);
            out.max_change = out.max_change.max(change);
            if g.is_finite() && contact::barrier(e, d, g - c).1 < 0.0 {
                out.active_points += 1;
            }
            new.push(c_new);
        });
        if out.max_change > tol {
            self.set_contact_shifts(&new);
            out.applied = true;
        }
        out
    }

    fn n_contact_points(&self) -> usize {
        9 * (self.plane_shifts.iter().map(Vec::len).sum::<usize>() + self.pair_shifts.len())
    }

    /// Smallest shifted gap `g − c` over every contact point (mm) at the displacement `u`
    /// (all dofs), and the largest smoothing δ; `(∞, 0)` without contact.
    pub fn min_shifted_gap(&self, u: &[f64]) -> (f64, f64) {
        let (mut gmin, mut dmax) = (f64::INFINITY, 0.0f64);
        self.visit_contact_points(u, |_, d, g, c| {
            if (g - c) < gmin {
                gmin = g - c;
            }
            dmax = dmax.max(d);
        });
        (gmin, dmax)
    }

    /// Calls `f(ε, δ, g, c)` for every contact quadrature point (plane faces by element, then
    /// pairs: the order of [`Self::contact_shifts`]).
    fn visit_contact_points(&self, u: &[f64], mut f: impl FnMut(f64, f64, f64, f64)) {
        let pos = |n: usize| {
            let x = self.mesh.nodes[n];
            [x[0] + u[3 * n], x[1] + u[3 * n + 1], x[2] + u[3 * n + 2]]
        };
        for (e, faces) in self.contact_faces.iter().enumerate() {
            let conn = &self.mesh.elements[e];
            for ((pi, local), shift) in faces.iter().zip(&self.plane_shifts[e]) {
                let plane = &self.planes[*pi];
                let x0: [[f64; 3]; 9] = local.map(|l| self.mesh.nodes[conn[l]]);
                let x: [[f64; 3]; 9] = local.map(|l| pos(conn[l]));
                let gaps = contact::plane_face_gaps(plane, &x0, &x);
                for (g, c) in gaps.into_iter().zip(load_shifts(shift)) {
                    f(plane.stiffness, plane.smoothing, g, c);
                }
            }
        }
        let set = self.pair_settings;
        for (p, shift) in self.pairs.iter().zip(&self.pair_shifts) {
            let x0b = p.back.map(|n| self.mesh.nodes[n]);
            let gaps = contact::pair_face_gaps(
                &set,
                p.orientation,
                &x0b,
                &p.back.map(pos),
                &p.front.map(pos),
            );
            for (g, c) in gaps.into_iter().zip(load_shifts(shift)) {
                f(set.stiffness, set.smoothing, g, c);
            }
        }
    }

    /// All contact gap shifts (plane faces by element, then pairs; 9 per face).
    pub fn contact_shifts(&self) -> Vec<f64> {
        self.plane_shifts
            .iter()
            .flatten()
            .chain(&self.pair_shifts)
            .flat_map(load_shifts)
            .collect()
    }

    /// Sets the contact gap shifts (in the order of [`Self::contact_shifts`]).
    pub fn set_contact_shifts(&self, values: &[f64]) {
        let cells = self.plane_shifts.iter().flatten().chain(&self.pair_shifts);
        for (a, v) in cells.flatten().zip(values) {
            a.store(v.to_bits(), Ordering::Relaxed);
        }
    }

    /// Sets every contact gap shift to zero (the plain penalty).
    pub fn reset_contact_shifts(&self) {
        for a in self
            .plane_shifts
            .iter()
            .flatten()
            .chain(&self.pair_shifts)
            .flatten()
        {
            a.store(0.0f64.to_bits(), Ordering::Relaxed);
        }
    }

    /// The gap shift of a face pair's centre quadrature point (for output).
    pub fn pair_centre_shift(&self, pair: usize) -> f64 {
        self.pair_shifts
            .get(pair)
            .map_or(0.0, |s| f64::from_bits(s[4].load(Ordering::Relaxed)))
    }

    /// Per element, the projected pressure linearised about `u` and evaluated at `u + du`
    /// ([`element::linearised_pressure`]); `u`, `du` are full displacement vectors.
    ///
    /// # Errors
    /// [`ElementError::Inverted`] if an element is inverted at `u`.
    pub fn linearised_pressures(
        &self,
        u: &[f64],
        du: &[f64],
        out: &mut [[f64; 4]],
    ) -> Result<(), ElementError> {
        out.par_iter_mut().enumerate().try_for_each(|(e, o)| {
            let conn = &self.mesh.elements[e];
            let ue = conn.map(|n| [u[3 * n], u[3 * n + 1], u[3 * n + 2]]);
            let de = conn.map(|n| [du[3 * n], du[3 * n + 1], du[3 * n + 2]]);
            *o = element::linearised_pressure(e, &self.geometry[e], &ue, &de, &self.material)?;
            Ok(())
        })
    }

    /// As [`Self::assemble`], and also evaluates the total potential
    /// `Π = Σ_e Π_e + p Σ_faces (1/3)∫(x − o)·n da − f_dead · u` (in [`AssemblyInfo::energy`]),
    /// whose gradient is the residual. `o` is [`Self::pressure_origin`]: the potential is exact
    /// when the pressurised surfaces are closed, or closed by planes through `o` on which the
    /// nodes stay (symmetry planes, clamped faces).
    ///
    /// # Errors
    /// As [`Self::assemble`].
    pub fn assemble_with_energy(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, true, None)
    }

    fn assemble_impl(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        mut k_values: Option<&mut [f64]>,
        with_energy: bool,
        tangent_pressure: Option<&[[f64; 4]]>,
    ) -> Result<AssemblyInfo, ElementError> {
        r_full.iter_mut().for_each(|v| *v = 0.0);
        if let Some(k) = k_values.as_deref_mut() {
            k.iter_mut().for_each(|v| *v = 0.0);
        }
        let with_k = k_values.is_some();
        let k_ptr = SharedMut(k_values.map_or(std::ptr::null_mut(), |k| k.as_mut_ptr()));
        let r_ptr = SharedMut(r_full.as_mut_ptr());
        let mut p_full = vec![0.0; r_full.len()];
        let p_ptr = SharedMut(p_full.as_mut_ptr());
        let mut energy = 0.0;
        let mut plane_forces = [0.0; MAX_PLANES];
        let mut plane_min_gaps = [f64::INFINITY; MAX_PLANES];
        for color in &self.mesh.colors {
            let results: Vec<Result<ElementOutput, ElementError>> = color
                .par_iter()
                .map_init(
                    || {
                        let mut w = ElementWork::default();
                        w.with_energy = with_energy;
                        w
                    },
                    |work, &e| {
                        work.tangent_pressure = tangent_pressure.map(|t| t[e]);
                        let conn = &self.mesh.elements[e];
                        let ue: [[f64; 3]; 27] =
                            conn.map(|n| [u[3 * n], u[3 * n + 1], u[3 * n + 2]]);
                        let mut en = element::residual_tangent(
                            e,
                            &self.geometry[e],
                            &ue,
                            &self.material,
                            with_k,
                            work,
                        )?;
                        let mut fp = [0.0; DOFS];
                        for pf in &self.pressure_faces[e] {
                            let xf: [[f64; 3]; 9] = pf.local.map(|l| {
                                let x0 = self.mesh.nodes[conn[l]];
                                [x0[0] + ue[l][0], x0[1] + ue[l][1], x0[2] + ue[l][2]]
                            });
                            let mut rf = [0.0; 27];
                            let mut kf = [0.0; 729];
                            let p = level.pressure * pf.scale;
                            loads::pressure_face(p, &xf, &mut rf, with_k.then_some(&mut kf));
                            if with_energy {
                                let o = self.pressure_origin;
                                let rel = xf.map(|x| [x[0] - o[0], x[1] - o[1], x[2] - o[2]]);
                                en += p * loads::face_volume(&rel);
                            }
                            for (a, &la) in pf.local.iter().enumerate() {
                                for i in 0..3 {
                                    work.r[3 * la + i] += rf[3 * a + i];
                                    fp[3 * la + i] += rf[3 * a + i];
                                    if with_k {
                                        for (b, &lb) in pf.local.iter().enumerate() {
                                            for c in 0..3 {
                                                work.k[(3 * la + i) * DOFS + 3 * lb + c] +=
                                                    kf[(3 * a + i) * 27 + 3 * b + c];
                                            }
                                        }
                                    }
                                }
                            }
                        }
                        let mut forces = [0.0; MAX_PLANES];
                        let mut gaps = [f64::INFINITY; MAX_PLANES];
                        for ((pi, local), shift) in
                            self.contact_faces[e].iter().zip(&self.plane_shifts[e])
                        {
                            let x0: [[f64; 3]; 9] = local.map(|l| self.mesh.nodes[conn[l]]);
                            let xf: [[f64; 3]; 9] = std::array::from_fn(|a| {
                                let l = local[a];
                                [
                                    x0[a][0] + ue[l][0],
                                    x0[a][1] + ue[l][1],
                                    x0[a][2] + ue[l][2],
                                ]
                            });
                            let mut rf = [0.0; 27];
                            let mut kf = [0.0; 729];
                            let (ce, cf, cg) = contact::plane_face(
                                &self.planes[*pi],
                                &x0,
                                &xf,
                                &load_shifts(shift),
                                &mut rf,
                                with_k.then_some(&mut kf),
                            );
                            if with_energy {
                                en += ce;
                            }
                            forces[*pi] += cf;
                            gaps[*pi] = gaps[*pi].min(cg);
                            for (a, &la) in local.iter().enumerate() {
                                for i in 0..3 {
                                    work.r[3 * la + i] += rf[3 * a + i];
                                    if with_k {
                                        for (b, &lb) in local.iter().enumerate() {
                                            for c in 0..3 {
                                                work.k[(3 * la + i) * DOFS + 3 * lb + c] +=
                                                    kf[(3 * a + i) * 27 + 3 * b + c];
                                            }
                                        }
                                    }
                                }
                            }
                        }
                        // SAFETY: elements of one colour share no node, so the dofs and matrix
                        // entries written here are written by no other task of this colour.
                        unsafe {
                            for (l, &n) in conn.iter().enumerate() {
                                for i in 0..3 {
                                    r_ptr.add(3 * n + i, work.r[3 * l + i]);
                                    p_ptr.add(3 * n + i, fp[3 * l + i]);
                                }
                            }
                            if with_k {
                                let map = &self.pattern.element_map[e];
                                for (pos, kv) in map.iter().zip(work.k.iter()) {
                                    if *pos != u32::MAX {
                                        k_ptr.add(*pos as usize, *kv);
                                    }
                                }
                            }
                        }
                        Ok((en, forces, gaps))
                    },
                )
                .collect();
            for r in results {
                let (en, forces, gaps) = r?;
                energy += en;
                for i in 0..MAX_PLANES {
                    plane_forces[i] += forces[i];
                    plane_min_gaps[i] = plane_min_gaps[i].min(gaps[i]);
                }
            }
        }
        let mut pair_force = 0.0;
        let mut pair_min_gap = f64::INFINITY;
        if !self.pairs.is_empty() {
            let pos = |n: usize| {
                let x = self.mesh.nodes[n];
                [x[0] + u[3 * n], x[1] + u[3 * n + 1], x[2] + u[3 * n + 2]]
            };
            type PairOut = (f64, f64, f64, Option<Box<([f64; PAIR_DOFS], Vec<f64>)>>);
            let results: Vec<PairOut> = self
                .pairs
                .par_iter()
                .zip(&self.pair_shifts)
                .map(|(p, shift)| {
                    let x0b = p.back.map(|n| self.mesh.nodes[n]);
                    let xb = p.back.map(pos);
                    let xf = p.front.map(pos);
                    let mut r = [0.0; PAIR_DOFS];
                    let mut k = with_k.then(|| Box::new([0.0; PAIR_DOFS * PAIR_DOFS]));
                    let (e, f, g) = contact::pair_face(
                        &self.pair_settings,
                        p.orientation,
                        &x0b,
                        &xb,
                        &xf,
                        &load_shifts(shift),
                        &mut r,
                        k.as_deref_mut(),
                    );
                    let active = r.iter().any(|v| *v != 0.0)
                        || k.as_ref().is_some_and(|k| k.iter().any(|v| *v != 0.0));
                    let local = active.then(|| Box::new((r, k.map_or(Vec::new(), |k| k.to_vec()))));
                    (e, f, g, local)
                })
                .collect();
            for (p, (i, (e, f, g, local))) in self.pairs.iter().zip(results.into_iter().enumerate())
            {
                if with_energy {
                    energy += e;
                }
                pair_force += f;
                pair_min_gap = pair_min_gap.min(g);
                let Some(local) = local else { continue };
                let (r, k) = &*local;
                for (l, &n) in p.back.iter().chain(&p.front).enumerate() {
                    for c in 0..3 {
                        r_full[3 * n + c] += r[3 * l + c];
                    }
                }
                if with_k {
                    // SAFETY: no other thread writes here (serial loop after the colours).
                    for (slot, kv) in self.pair_maps[i].iter().zip(k.iter()) {
                        if *slot != u32::MAX {
                            unsafe { k_ptr.add(*slot as usize, *kv) };
                        }
                    }
                }
            }
        }
        let mut ext2 = 0.0;
        for d in 0..r_full.len() {
            let dead = level.gravity * self.f_gravity[d] + level.traction * self.f_traction[d];
            r_full[d] -= dead;
            if with_energy {
                energy -= dead * u[d];
            }
            if self.dofs.eq(d).is_some() {
                let f = dead - p_full[d];
                ext2 += f * f;
            }
        }
        Ok(AssemblyInfo {
            energy,
            external_norm: ext2.sqrt(),
            plane_forces,
            plane_min_gaps,
            pair_force,
            pair_min_gap,
        })
    }

    /// Free part of a full residual.
    pub fn restrict(&self, r_full: &[f64], out: &mut [f64]) {
        for (d, v) in r_full.iter().enumerate() {
            if let Some(e) = self.dofs.eq(d) {
                out[e] = *v;
            }
        }
    }
}
