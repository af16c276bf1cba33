//! The parameter box: the input domain of a surrogate or of a plan, and the one check of a
//! query against it.
//!
//! A snapshot plan samples the material in `(μ0, s, α₁, α₂)`,
//!
//! ```text
//!   μ0 = ½ (μ₁α₁ + μ₂α₂)     initial shear modulus (log-uniform)
//!   s  = μ₁α₁ / (2 μ0)        share of term 1
//! ```
//!
//! and the surrogate regresses on exactly these features (`ln μ0`, `s`, `α₁`, `α₂`, with `N`
//! and `T`; [`super::features::raw_features`]). The domain is therefore a box in those
//! coordinates, not in the raw `μ₁, μ₂`: the marginal ranges of `μ₁` and `μ₂` over the
//! training cases are not a region the regression saw (`μ₂ = −1214 MPa` with `α₂ = −0.0054`
//! is an ordinary `μ₂α₂`). A [`Domain`] holds that box, the trained numbers of bellows and the
//! pressure grid's ends; [`Domain::violations`] is the single test of a query, used by
//! [`Surrogate::domain_violations`](crate::rom::Surrogate::domain_violations) (the box of the
//! training cases, stored in the model's [`FeatureScaler`]) and by the snapshot plan's report
//! [`Plan::sampled_domain`](crate::snapshots::plan::Plan::sampled_domain) (the box of the
//! plan's cases, built the same way), so a plan and a model trained on all its cases say the
//! same of every query.
//!
//! Outside the box the regression **extrapolates**; outside the pressure grid the prediction is
//! **clamped**: it holds the value at the nearer end of the grid (and its derivative with respect
//! to the pressure is zero there). Both are reported in [`DomainViolation::clamped`].
//!
//! ## The plan's ranges
//!
//! A Latin hypercube of `K` cases puts one case in each of `K` equal strata of every axis, so
//! its extreme cases lie within one stratum, `(hi − lo)/K`, of the plan's nominal ends (μ0 in
//! `ln μ0`, the coordinate it is sampled in): a query between the extreme case and the end
//! is no farther from the design than a query between two neighbouring strata inside it. The
//! domain therefore reaches the plan's nominal end wherever the training cases come within
//! one stratum of it ([`Domain::with_plan_ends`]), and keeps the cases' extreme where they do
//! not (cases dropped at an edge, a subset that misses it). A model trained on a plan states
//! the result in its file ([`PlanDomain`], in the model's training information), so the
//! shipped model accepts `T = 1.4 … 2.6 mm`, the plan's range, not `1.4017 … 2.5973`, the
//! span of its cases. `N` is never widened: only trained values are predicted.
//!
//! ## Tolerance at the ends
//!
//! A value beyond an end by at most [`BOUND_TOLERANCE`] of the range (in the coordinate the
//! domain states it in: `μ0` in MPa) is inside: a calibrated set on a bound, printed to four
//! decimals and typed back, is accepted. [`Domain::snap`] moves such a value onto the end and
//! returns a note for each ([`BoundSnap`]); the prediction commands evaluate the snapped query.

use serde::{Deserialize, Serialize};

use super::features::{raw_features, FeatureScaler};
use super::inputs::{CaseInputs, Query};
use super::OgdenSet;
use crate::schema;
use surrogate_predict::N_FEATURES;

/// How far beyond an end of the domain a value is still inside, as a fraction of the range
/// (see the [module docs](self)): `1e-4`, far below any resolution of the regression, and above
/// the rounding of a set printed to four decimals (`α₂ = −1.9965` for the bound
/// `−1.996454…`: `2.3e-5` of the range).
pub const BOUND_TOLERANCE: f64 = 1e-4;

/// Indices (in [`DOMAIN_INPUTS`]) of the material coordinates `μ0, s, α₁, α₂`.
const MATERIAL_INPUTS: [usize; 4] = [3, 4, 5, 6];

/// The checked inputs (name, unit, meaning), in the order violations are reported.
pub use crate::schema::DOMAIN_INPUTS;

/// Index of each regression feature `(N, T, ln μ0, α₁, s, α₂)` among [`DOMAIN_INPUTS`].
const FEATURE_INPUT: [usize; N_FEATURES] = [0, 1, 3, 5, 4, 6];

/// An input outside the domain.
#[derive(Debug, Clone, PartialEq)]
pub struct DomainViolation {
    /// Input name ([`DOMAIN_INPUTS`]).
    pub name: String,
    /// Value given.
    pub value: f64,
    /// Smallest value of the domain.
    pub min: f64,
    /// Largest value of the domain.
    pub max: f64,
    /// `true`: the prediction holds the value at the nearer end (`min` or `max`) instead of
    /// extrapolating (the pressure); `false`: the regression extrapolates.
    pub clamped: bool,
}

impl DomainViolation {
    /// The value the prediction is evaluated at: the nearer end when clamped, else the value.
    pub fn used(&self) -> f64 {
        if self.clamped {
            self.value.clamp(self.min, self.max)
        } else {
            self.value
        }
    }

    /// A short form for tables: `pressure_bar=5 (clamped to 3.5)` or
    /// `alpha2=-0.0054 (extrapolated)`.
    pub fn short(&self) -> String {
        if self.clamped {
            format!("{}={} (clamped to {})", self.name, self.value, self.used())
        } else {
            format!("{}={} (extrapolated)", self.name, self.value)
        }
    }
}

impl std::fmt::Display for DomainViolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.name == schema::N_BELLOWS.name {
            return write!(f, "{} = {} was not trained", self.name, self.value);
        }
        write!(
            f,
            "{} = {} outside the training domain [{}, {}]",
            self.name, self.value, self.min, self.max
        )?;
        if self.clamped {
            write!(f, " (a prediction there is clamped to {})", self.used())
        } else {
            write!(f, " (a prediction there is extrapolated)")
        }
    }
}

/// A value of a query beyond an end of the domain by at most [`BOUND_TOLERANCE`] of the
/// range, moved onto the end ([`Domain::snap`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BoundSnap {
    /// Input name ([`DOMAIN_INPUTS`]).
    pub name: String,
    /// Value given.
    pub value: f64,
    /// The end it was moved onto.
    pub bound: f64,
    /// The range's width (the tolerance is [`BOUND_TOLERANCE`] of it).
    pub width: f64,
}

impl std::fmt::Display for BoundSnap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} = {} lies {:.1e} beyond the training domain's end {}, within the tolerance at \
             the ends ({BOUND_TOLERANCE:e} of the range): predicted at the end",
            self.name,
            self.value,
            (self.value - self.bound).abs(),
            self.bound
        )
    }
}

/// The range of one input, by name, as a model file states it ([`PlanDomain`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InputRange {
    /// Input name ([`DOMAIN_INPUTS`]).
    pub name: String,
    /// Smallest value of the domain.
    pub min: f64,
    /// Largest value of the domain.
    pub max: f64,
}

/// The domain of a model trained on a snapshot plan, as its file states it: for each input
/// but `N` and the pressure, the plan's nominal end where the training cases come within one
/// stratum of it, else the cases' extreme ([`Domain::with_plan_ends`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanDomain {
    /// The plan: its file and hash.
    pub plan: String,
    /// Cases of the plan (one stratum is `1/cases` of a range).
    pub plan_cases: usize,
    /// The ranges, in [`DOMAIN_INPUTS`] order.
    pub ranges: Vec<InputRange>,
}

/// The domain of a surrogate or of a plan (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    /// The numbers of bellows, increasing.
    pub n_bellows: Vec<u32>,
    /// Range of each of [`DOMAIN_INPUTS`] except `n_bellows` (index 0, unused); `None`: not
    /// constrained (a feature constant over the cases, which the regression does not use).
    pub ranges: [Option<[f64; 2]>; 7],
}

impl Domain {
    /// The domain of a fitted feature box: `scaler` holds the range of each feature that
    /// varies over the cases ([`FeatureScaler::fit`]); `constant(f)` gives the value of a
    /// feature `f` that does not vary (the domain is then that single value; `None`: not
    /// constrained); `pressures` is the grid.
    pub fn from_features(
        n_bellows: &[u32],
        pressures: &[f64],
        scaler: &FeatureScaler,
        constant: impl Fn(usize) -> Option<f64>,
    ) -> Self {
        let mut n: Vec<u32> = n_bellows.to_vec();
        n.sort_unstable();
        n.dedup();
        let mut ranges = [None; 7];
        let lo = pressures.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = pressures.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        ranges[2] = Some([lo, hi]);
        for f in 1..N_FEATURES {
            if !scaler.index.contains(&f) {
                ranges[FEATURE_INPUT[f]] =
                    constant(f).map(|v| if f == 2 { [v.exp(); 2] } else { [v; 2] });
            }
        }
        for (j, &f) in scaler.index.iter().enumerate() {
            if f == 0 {
                continue;
            }
            let half = 1.0 / scaler.inv_half[j];
            let (a, b) = (scaler.center[j] - half, scaler.center[j] + half);
            ranges[FEATURE_INPUT[f]] = Some(if f == 2 { [a.exp(), b.exp()] } else { [a, b] });
        }
        Domain {
            n_bellows: n,
            ranges,
        }
    }

    /// The domain of a set of cases: their feature box ([`FeatureScaler::fit`]) and `N`s.
    pub fn of_cases(cases: &[CaseInputs], pressures: &[f64]) -> Self {
        let z: Vec<[f64; N_FEATURES]> = cases.iter().map(raw_features).collect();
        let n: Vec<u32> = cases.iter().map(|c| c.n_bellows).collect();
        Self::from_features(&n, pressures, &FeatureScaler::fit(&z), |f| {
            z.first().map(|z| z[f])
        })
    }

    /// This domain with the plan's nominal ends (`nominal`: [`Ranges::domain`]'s box) wherever
    /// this domain (the span of the cases) comes within one stratum of them, `1/plan_cases`
    /// of the nominal range (in `ln μ0` for μ0); see the [module docs](self). `N`, the
    /// pressure and an unconstrained or single-valued input are kept.
    ///
    /// [`Ranges::domain`]: crate::snapshots::plan::Ranges::domain
    pub fn with_plan_ends(&self, nominal: &Domain, plan_cases: usize) -> Domain {
        let mut out = self.clone();
        let k = plan_cases.max(1) as f64;
        for i in [1, 3, 4, 5, 6] {
            let (Some([a, b]), Some([lo, hi])) = (self.ranges[i], nominal.ranges[i]) else {
                continue;
            };
            if a >= b || lo >= hi {
                continue;
            }
            // the sampling coordinate: μ0 is log-uniform
            let c = |v: f64| if i == 3 { v.ln() } else { v };
            let stratum = (c(hi) - c(lo)) / k;
            let lower = if (0.0..=stratum).contains(&(c(a) - c(lo))) {
                lo
            } else {
                a
            };
            let upper = if (0.0..=stratum).contains(&(c(hi) - c(b))) {
                hi
            } else {
                b
            };
            out.ranges[i] = Some([lower, upper]);
        }
        out
    }

    /// The ranges of the inputs [`Self::with_plan_ends`] may change (`T` and the material
    /// coordinates), by name, for a model file ([`PlanDomain`]).
    pub fn stated_ranges(&self) -> Vec<InputRange> {
        [1, 3, 4, 5, 6]
            .into_iter()
            .filter_map(|i| {
                self.ranges[i].map(|[min, max]| InputRange {
                    name: DOMAIN_INPUTS[i].name.into(),
                    min,
                    max,
                })
            })
            .collect()
    }

    /// This domain with the ranges a model file states ([`PlanDomain::ranges`]) in place of
    /// its own; a name that is not one of [`DOMAIN_INPUTS`] (or is `N`) is ignored.
    pub fn with_stated(&self, ranges: &[InputRange]) -> Domain {
        let mut out = self.clone();
        for r in ranges {
            if let Some(i) = DOMAIN_INPUTS.iter().position(|c| c.name == r.name) {
                if i > 0 {
                    out.ranges[i] = Some([r.min, r.max]);
                }
            }
        }
        out
    }

    /// The values of `q` in [`DOMAIN_INPUTS`] order (`μ0` and `s` are NaN-free only for an
    /// admissible material) and whether the material is admissible.
    fn values(q: &Query) -> ([f64; 7], bool) {
        let m = &q.material;
        let (k1, k2) = (m.mu1_mpa * m.alpha1, m.mu2_mpa * m.alpha2);
        let mu0 = 0.5 * (k1 + k2);
        let values = [
            f64::from(q.n),
            q.t_mm,
            q.p_bar,
            mu0,
            k1 / (k1 + k2),
            m.alpha1,
            m.alpha2,
        ];
        (values, k1 > 0.0 && k2 > 0.0)
    }

    /// How far beyond the range `[lo, hi]` a value is still inside: [`BOUND_TOLERANCE`] of
    /// the width, and at least round-off.
    fn tolerance(lo: f64, hi: f64) -> f64 {
        (1e-9 * (1.0 + lo.abs().max(hi.abs()))).max(BOUND_TOLERANCE * (hi - lo))
    }

    /// `q` with every input that lies beyond an end by at most the tolerance
    /// ([`BOUND_TOLERANCE`] of the range) moved onto it, and a note for each. A material
    /// coordinate moved (`μ0`, `s`, `α₁`, `α₂`) gives the set `μ₁ = 2 s μ0/α₁`,
    /// `μ₂ = 2 (1 − s) μ0/α₂` of the moved coordinates. Inputs inside, or farther outside
    /// (violations), are left as given; an inadmissible material is left as given.
    pub fn snap(&self, q: &Query) -> (Query, Vec<BoundSnap>) {
        let (mut v, admissible) = Self::values(q);
        let mut notes = Vec::new();
        for i in 1..7 {
            let Some([lo, hi]) = self.ranges[i] else {
                continue;
            };
            if MATERIAL_INPUTS.contains(&i) && !admissible {
                continue;
            }
            let tol = Self::tolerance(lo, hi);
            let bound = if v[i] < lo && v[i] >= lo - tol {
                lo
            } else if v[i] > hi && v[i] <= hi + tol {
                hi
            } else {
                continue;
            };
            notes.push(BoundSnap {
                name: DOMAIN_INPUTS[i].name.into(),
                value: v[i],
                bound,
                width: hi - lo,
            });
            v[i] = bound;
        }
        let mut out = *q;
        out.t_mm = v[1];
        out.p_bar = v[2];
        let moved = |name: &str| notes.iter().any(|n: &BoundSnap| n.name == name);
        if MATERIAL_INPUTS
            .iter()
            .any(|&i| moved(DOMAIN_INPUTS[i].name))
        {
            let (mu0, s, a1, a2) = (v[3], v[4], v[5], v[6]);
            out.material = OgdenSet {
                mu1_mpa: 2.0 * s * mu0 / a1,
                alpha1: a1,
                mu2_mpa: 2.0 * (1.0 - s) * mu0 / a2,
                alpha2: a2,
            };
        }
        (out, notes)
    }

    /// The inputs of `q` outside the domain, in [`DOMAIN_INPUTS`] order; a value beyond an
    /// end by at most [`BOUND_TOLERANCE`] of the range is inside ([`Self::snap`]). An
    /// inadmissible material (`μᵢαᵢ ≤ 0`, rejected by
    /// [`Surrogate::check_query`](crate::rom::Surrogate::check_query)) has no `μ0` or `s`: only its
    /// exponents are checked.
    pub fn violations(&self, q: &Query) -> Vec<DomainViolation> {
        let (values, admissible) = Self::values(q);
        let mut out = Vec::new();
        if !self.n_bellows.contains(&q.n) {
            out.push(DomainViolation {
                name: DOMAIN_INPUTS[0].name.into(),
                value: values[0],
                min: self.n_bellows.first().map_or(f64::NAN, |&n| f64::from(n)),
                max: self.n_bellows.last().map_or(f64::NAN, |&n| f64::from(n)),
                clamped: false,
            });
        }
        for i in 1..7 {
            let Some([lo, hi]) = self.ranges[i] else {
                continue;
            };
            if (i == 3 || i == 4) && !admissible {
                continue;
            }
            let v = values[i];
            let tol = Self::tolerance(lo, hi);
            if !(v >= lo - tol && v <= hi + tol) {
                out.push(DomainViolation {
                    name: DOMAIN_INPUTS[i].name.into(),
                    value: v,
                    min: lo,
                    max: hi,
                    clamped: i == 2,
                });
            }
        }
        out
    }

    /// Whether the Ogden set lies inside the material part of the domain.
    pub fn contains_material(&self, m: OgdenSet) -> bool {
        let n = self.n_bellows.first().copied().unwrap_or(0);
        let t = self.ranges[1].map_or(0.0, |r| r[0]);
        let p = self.ranges[2].map_or(0.0, |r| r[0]);
        let q = Query::new(n, t, p, m);
        (m.mu1_mpa * m.alpha1 > 0.0 && m.mu2_mpa * m.alpha2 > 0.0) && self.violations(&q).is_empty()
    }
}

/// The domain violations of a batch of queries, summarised: how many rows, and the first few
/// with their violations (for one message per batch instead of one per row).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BatchDomainReport {
    /// Rows checked.
    pub rows: usize,
    /// Rows with at least one input outside the domain.
    pub outside: usize,
    /// The first rows outside: a label (line number) and the violations.
    pub first: Vec<(String, Vec<DomainViolation>)>,
}

impl BatchDomainReport {
    /// How many offending rows are listed in full.
    pub const LISTED: usize = 5;

    /// Records one row's violations.
    pub fn record(&mut self, label: impl FnOnce() -> String, v: &[DomainViolation]) {
        self.rows += 1;
        if v.is_empty() {
            return;
        }
        self.outside += 1;
        if self.first.len() < Self::LISTED {
            self.first.push((label(), v.to_vec()));
        }
    }
}

impl std::fmt::Display for BatchDomainReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of {} rows outside the training domain",
            self.outside, self.rows
        )?;
        let listed: Vec<String> = self
            .first
            .iter()
            .map(|(label, v)| {
                let v: Vec<String> = v.iter().map(DomainViolation::to_string).collect();
                format!("{label}: {}", v.join("; "))
            })
            .collect();
        if !listed.is_empty() {
            let more = if self.outside > self.first.len() {
                format!(" (first {})", self.first.len())
            } else {
                String::new()
            };
            write!(f, "{more}: {}", listed.join(" | "))?;
        }
        Ok(())
    }
}
