//! The sparse direct solver: supernodal LDLᵀ (faer) with its symbolic analysis done once per
//! model, on the better of two fill-reducing orderings; and supernodal LLᵀ on the same
//! analysis for the minimisation solver, whose tangents are meant to be positive definite
//! ([`LinearSolver::solve_llt`] says when one is not).
//!
//! The fill-reducing ordering is the one of AMD and METIS nested dissection
//! ([`crate::fe::ordering`]) that gives the smaller factor: nested dissection on the standard
//! mesh, AMD on the coarse one (measurements in `docs/SOLVER_MEASUREMENTS.md`).
//!
//! The numeric factorisation and the triangular solves run on one thread
//! ([`factor_parallelism`]) while the assembly uses all of rayon's: on the 2-core machine the
//! standard-mesh LDLᵀ takes 0.99 s sequentially and 1.37 s with faer's rayon parallelism
//! (`RAYON_NUM_THREADS=1|2 cargo bench --bench fe -- "standard actuator"`, nested dissection),
//! and a factor computed on one thread does not depend on the thread count.

use faer::dyn_stack::StackReq;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Par, Side};

use super::problem::NonlinearProblem;
use super::settings::SolverError;

/// Fill-reducing ordering of a [`LinearSolver`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ordering {
    /// faer's approximate minimum degree.
    MinimumDegree,
    /// METIS nested dissection on the node graph ([`crate::fe::ordering`]).
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
    /// Whether that factor is an LLᵀ ([`Self::solve_llt`]) rather than an LDLᵀ.
    factored_llt: bool,
    /// Parallelism of the numeric factorisation and the solves ([`factor_parallelism`]).
    par: Par,
}

/// Environment variable that sets the threads of the numeric factorisation (module docs);
/// unset, 0 or 1: one thread.
pub const FACTOR_THREADS_ENV: &str = "SURROGATE_FACTOR_THREADS";

/// The parallelism of the sparse factorisation: sequential unless
/// [`FACTOR_THREADS_ENV`] asks for more threads (for machines where faer's parallel
/// supernodal kernels pay; on the 2-core reference machine they cost 38 % more time).
pub fn factor_parallelism() -> Par {
    match std::env::var(FACTOR_THREADS_ENV)
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
    {
        Some(n) if n > 1 => Par::rayon(n),
        _ => Par::Seq,
    }
}

impl LinearSolver {
    /// Symbolic analysis (fill-reducing ordering, elimination tree) of the model's pattern.
    /// Both orderings are analysed, minimum degree and nested dissection, and the one with
    /// the smaller factor is kept (the choice depends only on the pattern).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if faer rejects the pattern.
    pub fn new(model: &impl NonlinearProblem) -> Result<Self, SolverError> {
        Self::with_ordering(model, None)
    }

    /// As [`Self::new`] with the given ordering (`None`: the one with the smaller factor).
    ///
    /// # Errors
    /// [`SolverError::Factorization`] if faer rejects the pattern, or METIS fails when nested
    /// dissection is asked for.
    pub fn with_ordering(
        model: &impl NonlinearProblem,
        choice: Option<Ordering>,
    ) -> Result<Self, SolverError> {
        let n = model.n_free();
        let col_ptr = model.pattern().col_ptr.clone();
        let row_idx = model.pattern().row_idx.clone();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let fail = |e| SolverError::Factorization(format!("{e:?}"));
        let amd = || {
            factorize_symbolic_cholesky(sym, Side::Lower, Default::default(), Default::default())
                .map_err(fail)
        };
        let nd = || -> Result<_, SolverError> {
            let Some(perm) = model.nested_dissection() else {
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
        let par = factor_parallelism();
        let factor_buf = MemBuffer::new(StackReq::or(
            symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        ));
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
            factored_llt: false,
            par,
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
        let par = self.par;
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
        self.factored_llt = false;
        self.solve_factored(b)
    }

    /// Solves `K x = b` in place with a Cholesky factorisation `K = LLᵀ` (K given by its lower
    /// triangle); returns `Ok(false)`, leaving `b` unchanged, if K is not numerically positive
    /// definite (a pivot ≤ 0), so that the caller can fall back to a modified matrix.
    ///
    /// # Errors
    /// [`SolverError::Factorization`] on a non-finite result.
    pub fn solve_llt(&mut self, values: &[f64], b: &mut [f64]) -> Result<bool, SolverError> {
        let sym = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let mat = SparseColMatRef::new(sym, values);
        let par = self.par;
        self.factorizations += 1;
        self.factored = false;
        match self.symbolic.factorize_numeric_llt(
            &mut self.l_values,
            mat,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut self.factor_buf),
            Default::default(),
        ) {
            Ok(_) => {}
            Err(LltError::NonPositivePivot { .. }) => return Ok(false),
        }
        self.factored = true;
        self.factored_llt = true;
        self.solve_factored(b)?;
        Ok(true)
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
        let par = self.par;
        for (i, v) in b.iter().enumerate() {
            self.rhs[(i, 0)] = *v;
        }
        let stack = MemStack::new(&mut self.solve_buf);
        if self.factored_llt {
            LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
                Conj::No,
                self.rhs.as_mut(),
                par,
                stack,
            );
        } else {
            LdltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
                Conj::No,
                self.rhs.as_mut(),
                par,
                stack,
            );
        }
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
