//! Load stepping with adaptive cut-back, Newton–Raphson with line search, and the sparse
//! direct solver (faer) whose symbolic analysis is done once per mesh.
//!
//! Each load step solves `r(u; λ) = 0` on the free equations. Newton: `K Δu = −r`, then a line
//! search on the directional residual `s(α) = Δu · r(u + α Δu)` (Crisfield / Matthies–Strang),
//! which, the problem being conservative, minimises the total potential along `Δu`. A trial
//! state with an inverted element (det F ≤ 0) halves `α`. A step that does not converge is
//! cut back (halved) and retried from the last converged state.
//!
//! Convergence behaviour with κ = 1000 μ0 (measured on the actuator, `SURROGATE_TRACE=1`):
//! a Newton step along the soft bending mode is a linearised rotation, which violates J = 1 at
//! second order; κ turns that into a residual far larger than the load increment, corrected
//! in the next iterations. Recomputing the pressure from those displacements would put the same
//! spurious κ·O(θ²) pressure into the initial-stress term of the next tangent and wreck the
//! bending stiffness of the thin walls (≈ 10 erratic iterations per 0.1 bar). The default
//! [`SolverSettings::mixed_tangent`] iteration carries the element pressures linearly instead
//! (the mixed u–θ–π Newton of Simo–Taylor–Pister, condensed per element): same residual, same
//! solution, quadratic convergence after the first two iterations, ≈ 6–8 iterations per
//! increment of 0.05–0.1 bar (N = 11, T = 2, coarse: 314 → 90 iterations for 0 → 3 bar).
//! Line searches do not help here and are off by default.
//!
//! Predictor (on by default): each increment starts from the path extrapolated in the
//! pressure, quadratic through the last three converged states (linear through two). A
//! linear extrapolation of rotations violates J = 1 at second order, like the Newton step
//! itself, but the quadratic one only at third order, and it carries the curvature of the
//! path, which the tangent does not. Two guards: a prediction that would push a contact point
//! deeper than the smoothing width δ below the smallest gap of the last state (contact that
//! the extrapolation cannot know about) is not used, and an increment that fails from a
//! prediction is retried once from the last converged state before it is cut back. After an
//! augmented-Lagrangian update the stored states are moved by the same correction as the
//! current one, so that the extrapolation does not see the jump. Measured, one thread, coarse,
//! 0 → 3.5 bar in 0.25 bar output steps, same solutions to 3e-9 mm:
//!
//! | case | Newton iterations without → with | wall time |
//! |---|---|---|
//! | N = 11, T = 2, Ogden 002, bending | 369 → 203 | 170 → 119 s |
//! | N = 11, T = 2, Ogden 002, blocked force | 255 → 254 | 147 → 145 s |
//! | snapshot case 15 (N = 13, T = 1.86, soft), bending | 1531 → 388 | 851 → 270 s |
//!
//! In force mode most iterations are the Uzawa re-solves at each output level, which the
//! predictor does not touch. Extrapolating the contact gap shifts too (linearly from the last
//! two output levels, points in contact at both) was tried and dropped: 203 → 200 iterations
//! in bending, 254 → 266 in force mode. It also showed how far the augmented-Lagrangian stop
//! (no multiplier change above ε · 1e-3 mm) leaves the result path-dependent: up to 0.022 mm
//! of tip displacement on the coarse N = 11, T = 2 bending ramp. Over-relaxing the Uzawa
//! update (`c ← c − ω g`) does not speed it up either: force mode 254 → 286 iterations at
//! ω = 1.5 and 442 at ω = 2. A stiffer penalty under the augmented Lagrangian (ε = 100
//! instead of 20 MPa/mm, coarse N = 11, T = 2, 0 → 3.5 bar in 0.25 bar steps): blocked force
//! 254 → 207 iterations (−19 %, force within 0.003 N), but bending 203 → 215 (tip within
//! 0.014 mm); 457 → 422 for a snapshot case, not enough to change the default.
//!
//! Giving up early and retrying: an iteration whose residual is more than 10× the best one
//! since the first (from the third on), or two iterations in a row that each keep more than
//! 90 % of the residual while it is still above 1e-3, end the attempt; the increment actually
//! tried is halved and retried. Measured on a snapshot case with bellows in contact from
//! 0.75 bar (N = 11, T = 1.94, coarse, 0 → 2 bar): 712 → 569 Newton iterations, same solution
//! to 3e-8 mm. Ending an attempt whose normalised residual is still above 1 from the fifth
//! iteration on was tried too: more cut-backs, 203 → 245 iterations in bending and 254 → 269
//! in force mode (coarse N = 11, T = 2, 0 → 3.5 bar in 0.25 bar steps). A contact step guard (shortening steps that push a contact point more than
//! 0.1 mm deeper) was tried: −11 % iterations there, but 2.5× more on N = 11, T = 2, Ogden 002
//! (159 → 399), so it is not used.
//!
//! Reusing a factorisation was also tried: right-preconditioned GMRES with the last LDLᵀ
//! factor, at the first iteration of an increment and once the residual is below 1e-2
//! (3–12 GMRES iterations there; the iterations in between change the tangent too much).
//! It saved a quarter of the factorisations with the same iterates, but one triangular solve
//! pair costs about 1/7 of a factorisation here, so the wall time did not change (N = 11,
//! T = 2, coarse, one thread: 68.6 → 67.0 s). Every iteration factorises by default.
//! [`SolverSettings::reuse_factor`] (`simulate --reuse-factor`) tries modified Newton in the
//! re-solves after the Uzawa updates, where the load does not change: the last factor is
//! kept while each iteration divides the residual by 4. Measured on the coarse blocked-force
//! ramp (N = 11, T = 2, 0 → 3.5 bar in 0.25 bar steps, one thread, machine loaded): same
//! forces to 1e-5 N, 254 → 304 iterations, factorisation time 56 → 50 s, wall 142 → 134 s. The
//! first re-solve iteration after an update often contracts too little (the set of points in
//! contact changes), so full Newton takes over; on the coarse mesh the assembly (58 % of the
//! time in force mode) limits what a saved factorisation buys. Off by default.
//!
//! The step guard's residual (the det F check assembles the residual at the state the step
//! moves to) is kept: when it already meets the tolerance, the next iteration returns
//! without assembling a tangent it would not use. Same residual, same decisions: the coarse
//! N = 11, T = 2 ramps (0 → 3.5 bar, 0.25 bar steps) give bit-identical steps, with about
//! 11 % less CPU time (bending 58.3 → 52.1 s, blocked force 73.6 → 65.7 s, one thread, loaded
//! machine).
//!
//! Through an instability ([`SolverSettings::stabilization`]): where an output step has been
//! cut back [`SolverSettings::max_cutbacks`] times in a row (a limit or bifurcation point:
//! the tangent is nearly singular and Newton steps shoot off along its soft mode), the rest
//! of the step is taken with a viscous term `β · diag(K₀) · (u − u_prev)` added to the
//! residual and `β · diag(K₀)` to the tangent, `K₀` the tangent where the step stopped and
//! `u_prev` the state of the previous substep (pseudo-time stepping, as the "stabilize"
//! option of commercial codes). At the output level the term is relaxed at constant load,
//! weakened fourfold per relaxation step (pseudo-transient continuation), and an undamped
//! Newton solve is tried whenever the viscous force of a step has fallen below 1 % of the
//! force scale: only an undamped equilibrium is reported ([`StepReport::stabilized`] marks
//! the step), otherwise the step fails as before. It acts only where the solver used to
//! stop, so every result that converged without it is unchanged. Test: a clamped shallow arch
//! under a dead load snaps through two instabilities to its inverted shape
//! (`tests/solver_stabilization.rs`). On the actuator, the blocked-force failures it was
//! written for (thin N = 13, soft sets, above 2.5 bar) turned out to be a missing contact
//! instead: the tip had turned past vertical on the plate and the end cap went through it
//! ([`super::simulate`]).
//!
//! The fill-reducing ordering is the one of AMD and METIS nested dissection
//! ([`super::ordering`]) that gives the smaller factor: nested dissection on the standard mesh
//! (nnz(L) 64.5 M → 52.5 M, one factorisation about 30 % faster, `cargo bench --bench fe --
//! standard`), AMD on the coarse one.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Side};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::assembly::{AssemblyInfo, FeModel, LoadLevel};
use super::element::ElementError;
use super::ordering::nested_dissection;

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
    /// First pressure increment of a step (MPa); later increments adapt.
    pub initial_pressure_increment: f64,
    /// An increment that converged in at most this many Newton iterations is followed by one
    /// 1.5 times larger.
    pub grow_below_iterations: usize,
    /// Largest pressure increment in one substep (MPa).
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
    /// displacements (see [`super::element::linearised_pressure`]). Same residual and
    /// solution; with κ = 1000 μ0 it converges in far fewer iterations.
    #[serde(default = "yes")]
    pub mixed_tangent: bool,
    /// Print every Newton iteration to stderr.
    #[serde(default)]
    pub trace: bool,
    /// Augmented-Lagrangian contact: after each converged output step, up to this many Uzawa
    /// updates of the contact gap shifts ([`super::contact::update_shift`]), each followed by
    /// a Newton solve at the same load, until no contact point's multiplier changes by more
    /// than ε · [`AUGMENTED_GAP_TOL`]; 0 gives the plain penalty. Default 6 (2–4 are used).
    /// Settings written before this field existed read as 0: the plain penalty they were
    /// computed with.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub augmented_updates: usize,
    /// Modified Newton in the re-solves after an Uzawa update: the iterations reuse the last
    /// factorised tangent (residual-only assembly and one pair of triangular solves) as long
    /// as each one divides the residual by at least 1 / [`REUSE_CONTRACTION`]; then full
    /// Newton takes over. Same tolerance, so the same solution up to it. Off by default;
    /// written to settings only when on, so that results computed before it keep their keys.
    #[serde(default, skip_serializing_if = "is_false")]
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
            reuse_factor: false,
            stabilization: DEFAULT_STABILIZATION,
        }
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
        /// The output level aimed at.
        target: LoadLevel,
        /// The last converged level.
        reached: LoadLevel,
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
}

/// Fill-reducing ordering of a [`LinearSolver`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ordering {
    /// faer's approximate minimum degree.
    MinimumDegree,
    /// METIS nested dissection on the node graph ([`super::ordering`]).
    NestedDissection,
}

/// Sparse direct solver with a reusable symbolic analysis: supernodal LDLᵀ (faer) on the
/// lower triangle. LDLᵀ needs no positive definiteness: the tangent of a pressurised
/// structure away from equilibrium may be indefinite.
pub struct LinearSolver {
    n: usize,
    /// The fill-reducing ordering in use.
    pub ordering: Ordering,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    factor_buf: MemBuffer,
    solve_buf: MemBuffer,
    rhs: Mat<f64>,
    /// Number of factorisations performed.
    pub factorizations: usize,
    /// Whether `l_values` holds a complete factor (of the last matrix passed to `solve`).
    factored: bool,
}

impl LinearSolver {
    /// Symbolic analysis (fill-reducing ordering, elimination tree) of the model's pattern.
    /// Both orderings are analysed, minimum degree and nested dissection, and the one with
    /// the smaller factor is kept (the choice depends only on the pattern).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if faer rejects the pattern.
    pub fn new(model: &FeModel) -> Result<Self, SolverError> {
        Self::with_ordering(model, None)
    }

    /// As [`Self::new`] with the given ordering (`None`: the one with the smaller factor).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if faer rejects the pattern, or METIS fails when nested
    /// dissection is asked for.
    pub fn with_ordering(model: &FeModel, choice: Option<Ordering>) -> Result<Self, SolverError> {
        let n = model.dofs.n_free;
        let col_ptr = model.pattern.col_ptr.clone();
        let row_idx = model.pattern.row_idx.clone();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let fail = |e| SolverError::Factorization(format!("{e:?}"));
        let amd = || {
            factorize_symbolic_cholesky(sym, Side::Lower, Default::default(), Default::default())
                .map_err(fail)
        };
        let nd = || -> Result<_, SolverError> {
            let Some(perm) = nested_dissection(&model.pattern, &model.dofs) else {
                return Ok(None);
            };
            let mut inverse = vec![0usize; n];
            for (new, &old) in perm.iter().enumerate() {
                inverse[old] = new;
            }
            factorize_symbolic_cholesky(
                sym,
                Side::Lower,
                SymmetricOrdering::Custom(PermRef::new_checked(&perm, &inverse, n)),
                Default::default(),
            )
            .map(Some)
            .map_err(fail)
        };
        let (symbolic, ordering) = match choice {
            Some(Ordering::MinimumDegree) => (amd()?, Ordering::MinimumDegree),
            Some(Ordering::NestedDissection) => (
                nd()?.ok_or_else(|| {
                    SolverError::Factorization("METIS nested dissection failed".into())
                })?,
                Ordering::NestedDissection,
            ),
            None => {
                let a = amd()?;
                match nd()? {
                    Some(d) if d.len_val() < a.len_val() => (d, Ordering::NestedDissection),
                    _ => (a, Ordering::MinimumDegree),
                }
            }
        };
        let par = faer::get_global_parallelism();
        let factor_buf =
            MemBuffer::new(symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()));
        let solve_buf = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(Self {
            n,
            ordering,
            l_values: vec![0.0; symbolic.len_val()],
            col_ptr,
            row_idx,
            symbolic,
            factor_buf,
            solve_buf,
            rhs: Mat::zeros(n, 1),
            factorizations: 0,
            factored: false,
        })
    }

    /// Stored entries of the factor L.
    pub fn nnz_l(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Solves `K x = b` in place, K given by its lower triangle.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] on a zero pivot (singular tangent) or non-finite result.
    pub fn solve(&mut self, values: &[f64], b: &mut [f64]) -> Result<(), SolverError> {
        let sym = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let mat = SparseColMatRef::new(sym, values);
        let par = faer::get_global_parallelism();
        self.factorizations += 1;
        self.factored = false;
        self.symbolic
            .factorize_numeric_ldlt(
                &mut self.l_values,
                mat,
                Side::Lower,
                LdltRegularization::default(),
                par,
                MemStack::new(&mut self.factor_buf),
                Default::default(),
            )
            .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
        self.factored = true;
        self.solve_factored(b)
    }

    /// Whether a factor is available to [`Self::solve_factored`].
    pub fn has_factor(&self) -> bool {
        self.factored
    }

    /// Solves `K x = b` in place with the factor of the last matrix passed to
    /// [`Self::solve`] (no factorisation).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if no factor is available or the result is not finite.
    pub fn solve_factored(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::Factorization(
                "no factor to reuse: the last factorisation failed or none was made".into(),
            ));
        }
        let par = faer::get_global_parallelism();
        for (i, v) in b.iter().enumerate() {
            self.rhs[(i, 0)] = *v;
        }
        LdltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            self.rhs.as_mut(),
            par,
            MemStack::new(&mut self.solve_buf),
        );
        for (i, v) in b.iter_mut().enumerate() {
            *v = self.rhs[(i, 0)];
            if !v.is_finite() {
                return Err(SolverError::Factorization(format!(
                    "non-finite solution at equation {i}"
                )));
            }
        }
        Ok(())
    }
}

/// The state carried along a load path.
pub struct PathState {
    /// Free unknowns at the last converged level.
    pub u_free: Vec<f64>,
    /// Full displacement vector at the last converged level.
    pub u_full: Vec<f64>,
    /// The last converged level.
    pub level: LoadLevel,
    /// Up to two earlier converged states (oldest first), for the predictor.
    history: Vec<(Vec<f64>, LoadLevel)>,
}

impl PathState {
    /// The undeformed state at zero load (and the model's contact gap shifts reset).
    pub fn new(model: &FeModel) -> Self {
        model.reset_contact_shifts();
        Self {
            u_free: vec![0.0; model.dofs.n_free],
            u_full: vec![0.0; 3 * model.mesh.n_nodes()],
            level: LoadLevel::default(),
            history: Vec::new(),
        }
    }
}

struct NewtonOutcome {
    converged: bool,
    iterations: usize,
    residual: f64,
    update: f64,
}

/// Drives a model along a load path.
pub struct Solver<'m> {
    model: &'m FeModel,
    linear: LinearSolver,
    settings: SolverSettings,
    r_full: Vec<f64>,
    u_pred: Vec<f64>,
    r_free: Vec<f64>,
    k: Vec<f64>,
    du: Vec<f64>,
    du_full: Vec<f64>,
    trial: Vec<f64>,
    /// Element pressures carried by the mixed iteration (valid when `use_tangent_pressure`).
    tangent_pressure: Vec<[f64; 4]>,
    use_tangent_pressure: bool,
    /// External-force norm of the residual that the step guard of [`Self::line_search`]
    /// assembled at exactly the state the step moved to (then in `r_full` / `r_free`).
    guard_residual: Option<f64>,
    factor_seconds: f64,
    assembly_seconds: f64,
    /// Floor of the force scale: 1e-3 · μ0 · V^(2/3) (a characteristic internal force).
    force_scale: f64,
    /// Pressure increment of the last converged substep.
    last_increment: Option<f64>,
    /// Viscous term of the stabilised continuation, while it is on.
    stab: Option<Stabilization>,
    /// Force scale of the last Newton iteration's convergence test.
    last_force_scale: f64,
}

/// The viscous term `c ⊙ (u − u_ref)` of the stabilised continuation
/// ([`SolverSettings::stabilization`]), on the free unknowns.
struct Stabilization {
    /// β · |K₀ᵢᵢ| per free unknown.
    damping: Vec<f64>,
    /// The state of the last substep.
    u_ref: Vec<f64>,
    /// The undamped equilibrium it started from, restored if it fails.
    origin: (Vec<f64>, LoadLevel),
    /// Factor on `damping` (pseudo-time step⁻¹ of the relaxation).
    scale: f64,
}

/// Stabilised relaxation steps at the output level, each followed by an undamped solve,
/// before the stabilised continuation gives up.
const MAX_RELAXATIONS: usize = 40;

/// First pressure increment (MPa) of the stabilised continuation.
const STABILIZED_INCREMENT: f64 = 0.0025;

/// A Newton iteration that keeps more than this share of the residual makes no progress.
const STALL_RATIO: f64 = 0.9;

impl<'m> Solver<'m> {
    /// Prepares a solver (symbolic factorisation) for a model.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if the symbolic analysis fails.
    pub fn new(model: &'m FeModel, settings: SolverSettings) -> Result<Self, SolverError> {
        let n = model.dofs.n_free;
        Ok(Self {
            model,
            linear: LinearSolver::new(model)?,
            settings,
            r_full: vec![0.0; 3 * model.mesh.n_nodes()],
            u_pred: Vec::new(),
            r_free: vec![0.0; n],
            k: vec![0.0; model.pattern.nnz()],
            du: vec![0.0; n],
            du_full: vec![0.0; 3 * model.mesh.n_nodes()],
            trial: vec![0.0; n],
            tangent_pressure: vec![[0.0; 4]; model.mesh.n_elements()],
            use_tangent_pressure: false,
            guard_residual: None,
            factor_seconds: 0.0,
            assembly_seconds: 0.0,
            last_increment: None,
            stab: None,
            last_force_scale: 0.0,
            force_scale: {
                let v: f64 = model.geometry.iter().map(|g| g.volume()).sum();
                1e-3 * model.material.mu0() * v.powf(2.0 / 3.0)
            },
        })
    }

    /// The residual (all dofs, reactions at constrained ones) of the last assembly.
    pub fn residual_full(&self) -> &[f64] {
        &self.r_full
    }

    /// Advances `state` to `target` with adaptive substeps.
    ///
    /// # Errors
    /// [`SolverError::NotConverged`] (with `completed = 0` and no reports: the caller fills
    /// them in) if the step fails after all cut-backs.
    pub fn advance(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
    ) -> Result<StepReport, SolverError> {
        let start = state.level;
        let dp = (target.pressure - start.pressure).abs();
        let mut frac = self.settings.initial_fraction.min(1.0);
        if dp > 0.0 {
            let first = self
                .last_increment
                .unwrap_or(self.settings.initial_pressure_increment);
            frac = frac.min(first.min(self.settings.max_pressure_increment) / dp);
        }
        let mut s = 0.0;
        let mut report = StepReport {
            level: target,
            newton_iterations: 0,
            substeps: 0,
            cutbacks: 0,
            residual: 0.0,
            update: 0.0,
            converged: false,
            factor_seconds: 0.0,
            assembly_seconds: 0.0,
            augmented_updates: 0,
            augmented_failed: false,
            factorizations: 0,
            stabilized: false,
        };
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        let mut consecutive_cuts = 0;
        let mut retry_plain = false;
        self.stab = None;
        while s < 1.0 - 1e-12 {
            let s_next = (s + frac).min(1.0);
            let level = start.lerp(&target, s_next);
            let saved = state.u_free.clone();
            let predicted = self.settings.predictor
                && !retry_plain
                && self.stab.is_none()
                && self.predict(state, &level);
            retry_plain = false;
            let out = self.newton(state, &level, false)?;
            report.newton_iterations += out.iterations;
            report.residual = out.residual;
            report.update = out.update;
            if !out.converged && predicted {
                // retry the same increment from the last converged state
                state.u_free = saved;
                retry_plain = true;
                continue;
            }
            if out.converged {
                if let Some(st) = &mut self.stab {
                    // the next substep is damped against this state; the predictor must not
                    // extrapolate across the jump
                    st.u_ref.copy_from_slice(&state.u_free);
                    state.history.clear();
                } else {
                    if state.history.len() == 2 {
                        state.history.remove(0);
                    }
                    state.history.push((saved, state.level));
                }
                state.level = level;
                s = s_next;
                report.substeps += 1;
                consecutive_cuts = 0;
                if dp > 0.0 {
                    self.last_increment = Some(frac * dp);
                }
                if out.iterations <= self.settings.grow_below_iterations {
                    frac *= 1.5;
                }
                if dp > 0.0 {
                    frac = frac.min(self.settings.max_pressure_increment / dp);
                }
            } else {
                state.u_free = saved;
                report.cutbacks += 1;
                consecutive_cuts += 1;
                // halve the increment actually tried (it may have been clipped to the end
                // of the step), so that the retry is a different, smaller one
                frac = 0.5 * (s_next - s);
                self.last_increment = None;
                if consecutive_cuts > self.settings.max_cutbacks
                    && self.stab.is_none()
                    && self.settings.stabilization > 0.0
                    && self.start_stabilization(state)
                {
                    // through the instability with the viscous term (module docs)
                    report.stabilized = true;
                    consecutive_cuts = 0;
                    frac = (STABILIZED_INCREMENT / dp.max(1e-300)).min(1.0 - s);
                    continue;
                }
                if consecutive_cuts > self.settings.max_cutbacks {
                    let origin = self.stab.take().map(|st| st.origin);
                    return Err(self.give_up(state, target, origin, report.cutbacks, out.residual));
                }
            }
        }
        let origin = self.stab.as_ref().map(|st| st.origin.clone());
        if origin.is_some() && !self.finish_stabilization(state, &target, &mut report)? {
            // the output level was reached only with the viscous term
            return Err(self.give_up(state, target, origin, report.cutbacks, report.residual));
        }
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        report.converged = true;
        report.factor_seconds = self.factor_seconds - f0;
        report.assembly_seconds = self.assembly_seconds - a0;
        report.factorizations = self.linear.factorizations - n0;
        Ok(report)
    }

    /// Ends a step that cannot reach `target`: back to the last undamped equilibrium
    /// (`origin`, where the stabilised continuation had moved on from it), and the error (its
    /// `completed` and `reports` are filled in by the caller).
    fn give_up(
        &mut self,
        state: &mut PathState,
        target: LoadLevel,
        origin: Option<(Vec<f64>, LoadLevel)>,
        cutbacks: usize,
        residual: f64,
    ) -> SolverError {
        if let Some(origin) = origin {
            (state.u_free, state.level) = origin;
            state.history.clear();
        }
        self.model
            .expand(&state.u_free, &state.level, &mut state.u_full);
        SolverError::NotConverged {
            target,
            reached: state.level,
            cutbacks,
            residual,
            completed: 0,
            reports: Vec::new(),
        }
    }

    /// Uzawa updates of the contact gap shifts at the converged `level`, each followed by a
    /// Newton solve at the same load (see [`SolverSettings::augmented_updates`]).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] / [`SolverError::Element`] from the Newton solves. A
    /// solve that does not converge is not an error: the step keeps the state converged with
    /// the shifts before that update ([`StepReport::augmented_failed`]).
    pub fn augment(
        &mut self,
        state: &mut PathState,
        level: LoadLevel,
        report: &mut StepReport,
    ) -> Result<(), SolverError> {
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let n0 = self.linear.factorizations;
        for _ in 0..self.settings.augmented_updates {
            let saved = self.model.contact_shifts();
            let update = self
                .model
                .update_contact_shifts(&state.u_full, AUGMENTED_GAP_TOL);
            if self.settings.trace {
                eprintln!(
                    "  augmented update: {} points in contact, largest change {:.3e} mm",
                    update.active_points, update.max_change
                );
            }
            if !update.applied {
                break;
            }
            report.augmented_updates += 1;
            // one Newton solve at the same load (cutting back a zero load increment would
            // only repeat it)
            let saved_u = state.u_free.clone();
            let out = self.newton(state, &level, self.settings.reuse_factor)?;
            report.newton_iterations += out.iterations;
            if out.converged {
                report.residual = out.residual;
                report.update = out.update;
                self.model
                    .expand(&state.u_free, &state.level, &mut state.u_full);
                // the predictor's earlier states move with the correction (they were
                // converged with the previous shifts)
                for (h, _) in &mut state.history {
                    for ((hv, now), before) in h.iter_mut().zip(&state.u_free).zip(&saved_u) {
                        *hv += now - before;
                    }
                }
            } else {
                // the jump of contact pressures was too large for Newton: keep the state
                // converged with the previous shifts
                state.u_free = saved_u;
                self.model
                    .expand(&state.u_free, &state.level, &mut state.u_full);
                self.model.set_contact_shifts(&saved);
                report.augmented_failed = true;
                break;
            }
        }
        report.factor_seconds += self.factor_seconds - f0;
        report.assembly_seconds += self.assembly_seconds - a0;
        report.factorizations += self.linear.factorizations - n0;
        Ok(())
    }

    /// Predictor: moves `state.u_free` to the extrapolated path at `level` and returns
    /// whether it did ([`SolverSettings::predictor`]).
    fn predict(&mut self, state: &mut PathState, level: &LoadLevel) -> bool {
        // extrapolate along a path on which one load component varies (the one that differs
        // between the last level and this one): quadratic through the last three converged
        // states, linear through two
        let parts = |l: &LoadLevel| [l.pressure, l.gravity, l.traction, l.prescribed];
        let (now, target) = (parts(&state.level), parts(level));
        let varying: Vec<usize> = (0..4).filter(|&c| now[c] != target[c]).collect();
        let [c] = varying[..] else {
            return false;
        };
        let same_path = |l: &LoadLevel| {
            let p = parts(l);
            (0..4).all(|i| i == c || p[i] == target[i])
        };
        let param = |l: &LoadLevel| parts(l)[c];
        let k = state.history.len();
        let usable = state
            .history
            .iter()
            .rev()
            .take_while(|(_, l)| same_path(l))
            .count();
        if usable == 0 {
            return false;
        }
        let t = param(level);
        let t2 = param(&state.level);
        let mut u_pred = std::mem::take(&mut self.u_pred);
        u_pred.clear();
        if usable >= 2 {
            let (u0, l0) = &state.history[k - 2];
            let (u1, l1) = &state.history[k - 1];
            let (t0, t1) = (param(l0), param(l1));
            if t0 == t1 || t1 == t2 || t0 == t2 {
                self.u_pred = u_pred;
                return false;
            }
            let w0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2));
            let w1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2));
            let w2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1));
            u_pred.extend(
                u0.iter()
                    .zip(u1)
                    .zip(&state.u_free)
                    .map(|((a, b), c)| w0 * a + w1 * b + w2 * c),
            );
        } else {
            let (u1, l1) = &state.history[k - 1];
            let t1 = param(l1);
            if t1 == t2 {
                self.u_pred = u_pred;
                return false;
            }
            let w = (t - t2) / (t2 - t1);
            u_pred.extend(u1.iter().zip(&state.u_free).map(|(a, c)| c + w * (c - a)));
        }
        // reject a prediction that pushes a contact point deeper than the smoothing zone
        // below where the last state had it (a contact that the extrapolation does not know
        // about: Newton would start from a deep penetration); one that inverts an element
        // fails at Newton's first assembly and is retried from the last state
        let mut u_full = std::mem::take(&mut state.u_full);
        self.model.expand(&state.u_free, &state.level, &mut u_full);
        let (g_last, delta) = self.model.min_shifted_gap(&u_full);
        self.model.expand(&u_pred, level, &mut u_full);
        let (g_pred, _) = self.model.min_shifted_gap(&u_full);
        let accept = g_pred >= g_last.min(0.0) - delta;
        if self.settings.trace {
            eprintln!(
                "  predictor ({} points): smallest gap {g_pred:.3e} mm (last {g_last:.3e}): {}",
                usable.min(2) + 1,
                if accept { "used" } else { "rejected" }
            );
        }
        if accept {
            state.u_free.copy_from_slice(&u_pred);
        }
        state.u_full = u_full;
        self.u_pred = u_pred;
        accept
    }

    /// Residual (and tangent) at `u_full`, the expansion of `u_free` at `level`; with the
    /// stabilised continuation on, its viscous term is added on the free unknowns.
    fn assemble(
        &mut self,
        u_free: &[f64],
        u_full: &[f64],
        level: &LoadLevel,
        with_k: bool,
    ) -> Result<AssemblyInfo, ElementError> {
        let t = std::time::Instant::now();
        let k = with_k.then_some(&mut self.k[..]);
        let tp = (with_k && self.use_tangent_pressure).then_some(&self.tangent_pressure[..]);
        let info = self
            .model
            .assemble_mixed(u_full, level, &mut self.r_full, k, tp)?;
        self.model.restrict(&self.r_full, &mut self.r_free);
        if let Some(st) = &self.stab {
            for (((r, c), u), u0) in self
                .r_free
                .iter_mut()
                .zip(&st.damping)
                .zip(u_free)
                .zip(&st.u_ref)
            {
                *r += st.scale * c * (u - u0);
            }
            if with_k {
                for (&p, c) in self.model.pattern.col_ptr.iter().zip(&st.damping) {
                    self.k[p] += st.scale * c;
                }
            }
        }
        self.assembly_seconds += t.elapsed().as_secs_f64();
        Ok(info)
    }

    /// Switches the stabilised continuation on at the converged `state`: the viscous
    /// coefficients from the diagonal of the tangent there. Returns false if that tangent
    /// cannot be assembled.
    fn start_stabilization(&mut self, state: &mut PathState) -> bool {
        self.stab = None;
        self.use_tangent_pressure = false;
        let mut u_full = std::mem::take(&mut state.u_full);
        self.model.expand(&state.u_free, &state.level, &mut u_full);
        let ok = self
            .assemble(&state.u_free, &u_full, &state.level, true)
            .is_ok();
        state.u_full = u_full;
        if !ok {
            return false;
        }
        let pattern = &self.model.pattern;
        let beta = self.settings.stabilization;
        let mut damping: Vec<f64> = (0..self.model.dofs.n_free)
            .map(|j| {
                let p = pattern.col_ptr[j];
                // rows are sorted and ≥ the column: the diagonal comes first
                debug_assert_eq!(pattern.row_idx[p], j);
                beta * self.k[p].abs()
            })
            .collect();
        let mean = damping.iter().sum::<f64>() / damping.len().max(1) as f64;
        for c in &mut damping {
            if *c <= 0.0 || !c.is_finite() {
                *c = mean;
            }
        }
        if self.settings.trace {
            eprintln!(
                "  stabilised continuation from p={:.4} (β = {beta:.1e})",
                state.level.pressure
            );
        }
        self.stab = Some(Stabilization {
            damping,
            u_ref: state.u_free.clone(),
            origin: (state.u_free.clone(), state.level),
            scale: 1.0,
        });
        true
    }

    /// End of a stabilised output step at `level`: pseudo-transient relaxation at the same
    /// load. Each relaxation step solves with the viscous term against the state before it;
    /// the term is then weakened fourfold (a longer pseudo-time step), or strengthened if the
    /// step failed. Once the viscous force of a step is below 1 % of the force scale, an
    /// undamped Newton solve is tried from there. Returns whether an undamped equilibrium was
    /// reached; the viscous term is off afterwards.
    fn finish_stabilization(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        report: &mut StepReport,
    ) -> Result<bool, SolverError> {
        let Some(mut st) = self.stab.take() else {
            return Ok(true);
        };
        let mut try_undamped = true;
        for relaxation in 0..MAX_RELAXATIONS {
            if try_undamped {
                let saved = state.u_free.clone();
                let out = self.newton(state, level, false)?;
                report.newton_iterations += out.iterations;
                if self.settings.trace {
                    eprintln!(
                        "  undamped solve after {relaxation} relaxations (viscous scale {:.1e}): {}",
                        st.scale,
                        if out.converged { "converged" } else { "not converged" }
                    );
                }
                if out.converged {
                    report.residual = out.residual;
                    report.update = out.update;
                    return Ok(true);
                }
                state.u_free = saved;
            }
            st.u_ref.copy_from_slice(&state.u_free);
            self.stab = Some(st);
            let out = self.newton(state, level, false);
            st = self.stab.take().expect("set above");
            let out = out?;
            report.newton_iterations += out.iterations;
            if !out.converged {
                state.u_free.copy_from_slice(&st.u_ref);
                st.scale *= 4.0;
                try_undamped = false;
                if st.scale > 1e3 {
                    break;
                }
                continue;
            }
            // the viscous force of this step is what the undamped residual now is
            let viscous = st
                .damping
                .iter()
                .zip(&state.u_free)
                .zip(&st.u_ref)
                .map(|((c, u), u0)| (st.scale * c * (u - u0)).powi(2))
                .sum::<f64>()
                .sqrt();
            try_undamped = viscous <= 1e-2 * self.last_force_scale;
            st.scale *= 0.25;
        }
        Ok(false)
    }

    fn newton(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        reuse: bool,
    ) -> Result<NewtonOutcome, SolverError> {
        let mut u_full = std::mem::take(&mut state.u_full);
        let out = self.newton_inner(state, level, &mut u_full, reuse);
        state.u_full = u_full;
        out
    }

    fn newton_inner(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
        reuse: bool,
    ) -> Result<NewtonOutcome, SolverError> {
        let mut out = NewtonOutcome {
            converged: false,
            iterations: 0,
            residual: f64::INFINITY,
            update: f64::INFINITY,
        };
        let mut best_residual = f64::INFINITY;
        let mut previous_residual = f64::INFINITY;
        let mut stalled = 0;
        self.use_tangent_pressure = false;
        // modified Newton (the last factor) while it contracts fast enough
        let mut modified = reuse && self.linear.has_factor();
        self.guard_residual = None;
        for it in 0..=self.settings.max_iterations {
            self.model.expand(&state.u_free, level, u_full);
            // the step guard already assembled the residual at this state: if it meets the
            // tolerance, the tangent is not needed (same residual, same decision)
            if let Some(ext) = self.guard_residual.take() {
                let scale = ext.max(self.reaction_norm()).max(self.force_scale);
                let rn = norm(&self.r_free);
                if rn <= self.settings.rtol * scale
                    && (it > 0 || level_is_zero_increment(state, level))
                {
                    out.residual = rn / scale;
                    out.iterations = it;
                    out.converged = true;
                    if self.settings.trace {
                        eprintln!(
                            "  newton {it:2}  level p={:.4} g={:.2}  |r|/f = {:.3e}  (|r| = {rn:.3e}, f = {scale:.3e})",
                            level.pressure, level.gravity, out.residual
                        );
                    }
                    return Ok(out);
                }
            }
            let mut ext = match self.assemble(&state.u_free, u_full, level, !modified) {
                Ok(info) => info.external_norm,
                Err(_) => return Ok(out),
            };
            if modified && it >= 1 && norm(&self.r_free) > REUSE_CONTRACTION * previous_residual {
                // too slow: the tangent of this state from here on
                modified = false;
                ext = match self.assemble(&state.u_free, u_full, level, true) {
                    Ok(info) => info.external_norm,
                    Err(_) => return Ok(out),
                };
            }
            let reactions = self.reaction_norm();
            let scale = ext.max(reactions).max(self.force_scale);
            self.last_force_scale = scale;
            let rn = norm(&self.r_free);
            out.residual = rn / scale;
            out.iterations = it;
            if self.settings.trace {
                eprintln!(
                    "  newton {it:2}{}  level p={:.4} g={:.2}  |r|/f = {:.3e}  (|r| = {rn:.3e}, f = {scale:.3e})",
                    if modified { " (reused factor)" } else { "" },
                    level.pressure, level.gravity, out.residual
                );
            }
            if !rn.is_finite() {
                return Ok(out);
            }
            if rn <= self.settings.rtol * scale && (it > 0 || level_is_zero_increment(state, level))
            {
                out.converged = true;
                return Ok(out);
            }
            if it == self.settings.max_iterations {
                return Ok(out);
            }
            // the first Newton step may raise the residual by orders of magnitude (the
            // linearised rotations violate J = 1 at second order, see the module docs); from
            // then on the residual must come down
            if it >= 1 {
                best_residual = best_residual.min(rn);
            }
            if it >= 3 && rn > 10.0 * best_residual {
                // diverging: give up early and let the step be cut back
                return Ok(out);
            }
            // stagnating far from the solution (two iterations in a row that barely reduce
            // the residual): Newton will not recover in the iterations left
            stalled = if it >= 2 && rn > STALL_RATIO * previous_residual {
                stalled + 1
            } else {
                0
            };
            if stalled >= 2 && out.residual > 1e-3 {
                return Ok(out);
            }
            previous_residual = rn;
            for (d, r) in self.du.iter_mut().zip(&self.r_free) {
                *d = -r;
            }
            let t = std::time::Instant::now();
            let solved = if modified {
                self.linear.solve_factored(&mut self.du)
            } else {
                self.linear.solve(&self.k, &mut self.du)
            };
            self.factor_seconds += t.elapsed().as_secs_f64();
            if let Err(e) = solved {
                if self.settings.trace {
                    eprintln!("           {e}: cutting back");
                }
                return Ok(out);
            }
            let alpha = self.line_search(state, level, u_full);
            if self.settings.trace {
                // where the largest component of the step is (reference position of its node)
                let (imax, dmax) = self.du.iter().enumerate().fold((0, 0.0f64), |m, (i, v)| {
                    if v.abs() > m.1 {
                        (i, v.abs())
                    } else {
                        m
                    }
                });
                let at = (0..u_full.len())
                    .find(|&d| self.model.dofs.eq(d) == Some(imax))
                    .map(|d| (self.model.mesh.nodes[d / 3], d % 3));
                eprintln!("           step |du|max = {dmax:.3e} at {at:?}, alpha = {alpha:.3}");
            }
            let un = norm(&state.u_free).max(1e-12);
            out.update = alpha * norm(&self.du) / un;
            if alpha == 0.0 {
                return Ok(out);
            }
            if self.settings.mixed_tangent {
                self.carry_pressures(state, level, u_full, alpha);
            }
            for (u, d) in state.u_free.iter_mut().zip(&self.du) {
                *u += alpha * d;
            }
            // converged on a tiny update after a full Newton step with a small residual
            if out.update < 1e-13 && rn <= 1e-4 * scale {
                out.converged = true;
                out.iterations = it + 1;
                self.model.expand(&state.u_free, level, u_full);
                return Ok(out);
            }
        }
        Ok(out)
    }

    /// Element pressures of the mixed iteration at `u + α Δu`, linearised about `u`.
    fn carry_pressures(
        &mut self,
        state: &PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
        alpha: f64,
    ) {
        self.model.expand(&state.u_free, level, u_full);
        self.du_full.iter_mut().for_each(|v| *v = 0.0);
        for (d, v) in self.du_full.iter_mut().enumerate() {
            if let Some(e) = self.model.dofs.eq(d) {
                *v = alpha * self.du[e];
            }
        }
        self.use_tangent_pressure = self
            .model
            .linearised_pressures(u_full, &self.du_full, &mut self.tangent_pressure)
            .is_ok();
    }

    fn reaction_norm(&self) -> f64 {
        let mut s = 0.0;
        for &(d, _) in &self.model.dofs.constrained {
            s += self.r_full[d] * self.r_full[d];
        }
        s.sqrt()
    }

    /// Returns the step length α ∈ (0, 1] (0 if no admissible step was found).
    ///
    /// `s(α) = Δu · r(u + αΔu)` is the directional derivative of the total potential; it is
    /// negative at α = 0. The full step is accepted while the potential still decreases there
    /// (`s(1) ≤ 0`) or has its minimum nearby (`|s| ≤ ½|s₀|`); otherwise regula falsi on `s`.
    fn line_search(&mut self, state: &PathState, level: &LoadLevel, u_full: &mut [f64]) -> f64 {
        self.guard_residual = None;
        let s0 = dot(&self.du, &self.r_free);
        let mut alpha = 1.0;
        let lo = (0.0, s0);
        let mut admissible = false;
        for _ in 0..16 {
            for ((t, u), d) in self.trial.iter_mut().zip(&state.u_free).zip(&self.du) {
                *t = u + alpha * d;
            }
            let trial = std::mem::take(&mut self.trial);
            self.model.expand(&trial, level, u_full);
            self.guard_residual = None;
            let assembled = self.assemble(&trial, u_full, level, false);
            self.trial = trial;
            let Ok(info) = assembled else {
                // det F guard: shorten the step until every element is admissible
                if admissible {
                    return lo.0;
                }
                alpha *= 0.5;
                continue;
            };
            admissible = true;
            let s = dot(&self.du, &self.r_free);
            if !self.settings.line_search || s0 >= 0.0 || s <= 0.0 || s.abs() <= 0.5 * s0.abs() {
                // the residual at the state the step moves to is in `r_full` / `r_free`
                self.guard_residual = Some(info.external_norm);
                return alpha;
            }
            // overshoot: minimum between lo.0 and alpha
            let hi = (alpha, s);
            let a = lo.0 + (hi.0 - lo.0) * (-lo.1) / (hi.1 - lo.1);
            alpha = a.clamp(lo.0 + 0.1 * (hi.0 - lo.0), lo.0 + 0.9 * (hi.0 - lo.0));
            if alpha < 1e-3 {
                return alpha;
            }
        }
        if admissible {
            alpha
        } else {
            0.0
        }
    }
}

fn level_is_zero_increment(state: &PathState, level: &LoadLevel) -> bool {
    level_distance(&state.level, level) == 0.0
}

fn level_distance(a: &LoadLevel, b: &LoadLevel) -> f64 {
    (a.pressure - b.pressure).abs() * 10.0
        + (a.gravity - b.gravity).abs()
        + (a.traction - b.traction).abs()
        + (a.prescribed - b.prescribed).abs()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves a model along a sequence of output levels starting from the undeformed state,
/// calling `observe` after every converged output step.
///
/// # Errors
/// [`SolverError::NotConverged`] carrying the reports of the steps that converged.
pub fn solve_path(
    model: &FeModel,
    settings: SolverSettings,
    levels: &[LoadLevel],
    observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    let mut state = PathState::new(model);
    solve_path_from(model, settings, &mut state, levels, observe)
}

/// As [`solve_path`], continuing from a converged `state` (e.g. after a change of the
/// model's obstacles between two phases of a load path).
///
/// # Errors
/// [`SolverError::NotConverged`] carrying the reports of the steps that converged.
pub fn solve_path_from(
    model: &FeModel,
    settings: SolverSettings,
    state: &mut PathState,
    levels: &[LoadLevel],
    mut observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    let augmented = settings.augmented_updates > 0;
    let mut solver = Solver::new(model, settings)?;
    let mut reports = Vec::with_capacity(levels.len());
    for (i, level) in levels.iter().enumerate() {
        let step = solver.advance(state, *level).and_then(|mut rep| {
            if augmented {
                solver.augment(state, *level, &mut rep)?;
            }
            Ok(rep)
        });
        match step {
            Ok(rep) => {
                observe(i, state, &rep);
                reports.push(rep);
            }
            Err(SolverError::NotConverged {
                target,
                reached,
                cutbacks,
                residual,
                ..
            }) => {
                return Err(SolverError::NotConverged {
                    target,
                    reached,
                    cutbacks,
                    residual,
                    completed: reports.len(),
                    reports,
                })
            }
            Err(e) => return Err(e),
        }
    }
    Ok(reports)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::assembly::Constraint;
    use crate::fe::material::Material;
    use crate::fe::mesh::{GridMesh, TensorGrid};

    /// A 4×4×4 block of Q2 hexes clamped at z = 0, loaded by gravity and pressure-free:
    /// both orderings must give the same Newton step.
    #[test]
    fn orderings_give_the_same_solution() {
        let line = || (0..=4).map(f64::from).collect::<Vec<_>>();
        let mesh = GridMesh::new(
            TensorGrid {
                lines: [line(), line(), line()],
            },
            |_| true,
            |s| s,
        )
        .mesh;
        let constraints: Vec<_> = (0..mesh.n_nodes())
            .filter(|&n| mesh.nodes[n][2] == 0.0)
            .flat_map(|node| {
                (0..3).map(move |comp| Constraint {
                    node,
                    comp,
                    value: 0.0,
                })
            })
            .collect();
        let material = Material::from_spec("ogden_002", 1000.0).expect("literature set");
        let mut fe = FeModel::new(mesh, material, &constraints, &[], &[]).expect("model");
        fe.set_body_force([0.1, -0.2, 0.3]);
        let u = vec![0.0; 3 * fe.mesh.n_nodes()];
        let level = LoadLevel {
            gravity: 1.0,
            ..Default::default()
        };
        let mut r_full = vec![0.0; u.len()];
        let mut k = vec![0.0; fe.pattern.nnz()];
        fe.assemble(&u, &level, &mut r_full, Some(&mut k))
            .expect("assembly");
        let mut r = vec![0.0; fe.dofs.n_free];
        fe.restrict(&r_full, &mut r);
        let mut x = Vec::new();
        let mut sizes = Vec::new();
        for o in [Ordering::MinimumDegree, Ordering::NestedDissection] {
            let mut ls = LinearSolver::with_ordering(&fe, Some(o)).expect("symbolic");
            assert_eq!(ls.ordering, o);
            sizes.push(ls.nnz_l());
            let mut b = r.clone();
            ls.solve(&k, &mut b).expect("solve");
            x.push(b);
        }
        let scale = norm(&x[0]);
        assert!(scale > 0.0);
        let diff: Vec<f64> = x[0].iter().zip(&x[1]).map(|(a, b)| a - b).collect();
        assert!(norm(&diff) <= 1e-10 * scale, "{} vs {scale}", norm(&diff));
        // the automatic choice keeps the smaller factor
        let auto = LinearSolver::new(&fe).expect("symbolic");
        assert_eq!(auto.nnz_l(), sizes[0].min(sizes[1]));
    }
}
