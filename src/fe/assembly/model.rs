//! The discretised model: mesh, material, constraints, loads and contact, with the data each
//! physical term reads ([`FeModel`]), and the augmented-Lagrangian contact shifts it carries
//! between solves.

// Index loops mirror the tensor index notation (a, b: nodes; i, j, k, l: components).
#![allow(clippy::needless_range_loop)]

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::dofs::{DofMap, Pattern};
use super::load::LoadLevel;
use super::terms::barrier::IpcBarrier;
use super::terms::term::{ElementTerm, MAX_PLANES};
use crate::fe::assembly::dofs::Constraint;
use crate::fe::contact::{self, ContactError, FacePair, PairSettings, RigidPlane, PAIR_DOFS};
use crate::fe::element::{self, ElementError, ElementGeometry};
use crate::fe::material::Material;
use crate::fe::mesh::{face_local_nodes, Face, Mesh};

/// A pressurised face attached to its element.
#[derive(Clone, Copy, Debug)]
pub struct PressureFace {
    /// Element-local node indices of the face (outward order).
    pub local: [usize; 9],
    /// Pressure multiplier of this face (1 for the nominal pressure).
    pub scale: f64,
}

/// The discretised model: mesh, material, constraints and loads, ready to assemble.
pub struct FeModel {
    /// The mesh.
    pub mesh: Mesh,
    /// Reference data per element.
    pub geometry: Vec<ElementGeometry>,
    /// The material.
    pub material: Material,
    /// Per element: the factor on its strain energy (a printed part stiffer or softer than
    /// the material, [`crate::fe::geometry::PartStiffness`]); 1 by default.
    pub stiffness: Vec<f64>,
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
    pub(super) pair_maps: Vec<Vec<u32>>,
    /// Augmented-Lagrangian gap shifts ([`contact::update_shift`]) of the plane-contact faces,
    /// per element in the order of `contact_faces`, one per quadrature point (f64 bits; set
    /// between Newton solves, read by the parallel assembly).
    pub(super) plane_shifts: Vec<Vec<[AtomicU64; 9]>>,
    /// Gap shifts of the face pairs.
    pub(super) pair_shifts: Vec<[AtomicU64; 9]>,
    /// Element terms added to this model after [`ELEMENT_TERMS`](super::ELEMENT_TERMS).
    pub(super) extra_terms: Vec<Box<dyn ElementTerm<FeModel>>>,
    /// The contact law of planes and face pairs: the log barrier if set (the minimisation
    /// solver's, no gap shifts), otherwise each obstacle's penalty.
    pub barrier: Option<IpcBarrier>,
}

pub(super) fn load_shifts(a: &[AtomicU64; 9]) -> [f64; 9] {
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
            stiffness: vec![1.0; geometry.len()],
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
            extra_terms: Vec::new(),
            barrier: None,
            mesh,
        })
    }

    /// Sets each element's strain-energy factor from its centroid (the mean of its nodes):
    /// `factor(centroid)`.
    pub fn set_stiffness(&mut self, factor: impl Fn([f64; 3]) -> f64) {
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            let c = conn.iter().fold([0.0; 3], |mut c, &n| {
                let x = self.mesh.nodes[n];
                (0..3).for_each(|i| c[i] += x[i] / conn.len() as f64);
                c
            });
            self.stiffness[e] = factor(c);
        }
    }

    /// Sets the face pairs of deformable–deformable contact. Their node couplings
    /// ([`super::dofs::pair_couplings`]) must have been passed to [`Self::new`].
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

    /// Adds an element term (evaluated after [`ELEMENT_TERMS`](super::ELEMENT_TERMS), in the order added).
    pub fn add_element_term(&mut self, term: Box<dyn ElementTerm<FeModel>>) {
        self.extra_terms.push(term);
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
            out[d] = level.prescribed() * v;
        }
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

    /// The gap of every contact quadrature point at the displacement `u` (all dofs), in the
    /// order of [`Self::contact_shifts`], into `out` (cleared first); a failed closest-point
    /// projection gives `+∞`.
    pub fn contact_gaps(&self, u: &[f64], out: &mut Vec<f64>) {
        out.clear();
        self.visit_contact_points(u, |_, _, g, _| out.push(g));
    }

    /// Every contact law `factor` times stiffer and sharper: stiffness `ε → factor·ε`,
    /// smoothing `δ → δ/factor`. With the gap shifts of [`Self::stiffened_shifts`] the
    /// contact forces at a state are unchanged and their slopes `factor` times larger: the
    /// linearisation about an augmented-Lagrangian solution then holds every touching point
    /// at its gap (the limit the multiplier updates converge to) instead of letting it sit on
    /// a penalty spring. A log-barrier model ([`FeModel::barrier`]) is left unchanged.
    pub fn scale_contact(&mut self, factor: f64) {
        if self.barrier.is_some() {
            return;
        }
        for p in &mut self.planes {
            p.stiffness *= factor;
            p.smoothing /= factor;
        }
        self.pair_settings.stiffness *= factor;
        self.pair_settings.smoothing /= factor;
    }

    /// The gap shifts that keep the contact forces of the state `(u, shifts)` (shifts of the
    /// unscaled law, in the order of [`Self::contact_shifts`]) once the law is scaled by
    /// `factor` ([`Self::scale_contact`]): `c → g − (g − c)/factor`, `g` each point's gap at
    /// `u` (the barrier `ψ'_{fε, δ/f}((g − c)/f) = ψ'_{ε, δ}(g − c)` exactly).
    pub fn stiffened_shifts(&self, u: &[f64], shifts: &[f64], factor: f64) -> Vec<f64> {
        let mut gaps = Vec::new();
        self.contact_gaps(u, &mut gaps);
        shifts
            .iter()
            .zip(&gaps)
            .map(|(&c, &g)| {
                if g.is_finite() {
                    g - (g - c) / factor
                } else {
                    c
                }
            })
            .collect()
    }

    /// Evaluates every contact face of rigid plane `plane` at the displacement `u` (all dofs)
    /// with the contact law and gap shifts the assembly uses, the face's tangent into `kf`
    /// when given (zeroed first), and calls `f(global nodes of the face, its normal force,
    /// its tangent)`.
    fn visit_plane_faces(
        &self,
        u: &[f64],
        plane: usize,
        mut kf: Option<&mut [f64; 729]>,
        mut f: impl FnMut([usize; 9], f64, Option<&[f64; 729]>),
    ) {
        let mut rf = [0.0; 27];
        for (e, faces) in self.contact_faces.iter().enumerate() {
            let conn = &self.mesh.elements[e];
            for ((pi, local), shift) in faces.iter().zip(&self.plane_shifts[e]) {
                if *pi != plane {
                    continue;
                }
                let p = &self.planes[*pi];
                let nodes = local.map(|l| conn[l]);
                let x0: [[f64; 3]; 9] = nodes.map(|n| self.mesh.nodes[n]);
                let x: [[f64; 3]; 9] = std::array::from_fn(|a| {
                    let n = nodes[a];
                    [
                        x0[a][0] + u[3 * n],
                        x0[a][1] + u[3 * n + 1],
                        x0[a][2] + u[3 * n + 2],
                    ]
                });
                if let Some(k) = kf.as_deref_mut() {
                    k.iter_mut().for_each(|v| *v = 0.0);
                }
                let (_, force, _) = match &self.barrier {
                    Some(b) => contact::plane_face_with(
                        |g| b.eval(g),
                        p,
                        &x0,
                        &x,
                        &[0.0; 9],
                        &mut rf,
                        kf.as_deref_mut(),
                    ),
                    None => contact::plane_face(
                        p,
                        &x0,
                        &x,
                        &load_shifts(shift),
                        &mut rf,
                        kf.as_deref_mut(),
                    ),
                };
                f(nodes, force, kf.as_deref());
            }
        }
    }

    /// The normal force of rigid plane `plane` on the body at the displacement `u` (all
    /// dofs), with the contact law and gap shifts the assembly uses: the plane's entry of
    /// [`AssemblyInfo::plane_forces`] from its contact faces alone (no other term assembled).
    pub fn plane_force(&self, u: &[f64], plane: usize) -> f64 {
        let mut total = 0.0;
        self.visit_plane_faces(u, plane, None, |_, force, _| total += force);
        total
    }

    /// The derivative of the residual (all dofs, added into `out`) with respect to the height
    /// `y` of rigid plane `plane`'s point, at the displacement `u`, with the contact law and
    /// gap shifts the assembly uses. Exact, from the face tangents: raising the plane by `dy`
    /// changes every gap by `−n_y·dy`, as translating the face by `−dy` along `y` does, so
    /// `∂r/∂y = −K_face·t` with `t` the unit translation along `y` of the face's nodes.
    ///
    /// The sensitivities use it for the plate that follows the sagged tip: a residual
    /// difference across the contact law's C² joints is off by about `h·s²·ψ'''` (`s` the
    /// plate's motion per unit parameter, about 10 mm for `density`), which with the
    /// stiffened law (`ψ''' ∝ factor²`) outgrew the derivative itself.
    pub fn plane_height_derivative(&self, u: &[f64], plane: usize, out: &mut [f64]) {
        let mut kf = [0.0; 729];
        self.visit_plane_faces(u, plane, Some(&mut kf), |nodes, _, k| {
            let k = k.expect("the tangent was asked for");
            for (a, &n) in nodes.iter().enumerate() {
                for c in 0..3 {
                    let row = 3 * a + c;
                    let d: f64 = (0..9).map(|b| k[row * 27 + 3 * b + 1]).sum();
                    out[3 * n + c] -= d;
                }
            }
        });
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

    /// Free part of a full residual.
    pub fn restrict(&self, r_full: &[f64], out: &mut [f64]) {
        for (d, v) in r_full.iter().enumerate() {
            if let Some(e) = self.dofs.eq(d) {
                out[e] = *v;
            }
        }
    }
}
