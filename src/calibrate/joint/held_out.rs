//! Prediction of held-out designs ([`HeldOut`]): every way of leaving `k` designs out,
//! refitted on the linearisation around the optimum of all designs.

use nalgebra::{DMatrix, DVector};

use super::evaluation::{mean, Evaluation, Recorded, Residual};
use super::lm::bounded_lm;
use super::report::HeldOut;

/// [`HeldOut`] of an evaluation at the optimum `x` (the unknowns' values) with bounds.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn held_out(e: &Evaluation, x: &[f64], bnds: &[(f64, f64)], k: usize) -> HeldOut {
    let mut designs: Vec<(usize, f64)> = e.what.iter().map(|w| (w.n, w.t)).collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    if designs.len() <= k || !e.error.is_empty() {
        return HeldOut::default();
    }
    let mut splits = Vec::new();
    combinations(designs.len(), k, &mut Vec::new(), 0, &mut splits);
    let (mut sum_be, mut sum_f, mut sum_in) = (0.0, 0.0, 0.0);
    let mut worst = (f64::NEG_INFINITY, Vec::new());
    for split in &splits {
        let out: Vec<(usize, f64)> = split.iter().map(|&i| designs[i]).collect();
        let held = |w: &Residual| out.contains(&(w.n, w.t));
        let keep: Vec<usize> = (0..e.what.len()).filter(|&i| !held(&e.what[i])).collect();
        let rk = DVector::from_fn(keep.len(), |i, _| e.r[keep[i]]);
        let jk = DMatrix::from_fn(keep.len(), x.len(), |i, c| e.j[(keep[i], c)]);
        let fit = bounded_lm(x, bnds, 1e-3, 1.0, 50, 0.0, |v| -> Result<_, ()> {
            let d = DVector::from_fn(v.len(), |i, _| v[i] - x[i]);
            Ok(Some((&rk + &jk * &d, jk.clone())))
        })
        .expect("the linear model does not fail");
        let v = &fit.steps[fit.best].x;
        let d = DVector::from_fn(v.len(), |i, _| v[i] - x[i]);
        let pred = &e.r + &e.j * &d;
        let (be, be_in, f) = split_errors(e, &pred, &held);
        sum_be += be;
        sum_in += be_in;
        sum_f += f;
        if be > worst.0 {
            worst = (be, out);
        }
    }
    let n = splits.len() as f64;
    HeldOut {
        k,
        splits: splits.len(),
        mean_be_mm: sum_be / n,
        worst_be_mm: worst.0,
        worst: worst.1,
        mean_abs_force_error_n: sum_f / n,
        in_sample_be_mm: sum_in / n,
    }
}

/// Mean tip BE of the held-out configurations with the refit's residuals `pred` and at the
/// optimum itself, and their mean |force error|.
fn split_errors(
    e: &Evaluation,
    pred: &DVector<f64>,
    held: &dyn Fn(&Residual) -> bool,
) -> (f64, f64, f64) {
    let (mut be, mut be_in, mut f) = (Vec::new(), Vec::new(), Vec::new());
    for (i, w) in e.what.iter().enumerate() {
        if !held(w) {
            continue;
        }
        match w.output {
            Recorded::TipUz => {
                // the Uy residual of the same configuration follows it
                let j = i + 1;
                be.push(w.sigma * pred[i].hypot(pred[j]));
                be_in.push(w.sigma * e.r[i].hypot(e.r[j]));
            }
            Recorded::TipUy => {}
            Recorded::Force => f.push(w.sigma * pred[i].abs()),
        }
    }
    (mean(&be), mean(&be_in), mean(&f))
}

/// Every `k`-subset of `0..n` in lexicographic order.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn combinations(
    n: usize,
    k: usize,
    cur: &mut Vec<usize>,
    from: usize,
    out: &mut Vec<Vec<usize>>,
) {
    if cur.len() == k {
        out.push(cur.clone());
        return;
    }
    for i in from..n {
        cur.push(i);
        combinations(n, k, cur, i + 1, out);
        cur.pop();
    }
}
