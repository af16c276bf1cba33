//! What the nonlinear solver needs from a model: [`NonlinearProblem`].
//!
//! A problem has free unknowns (the solver's) and a full vector (all degrees of freedom,
//! prescribed ones included, set from the load level), a residual and a tangent on the free
//! unknowns, a load parameter ([`LoadLevel`]) along which the solver continues, and the hooks
//! that the augmented-Lagrangian contact and the mixed Newton iteration use. The actuator's
//! [`FeModel`] implements it; a term added to the model (a support spring, a plate compliance,
//! an anisotropic material) changes its residual and tangent, not the solver.

use crate::fe::assembly::{FeModel, LoadLevel, Pattern, ShiftUpdate};
use crate::fe::element::ElementError;
use crate::fe::ordering::nested_dissection;

/// A discretised static problem `r(u; λ) = 0` that the solver drives along a load path.
///
/// The residual is the gradient of a total potential wherever the problem is conservative
/// (every load of the actuator model is), which the line search relies on.
pub trait NonlinearProblem: Sync {
    /// Number of free unknowns (the size of the linear systems).
    fn n_free(&self) -> usize;

    /// Length of the full vector of degrees of freedom.
    fn n_full(&self) -> usize;

    /// Lower-triangular CSC pattern of the tangent on the free unknowns.
    fn pattern(&self) -> &Pattern;

    /// A fill-reducing ordering of the free unknowns (new → old), if the problem has a better
    /// one than minimum degree to offer; the linear solver keeps whichever gives the smaller
    /// factor.
    fn nested_dissection(&self) -> Option<Vec<usize>> {
        None
    }

    /// A characteristic internal force (N): the floor of the convergence test's force scale.
    fn force_floor(&self) -> f64;

    /// The full vector from the free unknowns and the prescribed values at `level`.
    fn expand(&self, free: &[f64], level: &LoadLevel, full: &mut [f64]);

    /// The free part of a full vector.
    fn restrict(&self, full: &[f64], free: &mut [f64]);

    /// `α · du` on the free unknowns as a full vector, zero at the prescribed ones (an
    /// increment of the state at a fixed load).
    fn expand_increment(&self, du: &[f64], alpha: f64, full: &mut [f64]);

    /// Residual on all degrees of freedom (reactions at the prescribed ones) at the full
    /// displacement `u` and load `level`, and the tangent's lower triangle on the free
    /// unknowns if `tangent` is given; `mixed` replaces the consistent element fields of the
    /// tangent's initial-stress term by the mixed iteration's ([`Self::mixed_fields`]).
    /// Returns the Euclidean norm of the external forces on the free unknowns.
    ///
    /// # Errors
    /// [`ElementError`] if an element is inverted or degenerate at `u`.
    fn residual(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        tangent: Option<&mut [f64]>,
        mixed: Option<&[[f64; 4]]>,
    ) -> Result<f64, ElementError>;

    /// Euclidean norm of the reactions (the residual at the prescribed degrees of freedom).
    fn reaction_norm(&self, r_full: &[f64]) -> f64;

    /// Number of per-element fields the mixed Newton iteration carries (0: none).
    fn n_mixed_fields(&self) -> usize;

    /// The mixed iteration's element fields at `u + du`, linearised about `u` (full vectors).
    ///
    /// # Errors
    /// [`ElementError`] if an element is inverted at `u`.
    fn mixed_fields(&self, u: &[f64], du: &[f64], out: &mut [[f64; 4]])
        -> Result<(), ElementError>;

    /// Sets every contact gap shift to zero (the plain penalty).
    fn reset_contact_shifts(&self);

    /// All contact gap shifts.
    fn contact_shifts(&self) -> Vec<f64>;

    /// Restores contact gap shifts saved by [`Self::contact_shifts`].
    fn set_contact_shifts(&self, values: &[f64]);

    /// One Uzawa update of the contact gap shifts at the converged full displacement `u`,
    /// applied only if some multiplier changes by more than `tol` (mm).
    fn update_contact_shifts(&self, u: &[f64], tol: f64) -> ShiftUpdate;

    /// Smallest shifted contact gap at `u` (mm) and the largest smoothing width; `(∞, 0)`
    /// without contact.
    fn min_shifted_gap(&self, u: &[f64]) -> (f64, f64);

    /// Where free unknown `eq` sits, for traces.
    fn describe_unknown(&self, eq: usize) -> String {
        format!("unknown {eq}")
    }

    /// The total potential Π at the full displacement `u` and `level`, with the residual (its
    /// gradient) and the tangent as in [`Self::residual`]; `project` makes the tangent the sum
    /// of element tangents projected onto the positive semi-definite cone. Returns
    /// `(Π, norm of the external forces)`, or `None` for a problem without a potential
    /// (the default), which the minimisation solver refuses.
    ///
    /// # Errors
    /// [`ElementError`] if an element is inverted or degenerate at `u`.
    fn potential(
        &self,
        _u: &[f64],
        _level: &LoadLevel,
        _r_full: &mut [f64],
        _tangent: Option<&mut [f64]>,
        _mixed: Option<&[[f64; 4]]>,
        _project: bool,
    ) -> Result<Option<(f64, f64)>, ElementError> {
        Ok(None)
    }

    /// The gap (mm) of every contact point at the full displacement `u`, in a fixed order,
    /// into `out` (cleared first; empty without contact).
    fn contact_gaps(&self, _u: &[f64], out: &mut Vec<f64>) {
        out.clear();
    }
}

impl NonlinearProblem for FeModel {
    fn n_free(&self) -> usize {
        self.dofs.n_free
    }

    fn n_full(&self) -> usize {
        3 * self.mesh.n_nodes()
    }

    fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    fn nested_dissection(&self) -> Option<Vec<usize>> {
        nested_dissection(&self.pattern, &self.dofs)
    }

    fn force_floor(&self) -> f64 {
        let v: f64 = self.geometry.iter().map(|g| g.volume()).sum();
        1e-3 * self.material.mu0() * v.powf(2.0 / 3.0)
    }

    fn expand(&self, free: &[f64], level: &LoadLevel, full: &mut [f64]) {
        FeModel::expand(self, free, level, full);
    }

    fn restrict(&self, full: &[f64], free: &mut [f64]) {
        FeModel::restrict(self, full, free);
    }

    fn expand_increment(&self, du: &[f64], alpha: f64, full: &mut [f64]) {
        full.iter_mut().for_each(|v| *v = 0.0);
        for (d, v) in full.iter_mut().enumerate() {
            if let Some(e) = self.dofs.eq(d) {
                *v = alpha * du[e];
            }
        }
    }

    fn residual(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        tangent: Option<&mut [f64]>,
        mixed: Option<&[[f64; 4]]>,
    ) -> Result<f64, ElementError> {
        self.assemble_mixed(u, level, r_full, tangent, mixed)
            .map(|info| info.external_norm)
    }

    fn reaction_norm(&self, r_full: &[f64]) -> f64 {
        let mut s = 0.0;
        for &(d, _) in &self.dofs.constrained {
            s += r_full[d] * r_full[d];
        }
        s.sqrt()
    }

    fn n_mixed_fields(&self) -> usize {
        self.mesh.n_elements()
    }

    fn mixed_fields(
        &self,
        u: &[f64],
        du: &[f64],
        out: &mut [[f64; 4]],
    ) -> Result<(), ElementError> {
        self.linearised_pressures(u, du, out)
    }

    fn reset_contact_shifts(&self) {
        FeModel::reset_contact_shifts(self);
    }

    fn contact_shifts(&self) -> Vec<f64> {
        FeModel::contact_shifts(self)
    }

    fn set_contact_shifts(&self, values: &[f64]) {
        FeModel::set_contact_shifts(self, values);
    }

    fn update_contact_shifts(&self, u: &[f64], tol: f64) -> ShiftUpdate {
        FeModel::update_contact_shifts(self, u, tol)
    }

    fn min_shifted_gap(&self, u: &[f64]) -> (f64, f64) {
        FeModel::min_shifted_gap(self, u)
    }

    fn potential(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        tangent: Option<&mut [f64]>,
        mixed: Option<&[[f64; 4]]>,
        project: bool,
    ) -> Result<Option<(f64, f64)>, ElementError> {
        self.assemble_potential(u, level, r_full, tangent, mixed, project)
            .map(|info| Some((info.energy, info.external_norm)))
    }

    fn contact_gaps(&self, u: &[f64], out: &mut Vec<f64>) {
        FeModel::contact_gaps(self, u, out);
    }

    fn describe_unknown(&self, eq: usize) -> String {
        (0..3 * self.mesh.n_nodes())
            .find(|&d| self.dofs.eq(d) == Some(eq))
            .map_or_else(
                || format!("unknown {eq}"),
                |d| format!("{:?} component {}", self.mesh.nodes[d / 3], d % 3),
            )
    }
}
