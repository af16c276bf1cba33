//! The material box of a round, the bounds the optimum presses moved outwards, and the slabs
//! between the old box and the new one.

use serde::{Deserialize, Serialize};

use super::limits::PhysicalLimits;
use crate::calibrate::fit::ActiveBound;
use crate::calibrate::optimise::Bound;
use crate::calibrate::params::ParamSpace;
use crate::calibrate::CalibrateError;
use crate::case::material::COORD_NAMES;
use crate::snapshots::plan::Ranges;

/// A box in the sampling coordinates `(μ0, s, α₁, α₂)`, each range in its physical unit (`μ0`
/// in MPa; its widths and steps are taken in `ln μ0`, the coordinate it is sampled in).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialBox {
    /// `μ0` (MPa).
    pub mu0_mpa: [f64; 2],
    /// `s`.
    pub term1_share: [f64; 2],
    /// `α₁`.
    pub alpha1: [f64; 2],
    /// `α₂`.
    pub alpha2: [f64; 2],
}

/// A bound the optimum presses, and where the extension moves it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PressedBound {
    /// Coordinate name (`mu0_mpa`, `term1_share`, `alpha1`, `alpha2`).
    pub coordinate: String,
    /// Which bound.
    pub side: Bound,
    /// The box's bound before the extension.
    pub bound: f64,
    /// The physical limit on that side.
    pub limit: f64,
    /// Where the bound moves (`None`: it is at its physical limit already).
    pub moved_to: Option<f64>,
}

impl PressedBound {
    /// `alpha1 lower 2.01 → 1.05` or `alpha1 upper 20 (its physical limit)`.
    pub fn describe(&self) -> String {
        let side = match self.side {
            Bound::Lower => "lower",
            Bound::Upper => "upper",
        };
        match self.moved_to {
            Some(to) => format!(
                "{} {side} {} → {}",
                self.coordinate,
                sig(self.bound),
                sig(to)
            ),
            None => format!(
                "{} {side} {} (its physical limit {})",
                self.coordinate,
                sig(self.bound),
                sig(self.limit)
            ),
        }
    }
}

/// A number to 4 significant digits, for tables.
pub(super) fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return v.to_string();
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

/// Coordinate `i`'s value in its sampling coordinate (`ln μ0` for `μ0`).
fn sampling(i: usize, v: f64) -> f64 {
    if i == 0 {
        v.ln()
    } else {
        v
    }
}

/// Coordinate `i`'s physical value of a sampling-coordinate value.
fn physical(i: usize, x: f64) -> f64 {
    if i == 0 {
        x.exp()
    } else {
        x
    }
}

impl MaterialBox {
    /// The box of a training domain ([`ParamSpace::training_domain`]).
    ///
    /// # Errors
    /// A raw box (the study's ±10 % box is not a training domain).
    pub fn of_domain(domain: &ParamSpace) -> Result<Self, CalibrateError> {
        let ParamSpace::Training { lo, hi } = domain else {
            return Err(CalibrateError::input(
                "box",
                "a raw (μ₁, α₁, μ₂, α₂) box",
                "a training domain in (ln μ0, s, α₁, α₂)",
            ));
        };
        let r = |i: usize| [physical(i, lo[i]), physical(i, hi[i])];
        Ok(MaterialBox {
            mu0_mpa: r(0),
            term1_share: r(1),
            alpha1: r(2),
            alpha2: r(3),
        })
    }

    /// The range of coordinate `i` (physical units).
    pub fn range(&self, i: usize) -> [f64; 2] {
        [self.mu0_mpa, self.term1_share, self.alpha1, self.alpha2][i]
    }

    fn range_mut(&mut self, i: usize) -> &mut [f64; 2] {
        match i {
            0 => &mut self.mu0_mpa,
            1 => &mut self.term1_share,
            2 => &mut self.alpha1,
            _ => &mut self.alpha2,
        }
    }

    /// The width of coordinate `i` in its sampling coordinate.
    pub fn width(&self, i: usize) -> f64 {
        let [lo, hi] = self.range(i);
        sampling(i, hi) - sampling(i, lo)
    }

    /// `ranges` (the training plan's: `N`, `T`, sampled effects) with this box's material.
    pub fn ranges(&self, ranges: &Ranges) -> Ranges {
        Ranges {
            mu0_mpa: self.mu0_mpa,
            term1_share: self.term1_share,
            alpha1: self.alpha1,
            alpha2: self.alpha2,
            ..ranges.clone()
        }
    }

    /// The box in words: `μ0 2.000–4.000 MPa, s 0.3119–0.6978, α1 2.011–3.941, α2 −1.489–−0.5240`.
    pub fn describe(&self) -> String {
        let r = |i: usize| {
            let [lo, hi] = self.range(i);
            format!("{}–{}", sig(lo), sig(hi))
        };
        format!("μ0 {} MPa, s {}, α1 {}, α2 {}", r(0), r(1), r(2), r(3))
    }

    /// This box with every bound in `pressed` moved outwards by `step` of its coordinate's
    /// width (in the sampling coordinate), clipped at its physical limit; and each pressed
    /// bound with where it went (`moved_to: None` when it is at its limit already, or beyond
    /// it: a box trained outside the limits is not extended there).
    pub fn extended(
        &self,
        pressed: &[ActiveBound],
        step: f64,
        limits: &PhysicalLimits,
    ) -> (MaterialBox, Vec<PressedBound>) {
        let mut out = *self;
        let moves = pressed
            .iter()
            .map(|a| {
                let i = a.coordinate;
                let [lo, hi] = self.range(i);
                let [l_lo, l_hi] = limits.range(i);
                let (bound, limit, dir) = match a.side {
                    Bound::Lower => (lo, l_lo, -1.0),
                    Bound::Upper => (hi, l_hi, 1.0),
                };
                let (xb, xl) = (sampling(i, bound), sampling(i, limit));
                let room = dir * (xl - xb);
                let moved_to = (room > 1e-9 * (1.0 + xl.abs())).then(|| {
                    let x = xb + dir * (step * self.width(i)).min(room);
                    let v = physical(i, x);
                    out.range_mut(i)[usize::from(a.side == Bound::Upper)] = v;
                    v
                });
                PressedBound {
                    coordinate: COORD_NAMES[i].to_string(),
                    side: a.side,
                    bound,
                    limit,
                    moved_to,
                }
            })
            .collect();
        (out, moves)
    }

    /// The part of `self` outside `inner` (a box inside it) as disjoint boxes, the slabs, each
    /// with its share of `self`'s volume (in the sampling coordinates). Coordinate by
    /// coordinate, lower side before upper, a slab takes the new part of its coordinate and
    /// the old range of every coordinate sliced before it (the full range of the rest), so the
    /// slabs do not overlap and together fill `self − inner`.
    pub fn slabs(&self, inner: &MaterialBox) -> Vec<(MaterialBox, f64)> {
        let mut rest = *self;
        let mut out = Vec::new();
        for i in 0..4 {
            let [lo, hi] = self.range(i);
            let [ilo, ihi] = inner.range(i);
            for (a, b) in [(lo, ilo), (ihi, hi)] {
                if sampling(i, b) - sampling(i, a) > 1e-12 * (1.0 + sampling(i, b).abs()) {
                    let mut slab = rest;
                    *slab.range_mut(i) = [a, b];
                    let share = (0..4).map(|j| slab.width(j) / self.width(j)).product();
                    out.push((slab, share));
                }
            }
            *rest.range_mut(i) = [ilo.max(lo), ihi.min(hi)];
        }
        out
    }
}

/// `total` cases shared among slabs of volume shares `shares`: each slab first gets `floor`
/// (`floor · slabs ≤ total` is the caller's), the rest by volume, largest remainder first
/// (ties to the earlier slab).
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn allocate(total: usize, shares: &[f64], floor: usize) -> Vec<usize> {
    let mut counts = vec![floor; shares.len()];
    let free = total.saturating_sub(floor * shares.len());
    let sum: f64 = shares.iter().sum();
    if sum <= 0.0 || shares.is_empty() {
        return counts;
    }
    let exact: Vec<f64> = shares.iter().map(|s| free as f64 * s / sum).collect();
    for (c, e) in counts.iter_mut().zip(&exact) {
        *c += e.floor() as usize;
    }
    let given: usize = counts.iter().sum();
    let mut order: Vec<usize> = (0..shares.len()).collect();
    order.sort_by(|&a, &b| {
        (exact[b] - exact[b].floor())
            .total_cmp(&(exact[a] - exact[a].floor()))
            .then(a.cmp(&b))
    });
    for &i in order.iter().cycle().take(total.saturating_sub(given)) {
        counts[i] += 1;
    }
    counts
}
