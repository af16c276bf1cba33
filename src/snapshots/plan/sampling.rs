//! Sampling: the seeded maximin Latin hypercube stratified over `N`, and the maximin subset of
//! a plan.

use egobox_doe::{Lhs, LhsKind, SamplingMethod};
use ndarray::Array2;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;

use super::format::{Plan, FORMAT_VERSION};
use super::ranges::{max_wall_thickness_in, Ranges};
use super::settings::PlanSettings;
use crate::fe::mesh::MeshOptions;
use crate::snapshots::SnapshotError;

/// Description of the sampler recorded in generated plans.
pub const SAMPLER: &str =
    "egobox-doe 0.35 Lhs(Optimized: maximin ESE) on [0,1]^6, Xoshiro256Plus::seed_from_u64(seed); \
     N stratified by rank";

/// `K` points of a maximin Latin hypercube in `[0, 1]^dims`.
pub(crate) fn unit_lhs(k: usize, dims: usize, seed: u64) -> Array2<f64> {
    let limits = Array2::from_shape_fn((dims, 2), |(_, j)| j as f64);
    let kind = if k < 3 {
        LhsKind::Classic
    } else {
        LhsKind::Optimized
    };
    Lhs::new_with_rng(&limits, Xoshiro256Plus::seed_from_u64(seed))
        .kind(kind)
        .sample(k)
}

impl Plan {
    /// Samples a plan of `n_cases` cases (see the [module docs](crate::snapshots::plan)).
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] for a bad range, setting, or `n_cases = 0`.
    pub fn generate(
        n_cases: usize,
        seed: u64,
        ranges: Ranges,
        settings: PlanSettings,
    ) -> Result<Self, SnapshotError> {
        settings.validate()?;
        let geometry = settings.geometry();
        ranges.validate_in(&geometry)?;
        if n_cases == 0 {
            return Err(SnapshotError::field("cases", 0, "at least 1 case"));
        }
        let sampled = ranges.sampled_effects()?;
        let dims = 6 + sampled.len();
        let u = unit_lhs(n_cases, dims, seed);
        let mut order: Vec<usize> = (0..n_cases).collect();
        order.sort_by(|&a, &b| u[[a, 0]].total_cmp(&u[[b, 0]]).then(a.cmp(&b)));
        let mut stratum = vec![0; n_cases];
        let m = ranges.n_bellows.len();
        for (rank, &i) in order.iter().enumerate() {
            stratum[i] = rank * m / n_cases;
        }
        let cases = (0..n_cases)
            .map(|i| {
                let n = ranges.n_bellows[stratum[i]];
                let x = [u[[i, 1]], u[[i, 2]], u[[i, 3]], u[[i, 4]], u[[i, 5]]];
                let v: Vec<f64> = (6..dims).map(|d| u[[i, d]]).collect();
                let t_max = max_wall_thickness_in(&geometry, n);
                ranges
                    .case_at(i, n, t_max, x, &sampled, &v)
                    .map_err(|e| SnapshotError::field("ranges.effects", &e, "values in range"))
            })
            .collect::<Result<_, _>>()?;
        let sampler = if sampled.is_empty() {
            SAMPLER.to_owned()
        } else {
            let names: Vec<&str> = sampled.iter().map(|(e, _)| e.name()).collect();
            format!(
                "egobox-doe 0.35 Lhs(Optimized: maximin ESE) on [0,1]^{dims} (N, T, mu0, s, alpha1, \
                 alpha2, {}), Xoshiro256Plus::seed_from_u64(seed); N stratified by rank",
                names.join(", ")
            )
        };
        let plan = Self {
            format_version: FORMAT_VERSION,
            seed,
            sampler,
            ranges,
            settings,
            cases,
        };
        plan.validate()?;
        Ok(plan)
    }

    /// A plan of `k` of this plan's cases (same ids and inputs) with other mesh settings: the
    /// high-fidelity subset of a multi-fidelity training set, whose cases pair one to one with
    /// the low-fidelity ones.
    ///
    /// Cases are picked greedily for the largest distance to those already picked (maximin) in
    /// the unit box of `(N, T, ln μ0, s, α1, α2)` over the plan's ranges, taking the values of
    /// `N` in turn; the first is the case nearest the centre. Deterministic: ties go to the
    /// smaller id.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] for `k = 0` or `k` larger than the plan, or bad settings.
    pub fn subset(&self, k: usize, mesh: MeshOptions) -> Result<Self, SnapshotError> {
        if k == 0 || k > self.cases.len() {
            return Err(SnapshotError::field(
                "cases",
                k,
                &format!("1 ..= {} (the cases of the plan)", self.cases.len()),
            ));
        }
        let r = &self.ranges;
        let coords: Vec<[f64; 6]> = self.cases.iter().map(|c| r.unit_coordinates(c)).collect();
        let dist2 = |a: &[f64; 6], b: &[f64; 6]| -> f64 {
            a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
        };
        // smallest squared distance of each case to the picked ones (centre before the first)
        let mut nearest: Vec<f64> = coords.iter().map(|c| -dist2(c, &[0.5; 6])).collect();
        let mut picked = vec![false; self.cases.len()];
        let mut chosen = Vec::with_capacity(k);
        let mut turn = 0;
        while chosen.len() < k {
            let n = r.n_bellows[turn % r.n_bellows.len()];
            turn += 1;
            let best = (0..self.cases.len())
                .filter(|&i| !picked[i] && self.cases[i].n_bellows == n)
                .max_by(|&a, &b| {
                    nearest[a]
                        .total_cmp(&nearest[b])
                        .then(self.cases[b].id.cmp(&self.cases[a].id))
                });
            let Some(i) = best else {
                continue;
            };
            picked[i] = true;
            chosen.push(i);
            for (j, c) in coords.iter().enumerate() {
                let d = dist2(c, &coords[i]);
                nearest[j] = if chosen.len() == 1 {
                    d
                } else {
                    nearest[j].min(d)
                };
            }
        }
        chosen.sort_by_key(|&i| self.cases[i].id);
        let plan = Self {
            format_version: FORMAT_VERSION,
            seed: self.seed,
            sampler: format!(
                "subset of plan {} ({} cases): greedy maximin in the unit box of (N, T, ln mu0, s, \
                 alpha1, alpha2), N in turn; parent sampler: {}",
                self.hash(),
                self.cases.len(),
                self.sampler
            ),
            ranges: self.ranges.clone(),
            settings: PlanSettings {
                mesh,
                ..self.settings.clone()
            },
            cases: chosen.iter().map(|&i| self.cases[i].clone()).collect(),
        };
        plan.validate()?;
        Ok(plan)
    }
}
