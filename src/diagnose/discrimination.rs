//! How well a set of measurements would tell two candidate effects apart: the T-optimality
//! criterion of model discrimination (Atkinson and Fedorov, Biometrika 62, 1975, 57–70 for
//! two models, 289–303 for several), for linear models that share the material as nuisance
//! parameters.
//!
//! Every number is in its own σ (and, for the recorded cells, whitened as the Name stage
//! whitens them, [`super::name`]). The recorded cells give the residual `z` (n), the material's
//! columns `M` (n × 4) and each candidate's signature `a` (n); an added measurement `x` gives
//! its rows `m_x` (4) and `a_x`, its derivatives over its own σ. Candidate `a` is first fitted
//! jointly with the material on the recorded cells,
//!
//! ```text
//!   θ̂_a = ã ᵀ z̃ / ã ᵀ ã,      ã = P⊥_M a,  z̃ = P⊥_M z
//! ```
//!
//! (only `|θ̂_a|` matters below). If `a` is the truth at that size, the material plus candidate
//! `b` fit the expected recordings of a design `ξ` (the recorded cells and the added
//! measurements) no better than
//!
//! ```text
//!   T_ab(ξ) = min over β, θ_b of ‖ θ̂_a a − M β − b θ_b ‖²_ξ  =  θ̂_a² ‖ P⊥_[M b] a ‖²_ξ
//! ```
//!
//! the expected increase of `χ²` of the wrong model: the non-centrality of the F test that
//! rejects `b`, and twice the Kullback–Leibler divergence from the truth to the best fit of
//! `b` (Gaussian noise of unit variance), so `T_ab / 2` is the expected log Bayes factor
//! (log-likelihood ratio) in favour of `a`. Which of the two is the truth is not known, so a
//! pair is scored by the symmetric
//!
//! ```text
//!   δ_ab(ξ) = min(T_ab(ξ), T_ba(ξ)),      separation in σ: √δ_ab
//! ```
//!
//! and a tie set (the first candidate `ℓ` and the rivals the recordings cannot separate from
//! it) by the separations `δ_ℓj` of every rival `j`, compared leximin (the smallest first,
//! then the next: Atkinson and Fedorov's maximin for several models, with its ties broken).
//! `k` measurements are chosen greedily: each step adds the candidate measurement that
//! raises the sorted separations most. Adding rows never lowers a `T` (the minimum over more
//! rows is at least that over fewer), so `k` greedy measurements are never worse than the
//! best single one.
//!
//! `T` is invariant to rescaling a signature: `c·a` has the size `θ̂_a / c`, and `P⊥_[M b]` does
//! not depend on the scale of `b`. The Hunter–Reiner criterion `(θ̂_a a_x − θ̂_b b_x)²` is the
//! single-measurement case without the refit of the rival; the refit matters here because the
//! material absorbs much of every signature.
//!
//! Computation: on the recorded cells `[M b] = U S Vᵀ` (thin SVD, directions below 10⁻¹⁰ of
//! the largest dropped); in the coordinates `c = S Vᵀ β` the recorded rows are orthonormal and
//! an added row is `h_x = V S⁻¹ [m_x, b_x]`, so that with `v = θ̂_a a`
//!
//! ```text
//!   T_ab = vᵀv + Σ v_x² − wᵀ (I + Σ h_x h_xᵀ)⁻¹ w,      w = Uᵀv + Σ h_x v_x
//! ```
//!
//! a small positive-definite solve per design.
//!
//! Where the model misses the recordings by more than their σ, the Name stage tests against
//! the scatter left by the fit ([`Discrimination::scale`], `ŝ²`); the separations reported
//! are then `δ / ŝ²`, in the units of that test.

use nalgebra::{DMatrix, DVector};

use super::DiagnoseError;

/// An added measurement's rows: its derivatives by the material (the nuisance parameters)
/// and by every candidate, each over the measurement's σ.
#[derive(Clone, Debug, PartialEq)]
pub struct ItemRow {
    /// `∂y/∂θ_m / σ`, one per nuisance parameter.
    pub nuisance: Vec<f64>,
    /// `∂y/∂θ_j / σ`, one per candidate.
    pub candidates: Vec<f64>,
}

/// The recorded cells and the measurements that could be added, for the candidates' pairs.
#[derive(Clone, Debug)]
pub struct Discrimination {
    residual: DVector<f64>,
    nuisance: DMatrix<f64>,
    signatures: Vec<DVector<f64>>,
    sizes: Vec<f64>,
    items: Vec<ItemRow>,
}

/// One direction of a pair (`truth` true at its fitted size, `rival` refitted), reduced to
/// the coordinates of the module docs.
struct Direction {
    /// `V S⁻¹` (columns of the nuisance and the rival → reduced coordinates).
    to_reduced: DMatrix<f64>,
    /// `Uᵀ v` over the recorded cells.
    w0: DVector<f64>,
    /// `vᵀ v` over the recorded cells.
    vv0: f64,
    truth: usize,
    rival: usize,
}

/// One step of [`Discrimination::greedy`].
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    /// Index of the measurement added.
    pub item: usize,
    /// `δ_ℓj` of every rival after adding it (and the picks before it), in the rivals' order.
    pub separations: Vec<f64>,
}

impl Discrimination {
    /// The problem of `residual` (n), the nuisance columns (n × q) and the candidates'
    /// signatures (n each) on the recorded cells, with the rows of the measurements that
    /// could be added; each candidate's size is fitted jointly with the nuisance.
    ///
    /// # Errors
    /// [`DiagnoseError::Input`] for lengths that do not match.
    pub fn new(
        residual: &DVector<f64>,
        nuisance: DMatrix<f64>,
        signatures: Vec<DVector<f64>>,
        items: Vec<ItemRow>,
    ) -> Result<Self, DiagnoseError> {
        let n = residual.len();
        if nuisance.nrows() != n || signatures.iter().any(|s| s.len() != n) {
            return Err(DiagnoseError::input(
                "discrimination rows",
                format!(
                    "{} nuisance rows, signatures of {:?}",
                    nuisance.nrows(),
                    signatures.iter().map(|s| s.len()).collect::<Vec<_>>()
                ),
                &format!("one row per recorded cell ({n})"),
            ));
        }
        if let Some(i) = items.iter().find(|i| {
            i.nuisance.len() != nuisance.ncols() || i.candidates.len() != signatures.len()
        }) {
            return Err(DiagnoseError::input(
                "measurement row",
                format!("{} + {} values", i.nuisance.len(), i.candidates.len()),
                &format!(
                    "{} nuisance and {} candidate derivatives",
                    nuisance.ncols(),
                    signatures.len()
                ),
            ));
        }
        let q = orthonormal(&nuisance);
        let perp = |v: &DVector<f64>| v - &q * (q.transpose() * v);
        let r = perp(residual);
        let sizes = signatures
            .iter()
            .map(|s| {
                let st = perp(s);
                let ss = st.norm_squared();
                if ss > 0.0 {
                    st.dot(&r) / ss
                } else {
                    0.0
                }
            })
            .collect();
        Ok(Discrimination {
            residual: residual.clone(),
            nuisance,
            signatures,
            sizes,
            items,
        })
    }

    /// The variance factor of the fit of candidate `j` with the nuisance on the recorded
    /// cells, `ŝ² = ‖P⊥_[M a] z‖² / (n − rank − 1)`, floored at 1: the scale the Name stage
    /// tests against (a model that misses the recordings by several σ is judged against its
    /// own scatter, never against less than the recordings' σ). `T / ŝ²` is then the expected
    /// non-centrality of that test.
    pub fn scale(&self, j: usize) -> f64 {
        let mut g = self
            .nuisance
            .clone()
            .insert_column(self.nuisance.ncols(), 0.0);
        let last = g.ncols() - 1;
        g.set_column(last, &self.signatures[j]);
        let q = orthonormal(&g);
        let r = &self.residual - &q * (q.transpose() * &self.residual);
        let dof = self.residual.len() as f64 - q.ncols() as f64 - 1.0;
        if dof < 1.0 {
            return 1.0;
        }
        (r.norm_squared() / dof).max(1.0)
    }

    /// Number of measurements that could be added.
    pub fn items(&self) -> usize {
        self.items.len()
    }

    /// Candidate `j`'s size fitted with the nuisance on the recorded cells.
    pub fn size(&self, j: usize) -> f64 {
        self.sizes[j]
    }

    fn direction(&self, truth: usize, rival: usize) -> Direction {
        let mut g = self
            .nuisance
            .clone()
            .insert_column(self.nuisance.ncols(), 0.0);
        let last = g.ncols() - 1;
        g.set_column(last, &self.signatures[rival]);
        let svd = thin_svd(&g);
        let keep = svd.kept();
        let u = if keep.is_empty() {
            DMatrix::zeros(g.nrows(), 0)
        } else {
            DMatrix::from_columns(&keep.iter().map(|&i| svd.u.column(i)).collect::<Vec<_>>())
        };
        let to_reduced = DMatrix::from_fn(svd.v.nrows(), keep.len(), |r, c| {
            svd.v[(r, keep[c])] / svd.s[keep[c]]
        });
        let v = &self.signatures[truth] * self.sizes[truth];
        Direction {
            to_reduced,
            w0: u.transpose() * &v,
            vv0: v.norm_squared(),
            truth,
            rival,
        }
    }

    /// `(h_x, v_x)` of measurement `i` in a direction's coordinates.
    fn reduced_row(&self, d: &Direction, i: usize) -> (DVector<f64>, f64) {
        let it = &self.items[i];
        let g = DVector::from_iterator(
            it.nuisance.len() + 1,
            it.nuisance.iter().copied().chain([it.candidates[d.rival]]),
        );
        (
            d.to_reduced.transpose() * g,
            self.sizes[d.truth] * it.candidates[d.truth],
        )
    }

    fn lack_of_fit_in(&self, d: &Direction, chosen: &[usize]) -> f64 {
        let k = d.w0.len();
        let mut a = DMatrix::identity(k, k);
        let mut w = d.w0.clone();
        let mut vv = d.vv0;
        for &i in chosen {
            let (h, v) = self.reduced_row(d, i);
            a += &h * h.transpose();
            w += &h * v;
            vv += v * v;
        }
        let explained = a.cholesky().map_or(0.0, |c| w.dot(&c.solve(&w)));
        (vv - explained).max(0.0)
    }

    /// `T_ab` of the recorded cells plus the measurements `chosen` (module docs).
    pub fn lack_of_fit(&self, truth: usize, rival: usize, chosen: &[usize]) -> f64 {
        self.lack_of_fit_in(&self.direction(truth, rival), chosen)
    }

    /// `δ_ab = min(T_ab, T_ba)` of the recorded cells plus the measurements `chosen`.
    pub fn separation(&self, a: usize, b: usize, chosen: &[usize]) -> f64 {
        self.lack_of_fit(a, b, chosen)
            .min(self.lack_of_fit(b, a, chosen))
    }

    /// The single measurement that separates `a` from `b` most, with `δ_ab` once it is added
    /// (none without measurements, or when none raises `δ_ab`).
    pub fn best_single(&self, a: usize, b: usize) -> Option<(usize, f64)> {
        let (ab, ba) = (self.direction(a, b), self.direction(b, a));
        let before = self
            .lack_of_fit_in(&ab, &[])
            .min(self.lack_of_fit_in(&ba, &[]));
        (0..self.items.len())
            .map(|i| {
                let d = self
                    .lack_of_fit_in(&ab, &[i])
                    .min(self.lack_of_fit_in(&ba, &[i]));
                (i, d)
            })
            .filter(|(_, d)| *d > before * (1.0 + 1e-9) + 1e-12)
            .max_by(|x, y| x.1.total_cmp(&y.1))
    }

    /// Up to `k` measurements chosen greedily to separate `leader` from every one of
    /// `rivals` (leximin over `δ_ℓj`, module docs); stops early when no measurement raises the
    /// separations.
    pub fn greedy(&self, leader: usize, rivals: &[usize], k: usize) -> Vec<Pick> {
        let each: Vec<usize> = (0..self.items.len()).collect();
        self.greedy_records(leader, rivals, k, &each)
    }

    /// [`Self::greedy`] where measurements come in records: `record[i]` names the record of
    /// measurement `i` (a marker's two components, a pose's tip and angle), and choosing one
    /// measurement adds every row of its record. Each pick names the record's first
    /// measurement.
    ///
    /// # Panics
    /// `record` shorter than the measurements.
    pub fn greedy_records(
        &self,
        leader: usize,
        rivals: &[usize],
        k: usize,
        record: &[usize],
    ) -> Vec<Pick> {
        assert!(
            record.len() >= self.items.len(),
            "one record per measurement"
        );
        let dirs: Vec<(Direction, Direction)> = rivals
            .iter()
            .map(|&j| (self.direction(leader, j), self.direction(j, leader)))
            .collect();
        let score = |chosen: &[usize]| -> Vec<f64> {
            dirs.iter()
                .map(|(ab, ba)| {
                    self.lack_of_fit_in(ab, chosen)
                        .min(self.lack_of_fit_in(ba, chosen))
                })
                .collect()
        };
        let mut chosen: Vec<usize> = Vec::new();
        let mut picks = Vec::new();
        let mut current = score(&chosen);
        for _ in 0..k {
            let mut best: Option<(usize, Vec<f64>)> = None;
            let rows_of = |i: usize| (0..self.items.len()).filter(move |&j| record[j] == record[i]);
            let first_of_record = |i: &usize| rows_of(*i).next() == Some(*i);
            for i in (0..self.items.len())
                .filter(|i| !chosen.contains(i))
                .filter(first_of_record)
            {
                let mut trial = chosen.clone();
                trial.extend(rows_of(i));
                let s = score(&trial);
                if best.as_ref().is_none_or(|(_, b)| leximin_greater(&s, b)) {
                    best = Some((i, s));
                }
            }
            let Some((i, s)) = best.filter(|(_, s)| leximin_greater(s, &current)) else {
                break;
            };
            chosen.extend(rows_of(i));
            current = s.clone();
            picks.push(Pick {
                item: i,
                separations: s,
            });
        }
        picks
    }
}

/// Whether `a` beats `b` leximin: sorted ascending, the first entry that differs (beyond a
/// relative 10⁻⁹) is larger in `a`.
pub fn leximin_greater(a: &[f64], b: &[f64]) -> bool {
    let sorted = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v
    };
    let (a, b) = (sorted(a), sorted(b));
    for (x, y) in a.iter().zip(&b) {
        let tol = 1e-9 * x.abs().max(y.abs()) + 1e-12;
        if (x - y).abs() > tol {
            return x > y;
        }
    }
    false
}

/// Orthonormal basis of the column span of `a` (thin SVD, directions below 10⁻¹⁰ of the
/// largest singular value dropped; no column for a matrix of zeros).
pub(crate) fn orthonormal(a: &DMatrix<f64>) -> DMatrix<f64> {
    if a.ncols() == 0 {
        return DMatrix::zeros(a.nrows(), 0);
    }
    let svd = thin_svd(a);
    let keep: Vec<DVector<f64>> = svd
        .kept()
        .into_iter()
        .map(|i| svd.u.column(i).into_owned())
        .collect();
    if keep.is_empty() {
        return DMatrix::zeros(a.nrows(), 0);
    }
    DMatrix::from_columns(&keep)
}

/// A thin SVD `A = U Σ Vᵀ` (`U`: `m × k`, `V`: `n × k`, `k = min(m, n)`; singular values
/// non-increasing).
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub struct ThinSvd {
    u: DMatrix<f64>,
    s: Vec<f64>,
    v: DMatrix<f64>,
}

impl ThinSvd {
    /// `U` (`m × k`).
    // public for the tests in tests/diagnose/
    #[doc(hidden)]
    pub fn u(&self) -> &DMatrix<f64> {
        &self.u
    }

    /// The singular values, non-increasing.
    // public for the tests in tests/diagnose/
    #[doc(hidden)]
    pub fn s(&self) -> &[f64] {
        &self.s
    }

    /// `V` (`n × k`).
    // public for the tests in tests/diagnose/
    #[doc(hidden)]
    pub fn v(&self) -> &DMatrix<f64> {
        &self.v
    }

    /// Indices of the singular values above 10⁻¹⁰ of the largest; every index when they are
    /// NaN (a matrix with non-finite entries), so that the NaN reaches the caller's result.
    fn kept(&self) -> Vec<usize> {
        let smax = self.s.first().copied().unwrap_or(0.0);
        (0..self.s.len())
            .filter(|&i| self.s[i] > 1e-10 * smax || smax.is_nan())
            .collect()
    }
}

/// The thin SVD of `a` ([`crate::rom::svd::thin_svd`]: computed sequentially, so that the
/// result does not depend on the number of threads). A matrix with non-finite entries, on which
/// the iteration does not converge, gives NaN factors.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn thin_svd(a: &DMatrix<f64>) -> ThinSvd {
    let (m, n) = (a.nrows(), a.ncols());
    let k = m.min(n);
    let mat = faer::Mat::<f64>::from_fn(m, n, |i, j| a[(i, j)]);
    let Ok(svd) = crate::rom::svd::thin_svd(mat.as_ref()) else {
        return ThinSvd {
            u: DMatrix::from_element(m, k, f64::NAN),
            s: vec![f64::NAN; k],
            v: DMatrix::from_element(n, k, f64::NAN),
        };
    };
    ThinSvd {
        u: DMatrix::from_fn(m, k, |i, j| svd.u[(i, j)]),
        s: svd.s,
        v: DMatrix::from_fn(n, k, |i, j| svd.v[(i, j)]),
    }
}
