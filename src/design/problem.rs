//! The validated problem: checks of the material, pressures, bounds and settings against the
//! model at the door, and the cost `Φ` with its Gauss–Newton terms at one design.

use std::ops::Range;

use super::report::TLimit;
use super::target::{model_t_range, DesignBounds, DesignSearch, Target};
use super::DesignError;
use crate::case::{OgdenSet, Query, BOUND_TOLERANCE};
use crate::fe::preset::Geometry;
use crate::rom::{Jacobian, Prediction, Surrogate};
use crate::schema::DOMAIN_INPUTS;
use crate::snapshots::plan::max_wall_thickness_in;

/// The geometry the model's training cases were built with: the plan's preset
/// ([`crate::rom::provenance::BuiltWith`]), else the geometry as modelled.
pub(super) fn geometry(model: &Surrogate) -> Geometry {
    model
        .training
        .built_with
        .as_ref()
        .map_or_else(Geometry::as_modelled, |b| b.geometry.clone())
}

/// The largest buildable wall of `n` bellows with `geometry`, mm (`−∞`: none).
pub(super) fn buildable_t_max(geometry: &Geometry, n: u32) -> f64 {
    max_wall_thickness_in(geometry, n as usize)
}

/// How far beyond an end of `[lo, hi]` a value is still inside (the domain's tolerance).
fn slack(lo: f64, hi: f64) -> f64 {
    BOUND_TOLERANCE * (hi - lo).abs() + 1e-12
}

/// Checks a material: four finite numbers the model accepts, inside its training domain
/// (within the domain's tolerance, onto whose ends it is moved).
pub(super) fn check_material(model: &Surrogate, m: OgdenSet) -> Result<OgdenSet, DesignError> {
    let shown = || format!("{:?}", m.as_array());
    if m.as_array().iter().any(|v| !v.is_finite()) {
        return Err(DesignError::invalid(
            "material",
            shown(),
            "four finite numbers [mu1, alpha1, mu2, alpha2]",
        ));
    }
    let n = model.n_allowed.first().copied().unwrap_or(0);
    let [t_lo, t_hi] = model_t_range(model);
    let p = model.pressures.first().copied().unwrap_or(0.0);
    let q = Query::new(n, 0.5 * (t_lo + t_hi), p, m);
    model.check_query(&q).map_err(|e| {
        DesignError::invalid(
            "material",
            shown(),
            format!("a material the model accepts ({e})"),
        )
    })?;
    let (q, _) = model.snap_to_domain(&q);
    let outside: Vec<String> = model
        .domain_violations(&q)
        .iter()
        .filter(|v| DOMAIN_INPUTS[3..].iter().any(|c| c.name == v.name))
        .map(|v| v.to_string())
        .collect();
    if !outside.is_empty() {
        return Err(DesignError::invalid(
            "material",
            shown(),
            format!(
                "a set inside the model's training domain ({})",
                outside.join("; ")
            ),
        ));
    }
    Ok(q.material)
}

/// Checks a pressure: finite and inside the model's grid.
pub(super) fn check_pressure(model: &Surrogate, field: &str, p: f64) -> Result<(), DesignError> {
    let lo = model
        .pressures
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let hi = model
        .pressures
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    if p.is_finite() && p >= lo && p <= hi {
        return Ok(());
    }
    Err(DesignError::invalid(
        field,
        p,
        format!("a pressure in [{lo}, {hi}] bar (the model's grid)"),
    ))
}

/// Checks a wall thickness against the model's range of `T`.
pub(super) fn check_t(model: &Surrogate, field: &str, t: f64) -> Result<f64, DesignError> {
    let [lo, hi] = model_t_range(model);
    let s = slack(lo, hi);
    if t.is_finite() && t >= lo - s && t <= hi + s {
        return Ok(t.clamp(lo, hi));
    }
    Err(DesignError::invalid(
        field,
        t,
        format!("a wall thickness in [{lo}, {hi}] mm (the model's range)"),
    ))
}

/// The bounds of `T`: finite, MIN ≤ MAX, inside the model's range (within its tolerance,
/// onto whose ends they are moved).
fn check_t_bounds(model: &Surrogate, (a, b): (f64, f64)) -> Result<(f64, f64), DesignError> {
    let shown = format!("{a}..={b}");
    if !(a.is_finite() && b.is_finite() && a <= b) {
        return Err(DesignError::invalid(
            "bounds.t_mm",
            shown,
            "MIN..=MAX, finite, with MIN ≤ MAX",
        ));
    }
    let inside = |t: f64| {
        check_t(model, "bounds.t_mm", t).map_err(|_| {
            // shown to 3 decimals, rounded inwards: a range typed from the message is inside
            let [lo, hi] = model_t_range(model);
            let (lo, hi) = (
                (lo * 1e3 - 1e-6).ceil() / 1e3,
                (hi * 1e3 + 1e-6).floor() / 1e3,
            );
            DesignError::invalid(
                "bounds.t_mm",
                &shown,
                format!("a range inside the model's T [{lo}, {hi}] mm"),
            )
        })
    };
    Ok((inside(a)?, inside(b)?))
}

/// The targets: at least one, finite values, positive tolerances, pressures in the grid.
fn check_targets(model: &Surrogate, targets: &[Target]) -> Result<(), DesignError> {
    if targets.is_empty() {
        return Err(DesignError::invalid("targets", "[]", "at least one target"));
    }
    for (i, t) in targets.iter().enumerate() {
        if !t.value.is_finite() {
            return Err(DesignError::invalid(
                format!("targets[{i}].value"),
                t.value,
                format!("a finite {} in {}", t.output, t.output.unit()),
            ));
        }
        if !(t.tolerance.is_finite() && t.tolerance > 0.0) {
            return Err(DesignError::invalid(
                format!("targets[{i}].tolerance"),
                t.tolerance,
                format!("a finite scale > 0 {}", t.output.unit()),
            ));
        }
        check_pressure(model, &format!("targets[{i}].p_bar"), t.p_bar)?;
    }
    Ok(())
}

fn check_settings(s: &DesignSearch) -> Result<(), DesignError> {
    if s.starts == 0 {
        return Err(DesignError::invalid("settings.starts", 0, "at least 1"));
    }
    if s.max_iterations == 0 {
        return Err(DesignError::invalid(
            "settings.max_iterations",
            0,
            "at least 1",
        ));
    }
    if !(s.step_tolerance_mm.is_finite() && s.step_tolerance_mm > 0.0) {
        return Err(DesignError::invalid(
            "settings.step_tolerance_mm",
            s.step_tolerance_mm,
            "a finite length > 0 mm",
        ));
    }
    Ok(())
}

/// The numbers of bellows the model predicts inside `bounds.n`, checked.
fn check_n(model: &Surrogate, n: (u32, u32)) -> Result<Vec<u32>, DesignError> {
    let shown = format!("{}..={}", n.0, n.1);
    let allowed = &model.n_allowed;
    let (Some(&lo), Some(&hi)) = (allowed.iter().min(), allowed.iter().max()) else {
        return Err(DesignError::invalid(
            "model.n_allowed",
            "[]",
            "a model that predicts some N",
        ));
    };
    if n.0 > n.1 {
        return Err(DesignError::invalid(
            "bounds.n",
            shown,
            "MIN..=MAX with MIN ≤ MAX",
        ));
    }
    if n.0 < lo || n.1 > hi {
        return Err(DesignError::invalid(
            "bounds.n",
            shown,
            format!("a range inside the model's N {lo}..={hi}"),
        ));
    }
    let mut inside: Vec<u32> = allowed
        .iter()
        .copied()
        .filter(|v| (n.0..=n.1).contains(v))
        .collect();
    inside.sort_unstable();
    inside.dedup();
    if inside.is_empty() {
        return Err(DesignError::invalid(
            "bounds.n",
            shown,
            format!("a range holding an N the model predicts {allowed:?}"),
        ));
    }
    Ok(inside)
}

/// One distinct target pressure: the quantities to evaluate and the targets stated there.
pub(super) struct PressureGroup {
    pub p_bar: f64,
    pub range: Range<usize>,
    pub members: Vec<usize>,
}

/// The targets grouped by pressure, in order of first appearance.
fn groups(targets: &[Target]) -> Vec<PressureGroup> {
    let mut out: Vec<PressureGroup> = Vec::new();
    for (i, t) in targets.iter().enumerate() {
        let q = t.output.index();
        match out.iter_mut().find(|g| g.p_bar == t.p_bar) {
            Some(g) => {
                g.range = g.range.start.min(q)..g.range.end.max(q + 1);
                g.members.push(i);
            }
            None => out.push(PressureGroup {
                p_bar: t.p_bar,
                range: q..q + 1,
                members: vec![i],
            }),
        }
    }
    out
}

/// The cost and its Gauss–Newton terms at one design: `Φ = Σ r²`, `g = Σ J r`, `h = Σ J²`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Eval {
    pub cost: f64,
    pub g: f64,
    pub h: f64,
}

/// A validated problem (see the [module docs](super)).
pub(super) struct Problem<'a> {
    pub model: &'a Surrogate,
    pub material: OgdenSet,
    pub targets: &'a [Target],
    pub groups: Vec<PressureGroup>,
    pub n_values: Vec<u32>,
    pub geometry: Geometry,
    /// The lower end of `T` and what sets it.
    pub t_lo: (f64, TLimit),
    /// The upper end of `T` before buildability, and what sets it.
    pub t_hi: (f64, TLimit),
}

impl<'a> Problem<'a> {
    /// Checks every input against the model.
    pub fn new(
        model: &'a Surrogate,
        material: OgdenSet,
        targets: &'a [Target],
        bounds: &DesignBounds,
        settings: &DesignSearch,
    ) -> Result<Self, DesignError> {
        check_targets(model, targets)?;
        check_settings(settings)?;
        let n_values = check_n(model, bounds.n)?;
        let (a, b) = check_t_bounds(model, bounds.t_mm)?;
        let [lo, hi] = model_t_range(model);
        let material = check_material(model, material)?;
        Ok(Problem {
            model,
            material,
            targets,
            groups: groups(targets),
            n_values,
            geometry: geometry(model),
            t_lo: if a > lo {
                (a, TLimit::Bounds)
            } else {
                (lo, TLimit::Model)
            },
            t_hi: if b < hi {
                (b, TLimit::Bounds)
            } else {
                (hi, TLimit::Model)
            },
        })
    }

    /// The interval of `T` for `n` bellows and what sets its upper end (`hi < lo`: none
    /// buildable).
    pub fn t_interval(&self, n: u32) -> (f64, f64, TLimit) {
        let build = buildable_t_max(&self.geometry, n);
        if build <= self.t_hi.0 {
            (self.t_lo.0, build, TLimit::Buildable)
        } else {
            (self.t_lo.0, self.t_hi.0, self.t_hi.1)
        }
    }

    /// `Φ`, `Σ J r` and `Σ J²` at `(n, t)`, through `pred` and `jac` (no allocation).
    pub fn evaluate(
        &self,
        n: u32,
        t: f64,
        pred: &mut Prediction,
        jac: &mut Jacobian,
    ) -> Result<Eval, DesignError> {
        let mut e = Eval {
            cost: 0.0,
            g: 0.0,
            h: 0.0,
        };
        for group in &self.groups {
            let q = Query::new(n, t, group.p_bar, self.material);
            self.model
                .gradient_range_into(&q, group.range.clone(), pred, jac)?;
            for &k in &group.members {
                let target = &self.targets[k];
                let i = target.output.index();
                let r = (pred.values[i] - target.value) / target.tolerance;
                let j = jac.d[i][0] / target.tolerance;
                e.cost += r * r;
                e.g += j * r;
                e.h += j * j;
            }
        }
        Ok(e)
    }

    /// `Φ` at `(n, t)` through the scalar fast path (values only, no allocation).
    pub fn cost(&self, n: u32, t: f64, pred: &mut Prediction) -> Result<f64, DesignError> {
        let mut cost = 0.0;
        for group in &self.groups {
            let q = Query::new(n, t, group.p_bar, self.material);
            self.model.predict_scalars_into(&q, pred)?;
            for &k in &group.members {
                let target = &self.targets[k];
                let r = (pred.values[target.output.index()] - target.value) / target.tolerance;
                cost += r * r;
            }
        }
        Ok(cost)
    }

    /// The predicted value of each target's output at `(n, t)`, into `out` (one per target).
    pub fn values_into(
        &self,
        n: u32,
        t: f64,
        pred: &mut Prediction,
        jac: &mut Jacobian,
        out: &mut [f64],
    ) -> Result<(), DesignError> {
        for group in &self.groups {
            let q = Query::new(n, t, group.p_bar, self.material);
            self.model
                .gradient_range_into(&q, group.range.clone(), pred, jac)?;
            for &k in &group.members {
                out[k] = pred.values[self.targets[k].output.index()];
            }
        }
        Ok(())
    }
}
