//! Measurement: what the rig reads off a converged state, in the SPEC's conventions.
//!
//! A marker sits at local coordinates `ξ` of an element; its displacement is interpolated,
//! `d = Σ_a N_a(ξ) u_a`, and reported as `Uz = −d_z` (positive towards the support),
//! `Uy = d_y` (negative downwards). Marker 9 is the tip. With the free length `Lf` the tip
//! sits at `z_tip = Lf − Uz`, `y_tip = Uy`, and the bending angle seen from the support
//! point `(W/2, 0, 0)` is
//!
//! ```text
//!   α = atan2(−y_tip, z_tip).
//! ```
//!
//! Forces are the obstacles' reactions assembled at the converged state, doubled because the
//! model is the half `x ≤ W/2`: the force plate's (the blocked force), the clamp block's and
//! the total normal force between bellows. Gaps are reported twice: the smallest deformed
//! node-to-node gap between facing walls ([`ActuatorModel::min_gap`]) and the smallest gap
//! at a contact quadrature point.

use serde::{Deserialize, Serialize};

use super::model::{key, ActuatorModel};
use crate::fe::element::shape;
use crate::fe::mesh::{Face, GapSide};
use crate::fe::solver::{PathState, StepReport};

/// A marker's displacement in the tables' convention, as every JSON output writes it:
/// `Uz = −Δz` (positive towards the support), `Uy = Δy` (negative downwards), mm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// `Uz = −Δz`, mm.
    pub uz_mm: f64,
    /// `Uy = Δy`, mm.
    pub uy_mm: f64,
}

impl From<[f64; 2]> for Marker {
    fn from(m: [f64; 2]) -> Self {
        Marker {
            uz_mm: m[0],
            uy_mm: m[1],
        }
    }
}

/// Serde form of a marker list: written as [`Marker`] objects, read from objects or pairs.
pub mod marker_list {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    use super::Marker;

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Either {
        Object(Marker),
        Pair([f64; 2]),
    }

    /// Writes `[{"uz_mm", "uy_mm"}, …]`.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer>(m: &[[f64; 2]], s: S) -> Result<S::Ok, S::Error> {
        let v: Vec<Marker> = m.iter().map(|&p| Marker::from(p)).collect();
        v.serialize(s)
    }

    /// Reads objects `{"uz_mm", "uy_mm"}` or pairs `[Uz, Uy]`.
    ///
    /// # Errors
    /// Neither form.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
        let v: Vec<Either> = Vec::deserialize(d)?;
        Ok(v.into_iter()
            .map(|e| match e {
                Either::Object(m) => [m.uz_mm, m.uy_mm],
                Either::Pair(p) => p,
            })
            .collect())
    }
}

/// Results of one pressure step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepResult {
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Tip Uz = −Δz (mm).
    pub tip_uz_mm: f64,
    /// Tip Uy = Δy (mm).
    pub tip_uy_mm: f64,
    /// Bending angle (deg).
    pub angle_deg: f64,
    /// Markers 1..9: `[Uz, Uy]` (mm); written as `[{"uz_mm": …, "uy_mm": …}, …]`
    /// ([`Marker`], the form `predict` writes too); the older `[[Uz, Uy], …]` is still read.
    #[serde(with = "marker_list")]
    pub markers: Vec<[f64; 2]>,
    /// Newton iterations to reach this step.
    pub newton_iterations: usize,
    /// The step was solved directly from a neighbouring case's state
    /// ([`run_warm`](super::run_warm)).
    #[serde(default, skip_serializing_if = "is_false")]
    pub warm_start: bool,
    /// Load substeps.
    pub substeps: usize,
    /// Cut-backs.
    pub cutbacks: usize,
    /// Final normalised residual.
    pub residual: f64,
    /// Whether the step converged.
    pub converged: bool,
    /// Smallest deformed gap between neighbouring bellows (mm; negative = interpenetration).
    pub min_gap_mm: f64,
    /// Gap (or clamp gap) where it occurs.
    pub min_gap_at: String,
    /// Blocked force: the plate's vertical reaction (N, full actuator), in
    /// [`Mode::Force`](super::Mode::Force).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force_n: Option<f64>,
    /// Total normal force between neighbouring bellows (N, full actuator).
    #[serde(default)]
    pub contact_force_n: f64,
    /// Clamp block's reaction on the first bellow (N, full actuator).
    #[serde(default)]
    pub clamp_force_n: f64,
    /// Smallest gap at a contact quadrature point, bellows and clamp (mm; negative =
    /// penetration).
    #[serde(default)]
    pub min_contact_gap_mm: f64,
}

/// Results of a simulation.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Response {
    /// One entry per requested pressure.
    pub steps: Vec<StepResult>,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh elements.
    pub elements: usize,
    /// Free degrees of freedom.
    pub dofs: usize,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Time spent in factorisations (s).
    pub factor_time_s: f64,
    /// Time spent in assembly (s).
    pub assembly_time_s: f64,
    /// Factorisations of the tangent over the whole path.
    #[serde(default)]
    pub factorizations: usize,
}

/// The measured outputs of a converged state; `pressure_bar` is the requested level, reported
/// as given (not recomputed from the load in MPa, which would print `3.0000000000000004`).
pub(super) fn measure(
    model: &ActuatorModel,
    state: &PathState,
    rep: &StepReport,
    lf: f64,
    pressure_bar: f64,
) -> StepResult {
    let u = &state.u_full;
    let markers: Vec<[f64; 2]> = (0..9)
        .map(|k| {
            let d = model.marker_displacement(k, u);
            [-d[2], d[1]]
        })
        .collect();
    let tip = markers[8];
    let z_tip = lf - tip[0];
    let y_tip = tip[1];
    let (min_gap_mm, min_gap_at) = model.min_gap(u);
    // reactions of the obstacles at the converged state (×2: the model is a half)
    let mut r = vec![0.0; u.len()];
    let info = model.fe.assemble(u, &state.level, &mut r, None).ok();
    let plane = |i: Option<usize>| {
        i.zip(info.as_ref())
            .map(|(i, info)| (2.0 * info.plane_forces[i], info.plane_min_gaps[i]))
    };
    let force_n = plane(model.plate).map(|(f, _)| f);
    let (clamp_force_n, clamp_gap) = plane(model.clamp).unwrap_or((0.0, f64::INFINITY));
    let (contact_force_n, pair_gap) = info.as_ref().map_or((0.0, f64::INFINITY), |i| {
        (2.0 * i.pair_force, i.pair_min_gap)
    });
    StepResult {
        pressure_bar,
        tip_uz_mm: tip[0],
        tip_uy_mm: tip[1],
        angle_deg: (-y_tip).atan2(z_tip).to_degrees(),
        markers,
        newton_iterations: rep.newton_iterations,
        warm_start: rep.warm_start,
        substeps: rep.substeps,
        cutbacks: rep.cutbacks,
        residual: rep.residual,
        converged: rep.converged,
        min_gap_mm,
        min_gap_at,
        force_n,
        contact_force_n,
        clamp_force_n,
        min_contact_gap_mm: pair_gap.min(clamp_gap),
    }
}

impl ActuatorModel {
    /// Displacement of marker `k` (0-based) in a full displacement vector.
    pub fn marker_displacement(&self, k: usize, u: &[f64]) -> [f64; 3] {
        let m = &self.mesh.markers[k];
        let (n, _) = shape(m.xi);
        let conn = &self.fe.mesh.elements[m.element];
        let mut d = [0.0; 3];
        for (a, &node) in conn.iter().enumerate() {
            for i in 0..3 {
                d[i] += n[a] * u[3 * node + i];
            }
        }
        d
    }

    /// Smallest deformed gap between facing bellow walls (node to node, signed along the back
    /// wall's current normal) and between the first wall and the clamp plane, with where it
    /// occurs (`gap i-j` or `clamp`; the first of equal gaps).
    pub fn min_gap(&self, u: &[f64]) -> (f64, String) {
        let mut best = (f64::INFINITY, String::new());
        for (side, faces) in &self.mesh.gap_faces {
            let (gap, at) = match side {
                GapSide::Back(i) => {
                    let Some(front) = self.mesh.gap_faces.get(&GapSide::Front(*i)) else {
                        continue;
                    };
                    (
                        self.wall_gap(faces, front, u),
                        format!("gap {}-{}", i + 1, i + 2),
                    )
                }
                GapSide::Clamp => (self.clamp_gap(faces, u), "clamp".into()),
                GapSide::Front(_) => continue,
            };
            if gap < best.0 {
                best = (gap, at);
            }
        }
        best
    }

    /// Deformed position of node `n`.
    fn deformed(&self, u: &[f64], n: usize) -> [f64; 3] {
        let x = self.fe.mesh.nodes[n];
        [x[0] + u[3 * n], x[1] + u[3 * n + 1], x[2] + u[3 * n + 2]]
    }

    /// Smallest gap across one bellow gap: from each node of the back wall to the front-wall
    /// node of the same reference (x, y), its length signed by the side of the back wall's
    /// current normal, oriented into the gap as in the reference (+z), so that the sign
    /// survives any rotation of the bellow.
    fn wall_gap(&self, backs: &[Face], fronts: &[Face], u: &[f64]) -> f64 {
        let reference = |n: usize| self.fe.mesh.nodes[n];
        let pos = |n: usize| self.deformed(u, n);
        let mut lookup = std::collections::HashMap::new();
        for f in fronts {
            for &n in &f.nodes {
                let x = reference(n);
                lookup.insert(key(x[0], x[1]), n);
            }
        }
        let mut smallest = f64::INFINITY;
        for f in backs {
            let normal = |p: &dyn Fn(usize) -> [f64; 3]| {
                let (a, b, c) = (p(f.nodes[0]), p(f.nodes[2]), p(f.nodes[6]));
                let (s, t) = (sub(b, a), sub(c, a));
                [
                    s[1] * t[2] - s[2] * t[1],
                    s[2] * t[0] - s[0] * t[2],
                    s[0] * t[1] - s[1] * t[0],
                ]
            };
            let n_ref = normal(&reference);
            let n_cur = normal(&pos);
            let orient = n_ref[2].signum();
            for &n in &f.nodes {
                let x = reference(n);
                if let Some(&m) = lookup.get(&key(x[0], x[1])) {
                    let d = sub(pos(m), pos(n));
                    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let along = orient * (d[0] * n_cur[0] + d[1] * n_cur[1] + d[2] * n_cur[2]);
                    let gap = if along >= 0.0 { len } else { -len };
                    if gap < smallest {
                        smallest = gap;
                    }
                }
            }
        }
        smallest
    }

    /// Smallest deformed z of the first wall's nodes: its gap to the clamp plane `z = 0`.
    fn clamp_gap(&self, faces: &[Face], u: &[f64]) -> f64 {
        let mut smallest = f64::INFINITY;
        for f in faces {
            for &n in &f.nodes {
                let z = self.deformed(u, n)[2];
                if z < smallest {
                    smallest = z;
                }
            }
        }
        smallest
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn is_false(v: &bool) -> bool {
    !*v
}
