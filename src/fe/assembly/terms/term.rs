//! What an element term is ([`ElementTerm`]), what it sees ([`ElementContext`]) and what it
//! adds to ([`LocalSystem`]).

use crate::fe::assembly::load::{LoadFactor, LoadLevel};
use crate::fe::assembly::scatter::LocalVectors;
use crate::fe::element::{ElementError, ElementWork, DOFS};

/// Largest number of rigid planes in one model.
pub const MAX_PLANES: usize = 4;

/// The state of one element that a term sees.
pub struct ElementContext<'a> {
    /// Element id.
    pub element: usize,
    /// Its nodes.
    pub conn: &'a [usize; 27],
    /// Reference positions of all nodes of the mesh.
    pub nodes: &'a [[f64; 3]],
    /// Displacements of its nodes.
    pub ue: [[f64; 3]; 27],
    /// The load level.
    pub level: &'a LoadLevel,
    /// Whether the tangent is wanted.
    pub with_tangent: bool,
    /// Whether the potential energy is wanted.
    pub with_energy: bool,
    /// The mixed Newton iteration's element pressures for the tangent (see
    /// [`crate::fe::element::linearised_pressure`]).
    pub mixed: Option<[f64; 4]>,
}

impl ElementContext<'_> {
    /// Current position of local node `l`.
    pub fn position(&self, l: usize) -> [f64; 3] {
        let x0 = self.nodes[self.conn[l]];
        [
            x0[0] + self.ue[l][0],
            x0[1] + self.ue[l][1],
            x0[2] + self.ue[l][2],
        ]
    }
}

/// One element's local system: what every term adds to.
pub struct LocalSystem {
    /// Residual and row-major 81 × 81 tangent (with the volume term's scratch).
    pub work: ElementWork,
    /// External force from the follower pressure, per local dof.
    pub external: [f64; DOFS],
    /// Potential energy (when asked for).
    pub energy: f64,
    /// Normal force of each rigid plane on this element (N).
    pub plane_forces: [f64; MAX_PLANES],
    /// Smallest gap to each rigid plane at this element's contact points (mm).
    pub plane_gaps: [f64; MAX_PLANES],
}

impl LocalSystem {
    /// An empty local system.
    pub fn new(with_energy: bool) -> Self {
        let mut work = ElementWork::default();
        work.with_energy = with_energy;
        Self {
            work,
            external: [0.0; DOFS],
            energy: 0.0,
            plane_forces: [0.0; MAX_PLANES],
            plane_gaps: [f64::INFINITY; MAX_PLANES],
        }
    }

    /// Adds a face term's local residual `rf` (9 nodes × 3) and tangent `kf` (27 × 27) at the
    /// element-local nodes `local`.
    pub fn add_face(&mut self, local: &[usize; 9], rf: &[f64; 27], kf: Option<&[f64; 729]>) {
        for (a, &la) in local.iter().enumerate() {
            for i in 0..3 {
                self.work.r[3 * la + i] += rf[3 * a + i];
                if let Some(kf) = kf {
                    for (b, &lb) in local.iter().enumerate() {
                        for c in 0..3 {
                            self.work.k[(3 * la + i) * DOFS + 3 * lb + c] +=
                                kf[(3 * a + i) * 27 + 3 * b + c];
                        }
                    }
                }
            }
        }
    }
}

impl LocalVectors for LocalSystem {
    fn residual(&self) -> &[f64] {
        &self.work.r
    }
    fn external(&self) -> &[f64; DOFS] {
        &self.external
    }
    fn tangent(&self) -> &[f64] {
        &self.work.k
    }
}

/// A physical term evaluated element by element, reading its data from the model `M` (the
/// actuator's [`FeModel`](crate::fe::assembly::FeModel)) or carrying its own.
pub trait ElementTerm<M: ?Sized>: Send + Sync {
    /// Short name (for traces and documentation).
    fn name(&self) -> &'static str;

    /// The load factor the term scales its load by (`cx.level[factor]`), if it is a load:
    /// what [`FeModel::load_factors`](crate::fe::assembly::FeModel::load_factors) lists.
    fn load_factor(&self) -> Option<LoadFactor> {
        None
    }

    /// Adds the term's contribution of element `cx.element` to `local`. The first term of
    /// [`ELEMENT_TERMS`](super::ELEMENT_TERMS) (the volume) sets the local residual and tangent; every later one
    /// adds to them.
    ///
    /// # Errors
    /// [`ElementError`] if the element is inverted or degenerate.
    fn add(
        &self,
        model: &M,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError>;
}
