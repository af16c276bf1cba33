//! The search: for every `N`, multi-start bounded Gauss–Newton in `T`; then the pick and its
//! errors ([module docs](super)).

use super::problem::{Eval, Problem};
use super::report::{
    Accuracy, BoundHit, Candidate, DesignAtN, DesignReport, Evaluations, Pick, PickedOutput, Side,
    Stop, TLimit,
};
use super::target::{DesignBounds, DesignSearch, Target};
use super::DesignError;
use crate::case::{OgdenSet, Query};
use crate::rom::{Jacobian, Prediction, Surrogate};

/// The designs `(N, T)` of least cost `Φ` for `targets`, one per `N` the model predicts
/// inside `bounds`, and the pick among them ([module docs](super)).
///
/// # Errors
/// [`DesignError::Invalid`] naming the field, its value and what was expected: no target, a
/// non-finite target value, a tolerance ≤ 0, a pressure outside the model's grid, bounds
/// with MIN > MAX or beyond the model's `N` or `T`, bounds holding no `N` the model
/// predicts, settings out of range, a material the model refuses or outside its domain.
/// [`DesignError::NoBuildableDesign`] when no `N` has a buildable wall inside the bounds.
pub fn search(
    model: &Surrogate,
    material: OgdenSet,
    targets: &[Target],
    bounds: &DesignBounds,
    settings: &DesignSearch,
) -> Result<DesignReport, DesignError> {
    let problem = Problem::new(model, material, targets, bounds, settings)?;
    let mut pred = model.new_prediction();
    let mut jac = Jacobian::default();
    let mut evaluations = Evaluations::default();
    let mut designs = Vec::with_capacity(problem.n_values.len());
    for &n in &problem.n_values {
        let (lo, hi, limit) = problem.t_interval(n);
        let best = if hi < lo {
            None
        } else {
            let mut ws = Work {
                pred: &mut pred,
                jac: &mut jac,
                evaluations: &mut evaluations,
            };
            Some(best_wall(&problem, n, (lo, hi, limit), settings, &mut ws)?)
        };
        designs.push(DesignAtN {
            n,
            t_min_mm: lo,
            t_max_mm: hi,
            t_max_limit: limit,
            best,
        });
    }
    let pick = pick(&problem, &designs, &mut pred)?;
    let accuracy = match model.model_form() {
        Some(m) => Accuracy::Known {
            calibration_report: m.calibration.report.clone(),
        },
        None => Accuracy::Unknown,
    };
    Ok(DesignReport {
        material: problem.material,
        targets: targets.to_vec(),
        geometry: problem.geometry.name.clone(),
        designs,
        pick,
        accuracy,
        evaluations,
    })
}

/// The buffers of the search, reused by every evaluation.
struct Work<'w> {
    pred: &'w mut Prediction,
    jac: &'w mut Jacobian,
    evaluations: &'w mut Evaluations,
}

impl Work<'_> {
    /// `Φ` and its Gauss–Newton terms at `(n, t)`.
    fn eval(&mut self, p: &Problem<'_>, n: u32, t: f64) -> Result<Eval, DesignError> {
        self.evaluations.gradient += p.groups.len();
        p.evaluate(n, t, self.pred, self.jac)
    }

    /// `Φ` at `(n, t)`, values only.
    fn scan(&mut self, p: &Problem<'_>, n: u32, t: f64) -> Result<f64, DesignError> {
        self.evaluations.scan += p.groups.len();
        p.cost(n, t, self.pred)
    }
}

/// The end of one start.
struct Run {
    t: f64,
    cost: f64,
    iterations: usize,
    stop: Stop,
}

/// Bounded Gauss–Newton in `T` from `t0` with step halving ([module docs](super)).
fn descend(
    p: &Problem<'_>,
    n: u32,
    t0: f64,
    (lo, hi): (f64, f64),
    s: &DesignSearch,
    ws: &mut Work<'_>,
) -> Result<Run, DesignError> {
    let (mut t, mut e) = (t0, ws.eval(p, n, t0)?);
    let end = |t: f64, e: Eval, iterations: usize, stop: Stop| Run {
        t,
        cost: e.cost,
        iterations,
        stop,
    };
    for it in 0..s.max_iterations {
        if e.cost == 0.0 {
            return Ok(end(t, e, it, Stop::Converged));
        }
        if !(e.h > 0.0 && e.h.is_finite()) {
            return Ok(end(t, e, it, Stop::Flat));
        }
        let step = -e.g / e.h;
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..=s.max_halvings {
            let trial = (t + lambda * step).clamp(lo, hi);
            if (trial - t).abs() < s.step_tolerance_mm {
                let outward = (t <= lo && step < 0.0) || (t >= hi && step > 0.0);
                let stop = match (outward, lambda == 1.0) {
                    (true, _) => Stop::Bound,
                    (false, true) => Stop::Converged,
                    (false, false) => Stop::NoDescent,
                };
                return Ok(end(t, e, it, stop));
            }
            let et = ws.eval(p, n, trial)?;
            if et.cost <= e.cost {
                accepted = Some((trial, et));
                break;
            }
            lambda *= 0.5;
        }
        let Some((trial, et)) = accepted else {
            return Ok(end(t, e, it, Stop::NoDescent));
        };
        (t, e) = (trial, et);
    }
    Ok(end(t, e, s.max_iterations, Stop::Iterations))
}

/// The best end point of the descents from the local minima of `Φ` over the starting scan
/// of `[lo, hi]` for `n` bellows ([module docs](super)).
fn best_wall(
    p: &Problem<'_>,
    n: u32,
    (lo, hi, hi_limit): (f64, f64, TLimit),
    s: &DesignSearch,
    ws: &mut Work<'_>,
) -> Result<Candidate, DesignError> {
    let start = |k: usize| {
        if s.starts == 1 {
            0.5 * (lo + hi)
        } else {
            lo + (hi - lo) * k as f64 / (s.starts - 1) as f64
        }
    };
    let mut best: Option<Run> = None;
    let (mut before, mut here) = (f64::INFINITY, ws.scan(p, n, start(0))?);
    for k in 0..s.starts {
        let after = if k + 1 < s.starts {
            ws.scan(p, n, start(k + 1))?
        } else {
            f64::INFINITY
        };
        if here <= before && here <= after {
            let run = descend(p, n, start(k), (lo, hi), s, ws)?;
            if best.as_ref().is_none_or(|b| run.cost < b.cost) {
                best = Some(run);
            }
        }
        (before, here) = (here, after);
    }
    // a scan without a finite minimum: one descent from its first wall
    let run = match best {
        Some(run) => run,
        None => descend(p, n, start(0), (lo, hi), s, ws)?,
    };
    let mut predicted = vec![0.0; p.targets.len()];
    p.values_into(n, run.t, ws.pred, ws.jac, &mut predicted)?;
    let bound = if run.t <= lo {
        Some(BoundHit {
            side: Side::Lower,
            limit: p.t_lo.1,
        })
    } else if run.t >= hi {
        Some(BoundHit {
            side: Side::Upper,
            limit: hi_limit,
        })
    } else {
        None
    };
    Ok(Candidate {
        t_mm: run.t,
        cost: run.cost,
        predicted,
        bound,
        iterations: run.iterations,
        stop: run.stop,
    })
}

/// The design of least cost (the smaller `N` on a tie), with its surrogate std and
/// model-form error at every target.
fn pick(
    p: &Problem<'_>,
    designs: &[DesignAtN],
    pred: &mut Prediction,
) -> Result<Pick, DesignError> {
    let best = designs
        .iter()
        .filter_map(|d| d.best.as_ref().map(|c| (d.n, c)))
        .fold(None::<(u32, &Candidate)>, |acc, (n, c)| match acc {
            Some((_, b)) if b.cost <= c.cost => acc,
            _ => Some((n, c)),
        });
    let Some((n, c)) = best else {
        let (lo, hi) = (p.t_lo.0, p.t_hi.0);
        return Err(DesignError::NoBuildableDesign(format!(
            "no N in {:?} leaves a cavity with a wall in [{lo}, {hi}] mm (geometry '{}')",
            p.n_values, p.geometry.name
        )));
    };
    let mut outputs = Vec::with_capacity(p.targets.len());
    for (target, &predicted) in p.targets.iter().zip(&c.predicted) {
        let q = Query::new(n, c.t_mm, target.p_bar, p.material);
        p.model.predict_with_std_into(&q, pred)?;
        let i = target.output.index();
        outputs.push(PickedOutput {
            target: *target,
            predicted,
            surrogate_std: pred.std[i],
            model_form: p.model.model_form_error(&q).and_then(|e| e.values[i]),
        });
    }
    Ok(Pick {
        n,
        t_mm: c.t_mm,
        cost: c.cost,
        bound: c.bound,
        outputs,
    })
}
