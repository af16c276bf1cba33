//! The residual problem of a set of rows (the material through the surrogate, the effects
//! linearised) and its bounded Levenberg–Marquardt fit.

use nalgebra::{DMatrix, DVector};

use super::rows::Rows;
use crate::calibrate::objective::{Evaluator, ObservationSet};
use crate::calibrate::ParamSpace;
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;
use crate::rom::Surrogate;

/// A bounded fit's end point.
#[derive(Clone, Debug)]
pub(crate) struct Fitted {
    /// `[u (4), θ (k)]`.
    pub(crate) x: Vec<f64>,
    pub(crate) chi2: f64,
    pub(crate) iterations: usize,
    pub(crate) stop: &'static str,
    /// `JᵀJ` at the end point.
    pub(crate) jtj: DMatrix<f64>,
    /// Parameters at a bound that pushes outwards.
    pub(crate) active: Vec<bool>,
}

/// The residual problem of a set of rows: material through the surrogate, `k` linear effects.
pub(crate) struct Problem<'a> {
    pub(crate) rows: &'a Rows,
    pub(crate) set: ObservationSet,
    pub(crate) model: &'a Surrogate,
    pub(crate) space: ParamSpace,
    pub(crate) k: usize,
    pub(crate) lo: Vec<f64>,
    pub(crate) hi: Vec<f64>,
}

impl<'a> Problem<'a> {
    pub(crate) fn new(
        rows: &'a Rows,
        model: &'a Surrogate,
        space: ParamSpace,
        effects: &[Effect],
        k: usize,
    ) -> Self {
        let mut lo = vec![0.0; 4];
        let mut hi = vec![1.0; 4];
        // each effect's size from the sweep's value, its value inside its range
        for (e, base) in effects[..k].iter().zip(&rows.base) {
            let i = e.info();
            lo.push(i.range.0 - base);
            hi.push(i.range.1 - base);
        }
        Problem {
            rows,
            set: rows.observations(),
            model,
            space,
            k,
            lo,
            hi,
        }
    }

    /// Residuals `z` (and the Jacobian) at `x`.
    pub(crate) fn eval(
        &self,
        ev: &mut Evaluator<'_>,
        x: &[f64],
        r: &mut [f64],
        jac: Option<&mut DMatrix<f64>>,
    ) -> Result<(), DiagnoseError> {
        let u = [x[0], x[1], x[2], x[3]];
        let n = r.len();
        let mut jm = vec![[0.0; 4]; n];
        ev.residuals(&u, r, jac.is_some().then_some(jm.as_mut_slice()))?;
        for (i, ri) in r.iter_mut().enumerate() {
            let sigma = self.rows.cells[i].sigma;
            let mut lin = self.rows.offset[i];
            for k in 0..self.k {
                lin += x[4 + k] * self.rows.d[i][k];
            }
            *ri += lin / sigma;
        }
        if let Some(j) = jac {
            for i in 0..n {
                for a in 0..4 {
                    j[(i, a)] = jm[i][a];
                }
                for k in 0..self.k {
                    j[(i, 4 + k)] = self.rows.d[i][k] / self.rows.cells[i].sigma;
                }
            }
        }
        Ok(())
    }

    /// Predictions (unit of each output) at `x`.
    pub(crate) fn predictions(&self, x: &[f64]) -> Result<Vec<f64>, DiagnoseError> {
        let mut ev = Evaluator::new(self.model, &self.set, self.space.clone());
        let mut r = vec![0.0; self.rows.cells.len()];
        self.eval(&mut ev, x, &mut r, None)?;
        Ok(r.iter()
            .zip(&self.rows.cells)
            .map(|(z, c)| c.recorded + z * c.sigma)
            .collect())
    }

    /// Bounded Levenberg–Marquardt from `start`.
    pub(crate) fn fit(&self, start: &[f64]) -> Result<Fitted, DiagnoseError> {
        let p = 4 + self.k;
        let n = self.rows.cells.len();
        let mut ev = Evaluator::new(self.model, &self.set, self.space.clone());
        let mut x: Vec<f64> = (0..p)
            .map(|i| start[i].clamp(self.lo[i], self.hi[i]))
            .collect();
        let mut r = vec![0.0; n];
        let mut rt = vec![0.0; n];
        let mut j = DMatrix::zeros(n, p);
        self.eval(&mut ev, &x, &mut r, Some(&mut j))?;
        let mut cost: f64 = r.iter().map(|v| v * v).sum();
        let mut lambda = 1e-3;
        let mut stop = "iteration limit";
        let mut it = 0;
        let mut stalls = 0;
        let pushed = |x: &[f64], g: &DVector<f64>| -> Vec<bool> {
            (0..p)
                .map(|i| {
                    let span = self.hi[i] - self.lo[i];
                    (x[i] <= self.lo[i] + 1e-12 * span && g[i] > 0.0)
                        || (x[i] >= self.hi[i] - 1e-12 * span && g[i] < 0.0)
                })
                .collect()
        };
        while it < 300 {
            it += 1;
            let rv = DVector::from_column_slice(&r);
            let g = j.transpose() * &rv;
            let a = j.transpose() * &j;
            let fixed = pushed(&x, &g);
            let free: Vec<usize> = (0..p).filter(|&i| !fixed[i]).collect();
            let pg = free.iter().map(|&i| g[i].abs()).fold(0.0, f64::max);
            if pg < 1e-10 * (1.0 + cost) {
                stop = "gradient";
                break;
            }
            let mut accepted = false;
            let mut tiny = false;
            while lambda < 1e16 {
                let m = free.len();
                let mut af = DMatrix::zeros(m, m);
                let mut bf = DVector::zeros(m);
                for (a_, &ia) in free.iter().enumerate() {
                    bf[a_] = -g[ia];
                    for (b_, &ib) in free.iter().enumerate() {
                        af[(a_, b_)] = a[(ia, ib)];
                    }
                    af[(a_, a_)] += lambda * a[(ia, ia)].max(1e-12);
                }
                let Some(ch) = af.cholesky() else {
                    lambda *= 4.0;
                    continue;
                };
                let d = ch.solve(&bf);
                let mut trial = x.clone();
                for (a_, &ia) in free.iter().enumerate() {
                    trial[ia] = (x[ia] + d[a_]).clamp(self.lo[ia], self.hi[ia]);
                }
                let step = (0..p)
                    .map(|i| (trial[i] - x[i]).abs() / (self.hi[i] - self.lo[i]))
                    .fold(0.0, f64::max);
                if step < 1e-12 {
                    tiny = true;
                    break;
                }
                self.eval(&mut ev, &trial, &mut rt, None)?;
                let ct: f64 = rt.iter().map(|v| v * v).sum();
                if ct < cost {
                    let rel = (cost - ct) / cost.max(1e-300);
                    stalls = if rel < 1e-12 { stalls + 1 } else { 0 };
                    x = trial;
                    cost = ct;
                    lambda = (lambda / 3.0).max(1e-12);
                    accepted = true;
                    break;
                }
                lambda *= 4.0;
            }
            if tiny {
                stop = "step";
                break;
            }
            if !accepted {
                stop = "no descent";
                break;
            }
            self.eval(&mut ev, &x, &mut r, Some(&mut j))?;
            if stalls >= 2 {
                stop = "cost stalled";
                break;
            }
        }
        self.eval(&mut ev, &x, &mut r, Some(&mut j))?;
        let g = j.transpose() * DVector::from_column_slice(&r);
        Ok(Fitted {
            active: pushed(&x, &g),
            chi2: r.iter().map(|v| v * v).sum(),
            jtj: j.transpose() * &j,
            x,
            iterations: it,
            stop,
        })
    }
}
