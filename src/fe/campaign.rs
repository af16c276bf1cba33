//! A campaign of FE ramps at nearby parameter points, each started from a near neighbour that
//! was solved before it ([`super::warm_start`]).
//!
//! **Order.** Cases of the same model (design, mesh, rig and contact: the same unknowns) form a
//! group; within a group the cases are linked by a minimum spanning tree of their parameter
//! points (Prim's algorithm, distances in units of each coordinate's `scale`), grown from the
//! case nearest the group's centroid. Each case then starts from its tree parent, the nearest
//! case already grown when it joined; the tree's edges sum to the least total distance, so
//! the starts are as near as any order allows. The first case of a group starts cold.
//!
//! **Both cores.** The cases run on the FE campaign runner ([`super::runner`], nothing
//! stored, [`Start::Tree`]): on the threads of the current rayon pool (one ramp per thread;
//! run with `RAYON_NUM_THREADS` = cores). A thread takes the next case, in the order
//! the trees grew, whose parent has finished; the first cases of the groups, and the branches
//! of a tree, run side by side. A case whose parent failed starts cold. Each case's answer
//! does not depend on which thread ran it or when: only on its parent, which the tree fixes.
//!
//! **First order.** With [`WarmOrder::First`] every ramp also computes the displacement
//! sensitivities to the campaign's parameters ([`crate::fe::sensitivity`], 15–20 % of a
//! cold ramp), and its children start from its states moved by `(∂u/∂θ) Δθ`. With
//! [`WarmOrder::Zeroth`] they start from the states as they are: on a material step of 5 %
//! the first order saves one iteration in about eight (`examples/warm_start.rs`), less than the
//! sensitivities cost once the ramps are warm, so it pays only where the sensitivities are
//! wanted anyway (a calibration's iterations).

use std::time::Instant;

use super::runner::{
    spanning_order, Batch, CaseReport, NoStore, Obtained, Ramp, RampCase, Start, Tally,
};
use super::sensitivity::Parameter;
use super::simulate::{Case, Response};
use crate::case::OgdenSet;

pub use super::runner::{Link, WarmOrder, WarmPool};

/// One case of a campaign and its parameter point.
#[derive(Clone, Debug)]
pub struct CampaignCase {
    /// The case.
    pub case: Case,
    /// Its parameter point, one value per campaign parameter ([`Campaign::parameters`]).
    pub point: Vec<f64>,
}

/// A campaign: its cases, its parameters and how the cases start.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// The cases.
    pub cases: Vec<CampaignCase>,
    /// The parameters of the points (the sensitivities' parameters with [`WarmOrder::First`]).
    pub parameters: Vec<Parameter>,
    /// The distance scale of each parameter (its unit in the ordering's metric).
    pub scales: Vec<f64>,
    /// How the cases start.
    pub warm: WarmOrder,
}

/// A campaign that cannot run.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CampaignError {
    /// A point or the scales do not have one value per parameter.
    #[error("{what} has {got} values, expected one per parameter ({expected})")]
    Dimensions {
        /// Which vector.
        what: String,
        /// Its length.
        got: usize,
        /// The number of parameters.
        expected: usize,
    },
    /// A scale is not positive, or a coordinate not finite.
    #[error("{what} is {value}: expected a finite{positive} number")]
    Value {
        /// Which value.
        what: String,
        /// It.
        value: f64,
        /// " positive" for a scale.
        positive: &'static str,
    },
}

/// How one case of a campaign ran.
#[derive(Clone, Debug)]
pub struct CampaignRamp {
    /// Its index in [`Campaign::cases`].
    pub case: usize,
    /// The case it started from (`None`: cold).
    pub parent: Option<usize>,
    /// The ramp's results, or why it stopped.
    pub response: Result<Response, String>,
    /// Wall time of the ramp, sensitivities included (s).
    pub wall_s: f64,
}

impl Campaign {
    /// Checks the points and scales.
    ///
    /// # Errors
    /// A point or the scales of the wrong length; a scale that is not positive; a coordinate
    /// that is not finite.
    pub fn validate(&self) -> Result<(), CampaignError> {
        let n = self.parameters.len();
        let dims = |what: String, got: usize| {
            if got == n {
                Ok(())
            } else {
                Err(CampaignError::Dimensions {
                    what,
                    got,
                    expected: n,
                })
            }
        };
        dims("scales".into(), self.scales.len())?;
        for (j, &s) in self.scales.iter().enumerate() {
            if !(s.is_finite() && s > 0.0) {
                return Err(CampaignError::Value {
                    what: format!("scales[{j}]"),
                    value: s,
                    positive: " positive",
                });
            }
        }
        for (i, c) in self.cases.iter().enumerate() {
            dims(format!("cases[{i}].point"), c.point.len())?;
            if let Some((j, &v)) = c.point.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(CampaignError::Value {
                    what: format!("cases[{i}].point[{j}]"),
                    value: v,
                    positive: "",
                });
            }
        }
        Ok(())
    }

    /// The order the cases run in, each with the case it starts from (module docs); all roots
    /// with [`WarmOrder::Cold`].
    pub fn order(&self) -> Vec<Link> {
        let cases: Vec<(&Case, &[f64])> = self
            .cases
            .iter()
            .map(|c| (&c.case, c.point.as_slice()))
            .collect();
        let mut out = spanning_order(&cases, &self.scales);
        if self.warm == WarmOrder::Cold {
            for l in &mut out {
                l.parent = None;
            }
        }
        out
    }

    /// Runs every case (module docs) on the FE campaign runner ([`super::runner`], from the
    /// tree parents, nothing stored), calling `progress(done, total, ramp)` as each finishes.
    ///
    /// # Errors
    /// An invalid campaign, before any FE.
    pub fn run(
        &self,
        progress: impl Fn(usize, usize, &CampaignRamp) + Sync,
    ) -> Result<Vec<CampaignRamp>, CampaignError> {
        self.validate()?;
        let sensitivities = if self.warm == WarmOrder::First {
            self.parameters.clone()
        } else {
            Vec::new()
        };
        let cases: Vec<RampCase> = self
            .cases
            .iter()
            .map(|c| RampCase {
                case: c.case.clone(),
                point: c.point.clone(),
                sensitivities: sensitivities.clone(),
            })
            .collect();
        let store = NoStore::new();
        let Ok(batch) = Batch::look_up(&cases, &store);
        let start = Start::Tree(self.warm);
        let progress = |t: &Tally, r: &CaseReport<Ramp, Ramp>| {
            progress(t.ran, t.to_run, &campaign_ramp(r));
        };
        let Ok(reports) = batch.run(&self.order(), &start, progress);
        Ok(reports.iter().map(campaign_ramp).collect())
    }
}

/// How a case of the campaign ran, from the runner's report.
fn campaign_ramp(r: &CaseReport<Ramp, Ramp>) -> CampaignRamp {
    let response = match &r.obtained {
        Obtained::Run(ramp) | Obtained::Cache(ramp) => ramp
            .response
            .clone()
            .ok_or_else(|| "the ramp has no solver account".to_string()),
        Obtained::Failed { message, .. } => Err(message.clone()),
    };
    CampaignRamp {
        case: r.case,
        parent: r.parent,
        response,
        wall_s: r.wall_s,
    }
}

/// The material-sweep benchmark of warm starts ([`bench_material_sweep`]).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SweepBench {
    /// What was run.
    pub description: String,
    /// The materials (in the file: `[μ₁, α₁, μ₂, α₂]` each).
    #[serde(with = "crate::case::material::arrays")]
    pub materials: Vec<OgdenSet>,
    /// The designs `(N, T)`.
    pub designs: Vec<(usize, f64)>,
    /// Worker threads.
    pub threads: usize,
    /// One row per way of starting.
    pub rows: Vec<BenchRow>,
}

/// One way of starting a campaign, measured.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BenchRow {
    /// How the cases started.
    pub warm: WarmOrder,
    /// Ramps that finished.
    pub ramps: usize,
    /// Ramps that started from a neighbour.
    pub warm_ramps: usize,
    /// Newton iterations over all ramps (augmented re-solves and failed warm attempts
    /// included).
    pub newton_iterations: usize,
    /// Output levels over all ramps (the self-weight state and each pressure).
    pub output_levels: usize,
    /// `newton_iterations / output_levels`.
    pub iterations_per_level: f64,
    /// Mean Newton iterations at each output level of a ramp (0, then each pressure).
    pub iterations_per_level_by_pressure: Vec<f64>,
    /// Tangent factorisations.
    pub factorizations: usize,
    /// Wall time of the campaign (s).
    pub wall_s: f64,
    /// Sum of the ramps' wall times (s).
    pub ramp_s: f64,
    /// `wall_s` over the cold row's.
    pub wall_ratio: f64,
    /// Largest tip difference from the cold ramp, relative to the cold tip displacement.
    pub max_tip_difference: f64,
    /// Largest blocked-force difference from the cold ramp (N).
    pub max_force_difference_n: f64,
    /// Each ramp: its case, the case it started from, its Newton iterations and wall time.
    #[serde(default)]
    pub each: Vec<RampRow>,
}

/// One ramp of a benchmark row.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct RampRow {
    /// Its index in the campaign (designs outer, materials inner).
    pub case: usize,
    /// The case it started from (`None`: cold).
    pub parent: Option<usize>,
    /// Newton iterations per output level.
    pub newton_iterations: Vec<usize>,
    /// Wall time of the ramp (sensitivities included) (s).
    pub wall_s: f64,
    /// Why it stopped, if it did not finish.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// The materials of the benchmark: `count` points of a seeded Latin hypercube around the set
/// `centre`, `μ0` scaled by a factor log-uniform in `[1/(1+span), 1+span]` (μ₁ and μ₂
/// together) and `α₁` by one uniform in `[1 − span/2, 1 + span/2]`.
pub fn bench_materials(centre: OgdenSet, count: usize, span: f64, seed: u64) -> Vec<OgdenSet> {
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let centre = centre.as_array();
    let mut strata: [Vec<usize>; 2] = [(0..count).collect(), (0..count).collect()];
    for s in &mut strata {
        s.shuffle(&mut rng);
    }
    (0..count)
        .map(|i| {
            let u: [f64; 2] =
                [0, 1].map(|d| (strata[d][i] as f64 + rng.gen::<f64>()) / count as f64);
            let mu = ((1.0 + span).ln() * (2.0 * u[0] - 1.0)).exp();
            let alpha = 1.0 + span * (u[1] - 0.5);
            OgdenSet::from_array([centre[0] * mu, centre[1] * alpha, centre[2] * mu, centre[3]])
        })
        .collect()
}

/// Runs `cases(material, design)` for every material and design three ways (cold, warm from
/// the neighbour's states, warm moved by first-order sensitivities) and measures each
/// against the cold one; `progress(row, done, total)` as ramps finish.
///
/// # Errors
/// An invalid campaign.
pub fn bench_material_sweep(
    materials: &[OgdenSet],
    designs: &[(usize, f64)],
    case: impl Fn(OgdenSet, (usize, f64)) -> Case,
    orders: &[WarmOrder],
    progress: impl Fn(WarmOrder, usize, usize) + Sync,
) -> Result<SweepBench, CampaignError> {
    use super::sensitivity::OgdenParameter;
    let parameters = [
        OgdenParameter::Mu1,
        OgdenParameter::Alpha1,
        OgdenParameter::Mu2,
        OgdenParameter::Alpha2,
    ]
    .map(Parameter::Material)
    .to_vec();
    let centre = materials
        .first()
        .map(OgdenSet::as_array)
        .unwrap_or_default();
    let cases: Vec<CampaignCase> = designs
        .iter()
        .flat_map(|&d| materials.iter().map(move |&m| (m, d)))
        .map(|(m, d)| CampaignCase {
            case: case(m, d),
            point: m.as_array().to_vec(),
        })
        .collect();
    let mut rows: Vec<BenchRow> = Vec::new();
    let mut cold: Option<Vec<CampaignRamp>> = None;
    for &warm in orders {
        let campaign = Campaign {
            cases: cases.clone(),
            parameters: parameters.clone(),
            scales: centre.iter().map(|v| v.abs().max(1e-3)).collect(),
            warm,
        };
        let start = Instant::now();
        let ramps = campaign.run(|done, total, _| progress(warm, done, total))?;
        let wall_s = start.elapsed().as_secs_f64();
        let mut row = measure(warm, &ramps, wall_s, cold.as_deref());
        row.wall_ratio = rows.first().map_or(1.0, |c| wall_s / c.wall_s);
        rows.push(row);
        if cold.is_none() {
            cold = Some(ramps);
        }
    }
    Ok(SweepBench {
        description: format!(
            "{} materials x {} designs; rows: how the ramps started (the first row is the \
             reference the differences are taken from)",
            materials.len(),
            designs.len()
        ),
        materials: materials.to_vec(),
        designs: designs.to_vec(),
        threads: rayon::current_num_threads(),
        rows,
    })
}

fn measure(
    warm: WarmOrder,
    ramps: &[CampaignRamp],
    wall_s: f64,
    reference: Option<&[CampaignRamp]>,
) -> BenchRow {
    let ok: Vec<(&CampaignRamp, &Response)> = ramps
        .iter()
        .filter_map(|r| r.response.as_ref().ok().map(|x| (r, x)))
        .collect();
    let levels = ok.iter().map(|(_, r)| r.steps.len()).max().unwrap_or(0);
    let mut by_level = vec![(0.0, 0usize); levels];
    for (_, r) in &ok {
        for (k, s) in r.steps.iter().enumerate() {
            by_level[k].0 += s.newton_iterations as f64;
            by_level[k].1 += 1;
        }
    }
    let newton_iterations = ok
        .iter()
        .flat_map(|(_, r)| &r.steps)
        .map(|s| s.newton_iterations)
        .sum::<usize>();
    let output_levels = ok.iter().map(|(_, r)| r.steps.len()).sum::<usize>();
    let (mut tip, mut force) = (0.0f64, 0.0f64);
    if let Some(reference) = reference {
        for (r, resp) in &ok {
            let Some(Ok(c)) = reference
                .iter()
                .find(|c| c.case == r.case)
                .map(|c| &c.response)
            else {
                continue;
            };
            for (a, b) in resp.steps.iter().zip(&c.steps) {
                let d = (a.tip_uz_mm - b.tip_uz_mm).hypot(a.tip_uy_mm - b.tip_uy_mm);
                tip = tip.max(d / b.tip_uz_mm.hypot(b.tip_uy_mm).max(1e-9));
                if let (Some(fa), Some(fb)) = (a.force_n, b.force_n) {
                    force = force.max((fa - fb).abs());
                }
            }
        }
    }
    BenchRow {
        warm,
        ramps: ok.len(),
        warm_ramps: ok.iter().filter(|(r, _)| r.parent.is_some()).count(),
        newton_iterations,
        output_levels,
        iterations_per_level: newton_iterations as f64 / output_levels.max(1) as f64,
        iterations_per_level_by_pressure: by_level
            .iter()
            .map(|(s, n)| s / (*n).max(1) as f64)
            .collect(),
        factorizations: ok.iter().map(|(_, r)| r.factorizations).sum(),
        wall_s,
        ramp_s: ramps.iter().map(|r| r.wall_s).sum(),
        wall_ratio: 1.0,
        max_tip_difference: tip,
        max_force_difference_n: force,
        each: ramps
            .iter()
            .map(|r| RampRow {
                case: r.case,
                parent: r.parent,
                newton_iterations: r.response.as_ref().map_or_else(
                    |_| Vec::new(),
                    |x| x.steps.iter().map(|s| s.newton_iterations).collect(),
                ),
                wall_s: r.wall_s,
                error: r.response.as_ref().err().cloned(),
            })
            .collect(),
    }
}
