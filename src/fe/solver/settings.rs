//! What the nonlinear solver is asked to do ([`SolverSettings`]), what it reports for each
//! output step ([`StepReport`]) and why it stops ([`SolverError`]).

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::fe::assembly::LoadLevel;
use crate::fe::element::ElementError;
use crate::fe::InvalidSetting;

/// Settings of the nonlinear solver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverSettings {
    /// Relative residual tolerance: ‖r‖ ≤ rtol · max(‖f_ext‖, ‖reactions‖, 1e-3 μ0 V^(2/3)).
    pub rtol: f64,
    /// Maximum Newton iterations per (sub)step.
    pub max_iterations: usize,
    /// Maximum number of consecutive cut-backs in one output step.
    pub max_cutbacks: usize,
    /// Initial load increment as a fraction of an output step.
    pub initial_fraction: f64,
    /// First pressure increment of a step (MPa); later increments adapt. Measured as
    /// [`LoadLevel::bounded_increment`]: the change of the load factors with
    /// [`FactorInfo::bounds_increment`](crate::fe::assembly::FactorInfo::bounds_increment).
    pub initial_pressure_increment: f64,
    /// An increment that converged in at most this many Newton iterations is followed by one
    /// 1.5 times larger.
    pub grow_below_iterations: usize,
    /// Largest pressure increment in one substep (MPa), measured as
    /// [`Self::initial_pressure_increment`].
    pub max_pressure_increment: f64,
    /// Line-search on/off.
    pub line_search: bool,
    /// Start each increment from the pressure-extrapolated path: quadratic through the
    /// last three converged states (linear through two), not used where it would push a
    /// contact point into penetration, and dropped for a plain retry if Newton fails from it
    /// (module docs). On by default; settings written before it was the default (without
    /// the field) read as off, as they were computed.
    #[serde(default)]
    pub predictor: bool,
    /// Mixed (u, θ, π) Newton iteration: the tangent's initial-stress term uses the pressure
    /// carried linearly from the previous iterate rather than the one recomputed from the
    /// displacements (see [`crate::fe::element::linearised_pressure`]). Same residual and
    /// solution; with κ = 1000 μ0 it converges in far fewer iterations.
    #[serde(default = "yes")]
    pub mixed_tangent: bool,
    /// Print every Newton iteration to stderr.
    #[serde(default)]
    pub trace: bool,
    /// Augmented-Lagrangian contact: after each converged output step, up to this many Uzawa
    /// updates of the contact gap shifts ([`crate::fe::contact::update_shift`]), each followed by
    /// a Newton solve at the same load, until no contact point's multiplier changes by more
    /// than ε · [`AUGMENTED_GAP_TOL`]; 0 gives the plain penalty. Default 6 (2–4 are used).
    /// Settings written before this field existed read as 0: the plain penalty they were
    /// computed with.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub augmented_updates: usize,
    /// Modified Newton in the re-solves after an Uzawa update: the iterations reuse the last
    /// factorised tangent (residual-only assembly and one pair of triangular solves) as long
    /// as each one divides the residual by at least 1 / [`REUSE_CONTRACTION`]; then full
    /// Newton takes over. Same tolerance, so the same solution up to it (13 % less wall time
    /// on the standard mesh, `docs/SOLVER_MEASUREMENTS.md`). On by default; written to
    /// settings only when off. Results computed before it was the default (without the
    /// field, and computed without it) read as computed with it and keep their cache keys:
    /// the two agree to the augmented Lagrangian's own tolerance, within which a ramp's
    /// answer already depends on its path (`fe_reference/warm_start/README.md`).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub reuse_factor: bool,
    /// Stabilised continuation where plain load control stops (module docs, "Through an
    /// instability"): when an output step has been cut back [`Self::max_cutbacks`] times in
    /// a row, the rest of it is taken with a viscous term `β · diag(K₀) · (u − u_prev)` (β is
    /// this value, `K₀` the tangent where the step stopped, `u_prev` the state of the last
    /// substep), and the output level is then solved again without it, so that every reported
    /// state is an undamped equilibrium. 0 switches it off (the step fails there). It acts
    /// only where the solver used to stop, so results that converged without it are
    /// unchanged; written to settings only when it differs from the default.
    #[serde(
        default = "default_stabilization",
        skip_serializing_if = "is_default_stabilization"
    )]
    pub stabilization: f64,
    /// Which nonlinear solver: the residual Newton of this module (the reference) or the
    /// minimisation of the total potential with the log-barrier contact
    /// ([`super::minimise`]). Written only when it is not the default, so that results
    /// computed before it keep their keys.
    #[serde(default, skip_serializing_if = "SolverKind::is_newton")]
    pub kind: SolverKind,
}

/// The nonlinear solver of a case ([`SolverSettings::kind`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// Load control, residual Newton and augmented-Lagrangian penalty contact.
    #[default]
    Newton,
    /// Minimisation of the total potential: barrier contact, descent Newton with a line
    /// search on the potential ([`super::minimise`]).
    Minimise(MinimiseSettings),
}

impl SolverKind {
    /// Whether this is the default residual Newton.
    pub fn is_newton(&self) -> bool {
        *self == Self::Newton
    }
}

/// Settings of the minimisation solver ([`SolverKind::Minimise`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MinimiseSettings {
    /// Activation distance d̂ of the log-barrier contact (mm): the contact surface is exact to
    /// within it ([`crate::fe::assembly::terms::barrier`]).
    pub dhat_mm: f64,
    /// Pressure scale p̂ of the barrier (MPa).
    pub barrier_pressure: f64,
    /// Target Newton iterations per load increment: an increment that took at most this many
    /// is followed by one twice as large, one that took at most twice as many by one 1.5
    /// times as large; only a failed increment is halved.
    pub target_iterations: usize,
}

impl Default for MinimiseSettings {
    fn default() -> Self {
        Self {
            dhat_mm: crate::fe::assembly::terms::barrier::DEFAULT_DHAT,
            barrier_pressure: crate::fe::assembly::terms::barrier::DEFAULT_BARRIER_PRESSURE,
            target_iterations: 4,
        }
    }
}

/// Default of [`SolverSettings::stabilization`].
pub const DEFAULT_STABILIZATION: f64 = 1e-3;

fn default_stabilization() -> f64 {
    DEFAULT_STABILIZATION
}

#[allow(clippy::trivially_copy_pass_by_ref)]
fn is_default_stabilization(v: &f64) -> bool {
    *v == DEFAULT_STABILIZATION
}

fn is_false(v: &bool) -> bool {
    !*v
}

#[allow(clippy::trivially_copy_pass_by_ref)]
fn is_true(v: &bool) -> bool {
    *v
}

/// A modified-Newton iteration ([`SolverSettings::reuse_factor`]) must leave at most this
/// share of the previous residual, or the tangent is refactorised.
pub const REUSE_CONTRACTION: f64 = 0.25;

fn is_zero(v: &usize) -> bool {
    *v == 0
}

/// Change of a contact point's multiplier, divided by ε (mm), below which the
/// augmented-Lagrangian updates stop: the walls then touch to within about this distance.
pub const AUGMENTED_GAP_TOL: f64 = 1e-3;

fn yes() -> bool {
    true
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            rtol: 1e-7,
            max_iterations: 20,
            max_cutbacks: 10,
            initial_fraction: 1.0,
            initial_pressure_increment: 0.01,
            max_pressure_increment: 0.05,
            grow_below_iterations: 8,
            line_search: false,
            predictor: true,
            mixed_tangent: true,
            trace: false,
            augmented_updates: 6,
            reuse_factor: true,
            stabilization: DEFAULT_STABILIZATION,
            kind: SolverKind::Newton,
        }
    }
}

/// Largest relative residual tolerance [`SolverSettings::validate`] accepts: above it a
/// "converged" state is not an equilibrium worth reporting.
pub const MAX_RTOL: f64 = 1e-2;

impl SolverSettings {
    /// Checks every field's range; the error names the field (`rtol`, `max_iterations`, …).
    ///
    /// # Errors
    /// [`InvalidSetting`] for the first field out of range.
    pub fn validate(&self) -> Result<(), InvalidSetting> {
        let positive = |field: &str, v: f64, upper: f64, expected: &str| {
            if v.is_finite() && v > 0.0 && v <= upper {
                Ok(())
            } else {
                Err(InvalidSetting::new(field, v, expected))
            }
        };
        if !(self.rtol.is_finite() && self.rtol > 0.0 && self.rtol < MAX_RTOL) {
            return Err(InvalidSetting::new(
                "rtol",
                self.rtol,
                format!("a relative residual tolerance in (0, {MAX_RTOL:e})"),
            ));
        }
        if self.max_iterations == 0 {
            return Err(InvalidSetting::new("max_iterations", 0.0, "at least 1"));
        }
        positive(
            "initial_fraction",
            self.initial_fraction,
            1.0,
            "a fraction of an output step in (0, 1]",
        )?;
        positive(
            "initial_pressure_increment",
            self.initial_pressure_increment,
            0.5,
            "a pressure increment in (0, 0.5] MPa",
        )?;
        positive(
            "max_pressure_increment",
            self.max_pressure_increment,
            0.5,
            "a pressure increment in (0, 0.5] MPa (5 bar)",
        )?;
        if !(self.stabilization.is_finite() && self.stabilization >= 0.0) {
            return Err(InvalidSetting::new(
                "stabilization",
                self.stabilization,
                "a viscous factor β ≥ 0 (0 switches it off)",
            ));
        }
        if self.augmented_updates > 100 {
            return Err(InvalidSetting::new(
                "augmented_updates",
                self.augmented_updates as f64,
                "at most 100 Uzawa updates per output step (2–4 are used)",
            ));
        }
        if let SolverKind::Minimise(m) = &self.kind {
            if !(m.dhat_mm.is_finite() && (1e-6..=0.5).contains(&m.dhat_mm)) {
                return Err(InvalidSetting::new(
                    "kind.dhat_mm",
                    m.dhat_mm,
                    "a barrier activation distance d̂ in [1e-6, 0.5] mm",
                ));
            }
            if !(m.barrier_pressure.is_finite() && (1e-4..=1e3).contains(&m.barrier_pressure)) {
                return Err(InvalidSetting::new(
                    "kind.barrier_pressure",
                    m.barrier_pressure,
                    "a barrier pressure scale p̂ in [1e-4, 1e3] MPa",
                ));
            }
            if !(1..=20).contains(&m.target_iterations) {
                return Err(InvalidSetting::new(
                    "kind.target_iterations",
                    m.target_iterations as f64,
                    "a target of 1 to 20 Newton iterations per increment",
                ));
            }
        }
        Ok(())
    }
}

/// How one output step was reached.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// Load level reached.
    pub level: LoadLevel,
    /// Newton iterations over all substeps.
    pub newton_iterations: usize,
    /// Substeps taken.
    pub substeps: usize,
    /// Cut-backs.
    pub cutbacks: usize,
    /// Final normalised residual ‖r‖ / max(‖f_ext‖, ‖reactions‖, force floor).
    pub residual: f64,
    /// Final normalised update ‖Δu‖ / ‖u‖.
    pub update: f64,
    /// Whether the step converged.
    pub converged: bool,
    /// Seconds in factorisations.
    pub factor_seconds: f64,
    /// Seconds in assembly.
    pub assembly_seconds: f64,
    /// Augmented-Lagrangian updates of the contact gap shifts made at this step.
    #[serde(default)]
    pub augmented_updates: usize,
    /// An update's Newton solve failed: the step keeps the state converged with the shifts
    /// before it (contact accurate to that update's change rather than to the tolerance).
    #[serde(default)]
    pub augmented_failed: bool,
    /// Factorisations of the tangent (fewer than the iterations with
    /// [`SolverSettings::reuse_factor`]).
    #[serde(default)]
    pub factorizations: usize,
    /// The step was completed through an instability with the stabilised continuation
    /// ([`SolverSettings::stabilization`]); its final state is an undamped equilibrium.
    #[serde(default, skip_serializing_if = "is_false")]
    pub stabilized: bool,
    /// The step was solved directly from a neighbouring case's state
    /// ([`super::warm`]), not along the path from the previous level.
    #[serde(default, skip_serializing_if = "is_false")]
    pub warm_start: bool,
    /// Newton solves of the homotopy ([`super::warm`]) tried at this step where a warm
    /// start's direct Newton failed, the halved ones included; their iterations are in
    /// [`Self::newton_iterations`]. The step was reached by it if [`Self::warm_start`] is set,
    /// along the path after it otherwise. Reports written before it existed read as 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub homotopy_steps: usize,
}

/// Why a solve stopped.
#[derive(Debug, Error)]
pub enum SolverError {
    /// The load step could not be completed after all cut-backs.
    #[error(
        "Newton did not converge towards load {target:?}: stopped at {reached:?} after {cutbacks} \
         cut-backs (last normalised residual {residual:.3e}); {completed} output steps had converged"
    )]
    NotConverged {
        /// The output level aimed at (boxed, as `reached`: the error stays small).
        target: Box<LoadLevel>,
        /// The last converged level.
        reached: Box<LoadLevel>,
        /// Cut-backs made.
        cutbacks: usize,
        /// Last residual.
        residual: f64,
        /// Output steps completed before.
        completed: usize,
        /// Reports of the completed steps.
        reports: Vec<StepReport>,
    },
    /// The factorisation failed (singular tangent: the model is not restrained?).
    #[error("sparse factorisation failed: {0}")]
    Factorization(String),
    /// An element is degenerate or inverted at a converged state.
    #[error(transparent)]
    Element(#[from] ElementError),
    /// The minimisation solver was asked to drive a problem without a total potential.
    #[error("the minimisation solver needs a problem with a total potential; this one has none")]
    NoPotential,
    /// The starting state of the minimisation is not admissible (a contact gap ≤ 0 under the
    /// barrier, or an inverted element).
    #[error("the minimisation solver cannot start: {0}")]
    Inadmissible(String),
}

impl SolverError {
    /// A [`SolverError::NotConverged`] of a path, carrying the `reports` of the output steps
    /// that converged before it (`completed` is their number); other errors unchanged.
    pub fn after(self, reports: Vec<StepReport>) -> Self {
        match self {
            SolverError::NotConverged {
                target,
                reached,
                cutbacks,
                residual,
                ..
            } => SolverError::NotConverged {
                target,
                reached,
                cutbacks,
                residual,
                completed: reports.len(),
                reports,
            },
            e => e,
        }
    }
}
