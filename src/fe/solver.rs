//! Load stepping with adaptive cut-back, Newton–Raphson with line search, and the sparse
//! direct solver (faer) whose symbolic analysis is done once per mesh.
//!
//! Each load step solves `r(u; λ) = 0` on the free equations. Newton: `K Δu = −r`, then a line
//! search on the directional residual `s(α) = Δu · r(u + α Δu)` (Crisfield / Matthies–Strang),
//! which, the problem being conservative, minimises the total potential along `Δu`. A trial
//! state with an inverted element (det F ≤ 0) halves `α`. A step that does not converge is
//! cut back (halved) and retried from the last converged state.

use faer::prelude::*;
use faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Mat, Side};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::assembly::{FeModel, LoadLevel};
use super::element::ElementError;

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
    /// Largest pressure increment in one substep (MPa).
    pub max_pressure_increment: f64,
    /// Line-search on/off.
    pub line_search: bool,
    /// Print every Newton iteration to stderr.
    #[serde(default)]
    pub trace: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            max_iterations: 25,
            max_cutbacks: 10,
            initial_fraction: 1.0,
            max_pressure_increment: 0.05,
            line_search: true,
            trace: false,
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

/// Sparse direct solver with a reusable symbolic analysis.
pub struct LinearSolver {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    llt: SymbolicLlt<usize>,
    lu: Option<FullPattern>,
    /// Number of factorisations that needed the LU fallback.
    pub lu_fallbacks: usize,
}

/// Full (both triangles) pattern for the LU fallback, with the source of each value.
struct FullPattern {
    symbolic: SymbolicSparseColMat<usize>,
    lu: SymbolicLu<usize>,
    source: Vec<usize>,
    values: Vec<f64>,
}

impl LinearSolver {
    /// Symbolic analysis of the model's pattern.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if faer rejects the pattern.
    pub fn new(model: &FeModel) -> Result<Self, SolverError> {
        let n = model.dofs.n_free;
        let col_ptr = model.pattern.col_ptr.clone();
        let row_idx = model.pattern.row_idx.clone();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let llt = SymbolicLlt::try_new(sym, Side::Lower)
            .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
        Ok(Self {
            n,
            col_ptr,
            row_idx,
            llt,
            lu: None,
            lu_fallbacks: 0,
        })
    }

    /// Solves `K x = b` in place (K given by its lower triangle). Falls back to LU on the
    /// full symmetric matrix when K is not positive definite.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if both factorisations fail.
    pub fn solve(&mut self, values: &[f64], b: &mut [f64]) -> Result<(), SolverError> {
        let sym = SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx);
        let mat = SparseColMatRef::new(sym, values);
        let mut rhs = Mat::<f64>::from_fn(self.n, 1, |i, _| b[i]);
        match Llt::try_new_with_symbolic(self.llt.clone(), mat, Side::Lower) {
            Ok(f) => f.solve_in_place(rhs.as_mut()),
            Err(_) => {
                self.lu_fallbacks += 1;
                self.solve_lu(values, rhs.as_mut())?
            }
        }
        for (i, v) in b.iter_mut().enumerate() {
            *v = rhs[(i, 0)];
        }
        Ok(())
    }

    fn full_pattern(&self) -> Result<FullPattern, SolverError> {
        let mut trip = Vec::with_capacity(2 * self.row_idx.len());
        for c in 0..self.n {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[p];
                trip.push((c, r, p));
                if r != c {
                    trip.push((r, c, p));
                }
            }
        }
        trip.sort_unstable();
        let mut cp = vec![0usize; self.n + 1];
        let mut ri = Vec::with_capacity(trip.len());
        let mut source = Vec::with_capacity(trip.len());
        for &(c, r, p) in &trip {
            cp[c + 1] += 1;
            ri.push(r);
            source.push(p);
        }
        for c in 0..self.n {
            cp[c + 1] += cp[c];
        }
        let symbolic = SymbolicSparseColMat::new_checked(self.n, self.n, cp, None, ri);
        let lu = SymbolicLu::try_new(symbolic.as_ref())
            .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
        let values = vec![0.0; source.len()];
        Ok(FullPattern {
            symbolic,
            lu,
            source,
            values,
        })
    }

    fn solve_lu(&mut self, values: &[f64], rhs: faer::MatMut<'_, f64>) -> Result<(), SolverError> {
        if self.lu.is_none() {
            self.lu = Some(self.full_pattern()?);
        }
        let Some(full) = self.lu.as_mut() else {
            return Err(SolverError::Factorization("LU pattern unavailable".into()));
        };
        for (v, &p) in full.values.iter_mut().zip(&full.source) {
            *v = values[p];
        }
        let mat = SparseColMatRef::new(full.symbolic.as_ref(), &full.values);
        let lu = Lu::try_new_with_symbolic(full.lu.clone(), mat)
            .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
        lu.solve_in_place(rhs);
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
    prev_u_free: Option<(Vec<f64>, LoadLevel)>,
}

impl PathState {
    /// The undeformed state at zero load.
    pub fn new(model: &FeModel) -> Self {
        Self {
            u_free: vec![0.0; model.dofs.n_free],
            u_full: vec![0.0; 3 * model.mesh.n_nodes()],
            level: LoadLevel::default(),
            prev_u_free: None,
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
    r_free: Vec<f64>,
    k: Vec<f64>,
    du: Vec<f64>,
    trial: Vec<f64>,
    factor_seconds: f64,
    assembly_seconds: f64,
    /// Floor of the force scale: 1e-3 · μ0 · V^(2/3) (a characteristic internal force).
    force_scale: f64,
}

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
            r_free: vec![0.0; n],
            k: vec![0.0; model.pattern.nnz()],
            du: vec![0.0; n],
            trial: vec![0.0; n],
            factor_seconds: 0.0,
            assembly_seconds: 0.0,
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
    pub fn advance(&mut self, state: &mut PathState, target: LoadLevel) -> Result<StepReport, SolverError> {
        let start = state.level;
        let dp = (target.pressure - start.pressure).abs();
        let mut frac = self.settings.initial_fraction.min(1.0);
        if dp > 0.0 {
            frac = frac.min(self.settings.max_pressure_increment / dp);
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
        };
        let (f0, a0) = (self.factor_seconds, self.assembly_seconds);
        let mut consecutive_cuts = 0;
        while s < 1.0 - 1e-12 {
            let s_next = (s + frac).min(1.0);
            let level = start.lerp(&target, s_next);
            let saved = state.u_free.clone();
            self.predict(state, &level);
            let out = self.newton(state, &level)?;
            report.newton_iterations += out.iterations;
            report.residual = out.residual;
            report.update = out.update;
            if out.converged {
                state.prev_u_free = Some((saved, state.level));
                state.level = level;
                s = s_next;
                report.substeps += 1;
                consecutive_cuts = 0;
                if out.iterations <= 5 {
                    frac *= 1.5;
                }
                if dp > 0.0 {
                    frac = frac.min(self.settings.max_pressure_increment / dp);
                }
            } else {
                state.u_free = saved;
                report.cutbacks += 1;
                consecutive_cuts += 1;
                frac *= 0.5;
                if consecutive_cuts > self.settings.max_cutbacks {
                    self.model.expand(&state.u_free, &state.level, &mut state.u_full);
                    return Err(SolverError::NotConverged {
                        target,
                        reached: state.level,
                        cutbacks: report.cutbacks,
                        residual: out.residual,
                        completed: 0,
                        reports: Vec::new(),
                    });
                }
            }
        }
        self.model.expand(&state.u_free, &state.level, &mut state.u_full);
        report.converged = true;
        report.factor_seconds = self.factor_seconds - f0;
        report.assembly_seconds = self.assembly_seconds - a0;
        Ok(report)
    }

    /// Secant predictor from the previous converged increment.
    fn predict(&mut self, state: &mut PathState, level: &LoadLevel) {
        let Some((prev, prev_level)) = &state.prev_u_free else { return };
        let d_now = level_distance(&state.level, level);
        let d_prev = level_distance(prev_level, &state.level);
        if d_prev <= 0.0 {
            return;
        }
        let ratio = (d_now / d_prev).min(2.0);
        for (u, p) in state.u_free.iter_mut().zip(prev) {
            *u += ratio * (*u - p);
        }
        // reject a predictor that inverts an element
        let mut u_full = std::mem::take(&mut state.u_full);
        self.model.expand(&state.u_free, level, &mut u_full);
        if self.model.assemble(&u_full, level, &mut self.r_full, None).is_err() {
            for (u, p) in state.u_free.iter_mut().zip(prev) {
                *u = (*u + ratio * p) / (1.0 + ratio);
            }
        }
        state.u_full = u_full;
    }

    fn assemble(&mut self, u_full: &[f64], level: &LoadLevel, with_k: bool) -> Result<f64, ElementError> {
        let t = std::time::Instant::now();
        let info = self.model.assemble(
            u_full,
            level,
            &mut self.r_full,
            with_k.then_some(&mut self.k[..]),
        )?;
        self.model.restrict(&self.r_full, &mut self.r_free);
        self.assembly_seconds += t.elapsed().as_secs_f64();
        Ok(info.external_norm)
    }

    fn newton(&mut self, state: &mut PathState, level: &LoadLevel) -> Result<NewtonOutcome, SolverError> {
        let mut u_full = std::mem::take(&mut state.u_full);
        let out = self.newton_inner(state, level, &mut u_full);
        state.u_full = u_full;
        out
    }

    fn newton_inner(
        &mut self,
        state: &mut PathState,
        level: &LoadLevel,
        u_full: &mut [f64],
    ) -> Result<NewtonOutcome, SolverError> {
        let mut out = NewtonOutcome {
            converged: false,
            iterations: 0,
            residual: f64::INFINITY,
            update: f64::INFINITY,
        };
        for it in 0..=self.settings.max_iterations {
            self.model.expand(&state.u_free, level, u_full);
            let ext = match self.assemble(u_full, level, true) {
                Ok(e) => e,
                Err(_) => return Ok(out),
            };
            let reactions = self.reaction_norm();
            let scale = ext.max(reactions).max(self.force_scale);
            let rn = norm(&self.r_free);
            out.residual = rn / scale;
            out.iterations = it;
            if self.settings.trace {
                eprintln!(
                    "  newton {it:2}  level p={:.4} g={:.2}  |r|/f = {:.3e}  (|r| = {rn:.3e}, f = {scale:.3e})",
                    level.pressure, level.gravity, out.residual
                );
            }
            if !rn.is_finite() {
                return Ok(out);
            }
            if rn <= self.settings.rtol * scale && (it > 0 || level_is_zero_increment(state, level)) {
                out.converged = true;
                return Ok(out);
            }
            if it == self.settings.max_iterations {
                return Ok(out);
            }
            for (d, r) in self.du.iter_mut().zip(&self.r_free) {
                *d = -r;
            }
            let t = std::time::Instant::now();
            let solved = self.linear.solve(&self.k, &mut self.du);
            self.factor_seconds += t.elapsed().as_secs_f64();
            if solved.is_err() {
                return Ok(out);
            }
            let alpha = self.line_search(state, level, u_full);
            let un = norm(&state.u_free).max(1e-12);
            out.update = alpha * norm(&self.du) / un;
            if alpha == 0.0 {
                return Ok(out);
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
            self.trial = trial;
            if self.assemble(u_full, level, false).is_err() {
                // det F guard: shorten the step until every element is admissible
                if admissible {
                    return lo.0;
                }
                alpha *= 0.5;
                continue;
            }
            admissible = true;
            let s = dot(&self.du, &self.r_free);
            if !self.settings.line_search || s0 >= 0.0 || s <= 0.0 || s.abs() <= 0.5 * s0.abs() {
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
    mut observe: impl FnMut(usize, &PathState, &StepReport),
) -> Result<Vec<StepReport>, SolverError> {
    let mut solver = Solver::new(model, settings)?;
    let mut state = PathState::new(model);
    let mut reports = Vec::with_capacity(levels.len());
    for (i, level) in levels.iter().enumerate() {
        match solver.advance(&mut state, *level) {
            Ok(rep) => {
                observe(i, &state, &rep);
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
