//! The structure of one output's residual over N, T, P (and along the actuator): a weighted
//! least-squares fit of the standardised residual to a small additive model, each term with
//! its standard error and Student-t test (the model and the tests: the [module docs](super)).

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, FisherSnedecor, StudentsT};

use super::cells::{Cell, Family};

/// A term of the structure model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// `β₀`: the residual at the centre of the recorded designs and pressures.
    Constant,
    /// `β_P (P − P̄)`, per bar.
    P,
    /// `β_T (T − T̄)`, per mm.
    T,
    /// `β_N (N − N̄)`, per bellow.
    N,
    /// `β_s (s − s̄)`, `s = k/9` the marker's position along the actuator (markers only),
    /// per free length.
    Position,
    /// `β_PT (P − P̄)(T − T̄)`, per bar·mm.
    PT,
}

impl Term {
    /// Name in tables.
    pub fn label(self) -> &'static str {
        match self {
            Term::Constant => "constant",
            Term::P => "P",
            Term::T => "T",
            Term::N => "N",
            Term::Position => "position along the actuator",
            Term::PT => "P·T",
        }
    }

    /// Unit of the coefficient (σ per …).
    pub fn unit(self) -> &'static str {
        match self {
            Term::Constant => "σ",
            Term::P => "σ/bar",
            Term::T => "σ/mm",
            Term::N => "σ/bellow",
            Term::Position => "σ per free length",
            Term::PT => "σ/(bar·mm)",
        }
    }

    fn raw(self, c: &Cell) -> f64 {
        match self {
            Term::Constant => 1.0,
            Term::P => c.pressure_bar,
            Term::T => c.wall_thickness_mm,
            Term::N => f64::from(c.n_bellows),
            Term::Position => f64::from(c.marker.unwrap_or(9)) / 9.0,
            Term::PT => f64::NAN,
        }
    }
}

/// One term's estimate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TermFit {
    /// The term.
    pub term: Term,
    /// Mean of its variable over the cells (the centre; 0 for the constant and P·T).
    pub centre: f64,
    /// Smallest and largest value of its variable over the cells.
    pub range: [f64; 2],
    /// Coefficient (in σ per unit of the variable).
    pub coefficient: f64,
    /// Its standard error.
    pub std_error: f64,
    /// `coefficient / std_error`.
    pub t: f64,
    /// Two-sided p-value (Student t, `n − p` degrees of freedom).
    pub p_value: f64,
    /// Significant after Holm's correction over every test of the report.
    pub significant: bool,
}

/// A term left out of the fit, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dropped {
    /// The term.
    pub term: Term,
    /// Why.
    pub reason: String,
}

/// The structure of one output's residual.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Structure {
    /// The output.
    pub family: Family,
    /// Cells fitted.
    pub cells: usize,
    /// Residual degrees of freedom `n − p`.
    pub dof: usize,
    /// The terms fitted.
    pub terms: Vec<TermFit>,
    /// The terms left out.
    pub dropped: Vec<Dropped>,
    /// `Σ z²` of the output.
    pub chi2: f64,
    /// What the fitted structure leaves, `Σ (z − ẑ)²`.
    pub rss: f64,
    /// `1 − RSS / Σ z²`: the fraction of the output's χ² the structure explains.
    pub explained: f64,
    /// The same with the significant terms alone (0 when none is).
    pub explained_by_significant: f64,
    /// `ŝ = √(RSS / (n − p))`: the unstructured scatter in σ.
    pub scale: f64,
    /// F statistic of all terms against none.
    pub f: f64,
    /// Its p-value (F with `p` and `n − p` degrees of freedom).
    pub f_p_value: f64,
    /// Median `σ` of the cells (converts σ to the output's unit, roughly).
    pub median_sigma: f64,
}

impl Structure {
    /// The fitted term, if present.
    pub fn term(&self, t: Term) -> Option<&TermFit> {
        self.terms.iter().find(|f| f.term == t)
    }

    /// The structure's value with every variable at its centre except `term`'s, which is at
    /// `x` (only the significant terms when `significant_only`).
    pub fn along(&self, term: Term, x: f64, significant_only: bool) -> f64 {
        let use_term = |f: &&TermFit| !significant_only || f.significant;
        let c0 = self
            .term(Term::Constant)
            .filter(use_term)
            .map_or(0.0, |f| f.coefficient);
        c0 + self
            .term(term)
            .filter(use_term)
            .map_or(0.0, |f| f.coefficient * (x - f.centre))
    }
}

/// The terms tried for a family, in the order they are kept when some must go.
fn candidates(family: Family) -> Vec<Term> {
    let mut v = vec![Term::Constant, Term::P, Term::T, Term::N];
    if matches!(family, Family::MarkerUz | Family::MarkerUy) {
        v.push(Term::Position);
    }
    v.push(Term::PT);
    v
}

fn distinct(v: impl Iterator<Item = f64>) -> usize {
    let mut l: Vec<f64> = v.collect();
    l.sort_by(f64::total_cmp);
    l.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    l.len()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// The design matrix of `terms` over `cells` (centred variables) and each term's centre.
fn design(cells: &[&Cell], terms: &[Term]) -> (DMatrix<f64>, Vec<f64>) {
    let col = |t: Term| -> Vec<f64> { cells.iter().map(|c| t.raw(c)).collect() };
    let centred = |t: Term| -> (Vec<f64>, f64) {
        let v = col(t);
        let m = mean(&v);
        (v.iter().map(|x| x - m).collect(), m)
    };
    let mut x = DMatrix::zeros(cells.len(), terms.len());
    let mut centres = Vec::with_capacity(terms.len());
    for (j, &t) in terms.iter().enumerate() {
        let (v, m) = match t {
            Term::Constant => (vec![1.0; cells.len()], 0.0),
            Term::PT => {
                let (p, _) = centred(Term::P);
                let (tt, _) = centred(Term::T);
                (p.iter().zip(&tt).map(|(a, b)| a * b).collect(), 0.0)
            }
            _ => centred(t),
        };
        for (i, val) in v.into_iter().enumerate() {
            x[(i, j)] = val;
        }
        centres.push(m);
    }
    (x, centres)
}

/// Whether the columns of `x` are linearly independent (scaled smallest eigenvalue of XᵀX).
fn independent(x: &DMatrix<f64>) -> bool {
    let xtx = x.transpose() * x;
    let d: Vec<f64> = (0..xtx.nrows()).map(|i| xtx[(i, i)].sqrt()).collect();
    if d.iter().any(|v| *v < 1e-12) {
        return false;
    }
    let scaled = DMatrix::from_fn(xtx.nrows(), xtx.ncols(), |i, j| xtx[(i, j)] / (d[i] * d[j]));
    let eig = scaled.symmetric_eigenvalues();
    eig.iter().copied().fold(f64::INFINITY, f64::min) > 1e-8
}

/// Fits the structure of one family's cells (p-values unadjusted; `significant` is set by
/// the caller's multiple-comparison step). `None` with fewer than 3 cells.
pub fn fit(family: Family, cells: &[&Cell]) -> Option<Structure> {
    let n = cells.len();
    if n < 3 {
        return None;
    }
    let (terms, dropped) = choose_terms(family, cells);
    if terms.is_empty() {
        return None;
    }
    let z = DVector::from_iterator(n, cells.iter().map(|c| c.standardised));
    let (x, centres) = design(cells, &terms);
    let (beta, inv) = solve(&x, &z)?;
    let rss = (&z - &x * &beta).norm_squared();
    let chi2 = z.norm_squared();
    let p = terms.len();
    let dof = n - p;
    // floored: a structure that leaves nothing keeps finite statistics
    let s2 = (rss / dof as f64).max(1e-200);
    let student = StudentsT::new(0.0, 1.0, dof as f64).ok()?;
    let fits = terms
        .iter()
        .enumerate()
        .map(|(j, &t)| {
            let se = (s2 * inv[(j, j)]).sqrt();
            let tv = beta[j] / se;
            TermFit {
                term: t,
                centre: centres[j],
                range: range(t, cells),
                coefficient: beta[j],
                std_error: se,
                t: tv,
                p_value: 2.0 * (1.0 - student.cdf(tv.abs())),
                significant: false,
            }
        })
        .collect();
    let f = ((chi2 - rss) / p as f64) / s2;
    let f_p_value = FisherSnedecor::new(p as f64, dof as f64)
        .map(|d| if f.is_finite() { 1.0 - d.cdf(f) } else { 0.0 })
        .unwrap_or(f64::NAN);
    let mut sig: Vec<f64> = cells.iter().map(|c| c.sigma).collect();
    sig.sort_by(f64::total_cmp);
    Some(Structure {
        family,
        cells: n,
        dof,
        terms: fits,
        dropped,
        chi2,
        rss,
        explained: explained(chi2, rss),
        explained_by_significant: 0.0,
        scale: s2.sqrt(),
        f,
        f_p_value,
        median_sigma: sig[sig.len() / 2],
    })
}

/// The terms a family's cells can carry, in order of priority: each whose variable has two
/// levels or more, that leaves 2 residual degrees of freedom and keeps the columns
/// independent; and the others with the reason.
fn choose_terms(family: Family, cells: &[&Cell]) -> (Vec<Term>, Vec<Dropped>) {
    let n = cells.len();
    let levels = |t: Term| match t {
        Term::P => distinct(cells.iter().map(|c| c.pressure_bar)),
        Term::T => distinct(cells.iter().map(|c| c.wall_thickness_mm)),
        Term::N => distinct(cells.iter().map(|c| f64::from(c.n_bellows))),
        Term::Position => distinct(cells.iter().map(|c| f64::from(c.marker.unwrap_or(9)))),
        Term::Constant => 2,
        Term::PT => levels_min(cells),
    };
    let mut kept: Vec<Term> = Vec::new();
    let mut dropped = Vec::new();
    for t in candidates(family) {
        let mut trial = kept.clone();
        trial.push(t);
        let reason = if levels(t) < 2 {
            "one level on these recordings".to_string()
        } else if n < trial.len() + 2 {
            format!("too few cells ({n}) for the terms")
        } else if !independent(&design(cells, &trial).0) {
            "confounded with the other terms on these recordings".into()
        } else {
            kept = trial;
            continue;
        };
        dropped.push(Dropped { term: t, reason });
    }
    (kept, dropped)
}

/// The fewer of the numbers of P and T levels (what P·T needs two of).
fn levels_min(cells: &[&Cell]) -> usize {
    distinct(cells.iter().map(|c| c.pressure_bar))
        .min(distinct(cells.iter().map(|c| c.wall_thickness_mm)))
}

/// Smallest and largest value of a term's variable over the cells (0, 0 for the constant
/// and P·T).
fn range(t: Term, cells: &[&Cell]) -> [f64; 2] {
    match t {
        Term::Constant | Term::PT => [0.0, 0.0],
        _ => cells
            .iter()
            .map(|c| t.raw(c))
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
                [lo.min(v), hi.max(v)]
            }),
    }
}

fn explained(chi2: f64, rss: f64) -> f64 {
    if chi2 > 0.0 {
        (1.0 - rss / chi2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Least squares `β = (XᵀX)⁻¹ Xᵀ z` and `(XᵀX)⁻¹`.
fn solve(x: &DMatrix<f64>, z: &DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)> {
    let chol = (x.transpose() * x).cholesky()?;
    let beta = chol.solve(&(x.transpose() * z));
    Some((beta, chol.inverse()))
}

/// Refits with the significant terms alone and stores the fraction of χ² they explain.
pub fn explain_by_significant(s: &mut Structure, cells: &[&Cell]) {
    let terms: Vec<Term> = s
        .terms
        .iter()
        .filter(|f| f.significant)
        .map(|f| f.term)
        .collect();
    if terms.is_empty() {
        s.explained_by_significant = 0.0;
        return;
    }
    let z = DVector::from_iterator(cells.len(), cells.iter().map(|c| c.standardised));
    let (x, _) = design(cells, &terms);
    s.explained_by_significant = match solve(&x, &z) {
        Some((beta, _)) => explained(s.chi2, (&z - &x * &beta).norm_squared()),
        None => 0.0,
    };
}
