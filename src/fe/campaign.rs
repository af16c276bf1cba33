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
//! **Both cores.** The cases run on the threads of the current rayon pool (one ramp per
//! thread; run with `RAYON_NUM_THREADS` = cores). A thread takes the next case, in the order
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

use std::collections::BTreeMap;
use std::sync::{Condvar, Mutex};
use std::time::Instant;

use super::sensitivity::{sensitivities_with_fields, Parameter, WithFields};
use super::simulate::{Case, Response};
use super::warm_start::WarmStart;

/// How the cases of a campaign start.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WarmOrder {
    /// From the undeformed actuator (every ramp independent).
    Cold,
    /// From the tree parent's converged states.
    Zeroth,
    /// From the tree parent's states moved by their displacement sensitivities.
    First,
}

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

/// One link of the campaign's order: a case and the case it starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Link {
    /// The case.
    pub case: usize,
    /// Its tree parent (`None`: the root of its group).
    pub parent: Option<usize>,
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
        let mut groups: BTreeMap<String, Vec<usize>> = BTreeMap::new();
        for (i, c) in self.cases.iter().enumerate() {
            groups.entry(model_key(&c.case)).or_default().push(i);
        }
        let mut out = Vec::with_capacity(self.cases.len());
        for members in groups.values() {
            out.extend(self.tree(members));
        }
        if self.warm == WarmOrder::Cold {
            for l in &mut out {
                l.parent = None;
            }
        }
        out
    }

    /// Prim's minimum spanning tree of `members`, from the one nearest their centroid, in
    /// the order the cases join.
    fn tree(&self, members: &[usize]) -> Vec<Link> {
        let dist = |a: usize, b: usize| {
            let (pa, pb) = (&self.cases[a].point, &self.cases[b].point);
            pa.iter()
                .zip(pb)
                .zip(&self.scales)
                .map(|((x, y), s)| ((x - y) / s).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let dim = self.scales.len();
        let mut centroid = vec![0.0; dim];
        for &m in members {
            for (c, v) in centroid.iter_mut().zip(&self.cases[m].point) {
                *c += v / members.len() as f64;
            }
        }
        let to_centroid = |m: usize| {
            self.cases[m]
                .point
                .iter()
                .zip(&centroid)
                .zip(&self.scales)
                .map(|((x, y), s)| ((x - y) / s).powi(2))
                .sum::<f64>()
        };
        let Some(root) = members
            .iter()
            .copied()
            .min_by(|&a, &b| to_centroid(a).total_cmp(&to_centroid(b)).then(a.cmp(&b)))
        else {
            return Vec::new();
        };
        let mut links = vec![Link {
            case: root,
            parent: None,
        }];
        // best[k]: (distance to the tree, nearest tree member) of members[k] not yet in it
        let mut best: Vec<Option<(f64, usize)>> = members
            .iter()
            .map(|&m| (m != root).then(|| (dist(m, root), root)))
            .collect();
        while let Some(k) = (0..members.len())
            .filter(|&k| best[k].is_some())
            .min_by(|&a, &b| {
                let (da, db) = (best[a].map_or(0.0, |b| b.0), best[b].map_or(0.0, |b| b.0));
                da.total_cmp(&db).then(members[a].cmp(&members[b]))
            })
        {
            let (_, parent) = best[k].take().expect("filtered on is_some");
            let m = members[k];
            links.push(Link {
                case: m,
                parent: Some(parent),
            });
            for (j, b) in best.iter_mut().enumerate() {
                if let Some((d, p)) = b {
                    let dn = dist(members[j], m);
                    if dn < *d {
                        *d = dn;
                        *p = m;
                    }
                }
            }
        }
        links
    }

    /// Runs every case (module docs), calling `progress(done, total, ramp)` as each finishes.
    ///
    /// # Errors
    /// An invalid campaign, before any FE.
    pub fn run(
        &self,
        progress: impl Fn(usize, usize, &CampaignRamp) + Sync,
    ) -> Result<Vec<CampaignRamp>, CampaignError> {
        self.validate()?;
        let order = self.order();
        let n = order.len();
        let sensitivities: &[Parameter] = if self.warm == WarmOrder::First {
            &self.parameters
        } else {
            &[]
        };
        struct Board {
            taken: Vec<bool>,
            finished: Vec<bool>,
            kept: Vec<Option<std::sync::Arc<WithFields>>>,
            ramps: Vec<Option<CampaignRamp>>,
            done: usize,
        }
        let board = Mutex::new(Board {
            taken: vec![false; n],
            finished: vec![false; self.cases.len()],
            kept: vec![None; self.cases.len()],
            ramps: vec![None; self.cases.len()],
            done: 0,
        });
        let ready = Condvar::new();
        let workers = rayon::current_num_threads().clamp(1, n.max(1));
        rayon::scope(|s| {
            for _ in 0..workers {
                s.spawn(|_| loop {
                    // the next case, in order, whose parent has finished
                    let (k, parent) = {
                        let mut b = board.lock().unwrap_or_else(|e| e.into_inner());
                        loop {
                            let next = (0..n).find(|&k| {
                                !b.taken[k] && order[k].parent.is_none_or(|p| b.finished[p])
                            });
                            if let Some(k) = next {
                                b.taken[k] = true;
                                let parent = order[k].parent.map(|p| (p, b.kept[p].clone()));
                                break (k, parent);
                            }
                            if b.taken.iter().all(|&t| t) {
                                return;
                            }
                            b = ready.wait(b).unwrap_or_else(|e| e.into_inner());
                        }
                    };
                    let link = order[k];
                    let (ramp, kept) = self.run_one(link.case, parent.as_ref(), sensitivities);
                    let mut b = board.lock().unwrap_or_else(|e| e.into_inner());
                    b.finished[link.case] = true;
                    b.kept[link.case] = kept.map(std::sync::Arc::new);
                    b.done += 1;
                    progress(b.done, n, &ramp);
                    b.ramps[link.case] = Some(ramp);
                    ready.notify_all();
                });
            }
        });
        let b = board.into_inner().unwrap_or_else(|e| e.into_inner());
        Ok(b.ramps.into_iter().flatten().collect())
    }

    /// One case from its parent's kept states (if it finished with them).
    fn run_one(
        &self,
        i: usize,
        parent: Option<&(usize, Option<std::sync::Arc<WithFields>>)>,
        sensitivities: &[Parameter],
    ) -> (CampaignRamp, Option<WithFields>) {
        let start = Instant::now();
        let from = parent.and_then(|(p, kept)| kept.as_ref().map(|k| (*p, k)));
        let warm = from.and_then(|(p, k)| match self.warm {
            WarmOrder::Cold => None,
            WarmOrder::Zeroth => Some(WarmStart::new(k.states.clone())),
            WarmOrder::First => {
                let delta: Vec<f64> = self.cases[i]
                    .point
                    .iter()
                    .zip(&self.cases[p].point)
                    .map(|(a, b)| a - b)
                    .collect();
                k.warm_start(&delta).ok()
            }
        });
        let ran = sensitivities_with_fields(
            &self.cases[i].case,
            sensitivities,
            warm.as_ref(),
            |_, _| {},
            |_, _, _| {},
        );
        let wall_s = start.elapsed().as_secs_f64();
        let parent = warm.as_ref().and(from.map(|(p, _)| p));
        match ran {
            Ok(w) => (
                CampaignRamp {
                    case: i,
                    parent,
                    response: Ok(w.response.clone()),
                    wall_s,
                },
                (self.warm != WarmOrder::Cold).then_some(w),
            ),
            Err(e) => (
                CampaignRamp {
                    case: i,
                    parent,
                    response: Err(e.to_string()),
                    wall_s,
                },
                None,
            ),
        }
    }
}

/// The cases that share a model (the same unknowns and contact points): design, mesh, rig,
/// contact settings and gravity.
fn model_key(c: &Case) -> String {
    serde_json::json!({
        "design": c.design.params(),
        "mesh": c.mesh,
        "mode": c.mode,
        "contact": c.contact,
    })
    .to_string()
}

/// The material-sweep benchmark of warm starts ([`bench_material_sweep`]).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SweepBench {
    /// What was run.
    pub description: String,
    /// The materials `[μ₁, α₁, μ₂, α₂]`.
    pub materials: Vec<[f64; 4]>,
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

/// The materials of the benchmark: `count` points of a seeded Latin hypercube around `centre`
/// (`[μ₁, α₁, μ₂, α₂]`), `μ0` scaled by a factor log-uniform in `[1/(1+span), 1+span]` (μ₁ and
/// μ₂ together) and `α₁` by one uniform in `[1 − span/2, 1 + span/2]`.
pub fn bench_materials(centre: [f64; 4], count: usize, span: f64, seed: u64) -> Vec<[f64; 4]> {
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
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
            [centre[0] * mu, centre[1] * alpha, centre[2] * mu, centre[3]]
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
    materials: &[[f64; 4]],
    designs: &[(usize, f64)],
    case: impl Fn([f64; 4], (usize, f64)) -> Case,
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
    let centre = materials.first().copied().unwrap_or_default();
    let cases: Vec<CampaignCase> = designs
        .iter()
        .flat_map(|&d| materials.iter().map(move |&m| (m, d)))
        .map(|(m, d)| CampaignCase {
            case: case(m, d),
            point: m.to_vec(),
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

/// A pooled ramp: its parameter point and what it left.
type Pooled = (Vec<f64>, std::sync::Arc<WithFields>);

/// The latest converged ramp of each model in a repeated campaign (a calibration's
/// iterations: the same designs at a new parameter point each time), with its parameter point,
/// to start the next iteration's ramps from. Shared between threads; cloning shares it.
///
/// A ramp is matched by number of bellows, nominal wall thickness, rig, mesh and contact
/// settings: the dimensions being identified may differ (the mesh moves, its unknowns stay
/// the same; a start of another size is not used, [`LevelGuess::fits`](crate::fe::solver::LevelGuess::fits)).
#[derive(Clone, Default)]
pub struct WarmPool {
    inner: std::sync::Arc<Mutex<BTreeMap<String, Pooled>>>,
}

impl std::fmt::Debug for WarmPool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.inner.lock().map_or(0, |m| m.len());
        write!(f, "WarmPool({n} ramps)")
    }
}

/// Two handles are equal when they share the same pool.
impl PartialEq for WarmPool {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.inner, &other.inner)
    }
}

impl WarmPool {
    /// An empty pool.
    pub fn new() -> Self {
        Self::default()
    }

    /// A start for `case` at `point` from the pool's ramp of the same model: its states moved
    /// to `point` by their displacement sensitivities where it has them for every coordinate,
    /// as they are otherwise; `None` if the pool has no such ramp.
    pub fn start_for(&self, case: &Case, point: &[f64]) -> Option<WarmStart> {
        let map = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let (from, ran) = map.get(&pool_key(case))?;
        let delta: Vec<f64> = point.iter().zip(from).map(|(a, b)| a - b).collect();
        if from.len() == point.len() && ran.fields.parameters.len() == point.len() {
            if let Ok(w) = ran.warm_start(&delta) {
                return Some(w);
            }
        }
        Some(WarmStart::new(ran.states.clone()))
    }

    /// Keeps `ran` (of `case` at `point`) as the start of its model's next ramp.
    pub fn keep(&self, case: &Case, point: Vec<f64>, ran: WithFields) {
        let mut map = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        map.insert(pool_key(case), (point, std::sync::Arc::new(ran)));
    }

    /// The number of ramps kept.
    pub fn len(&self) -> usize {
        self.inner.lock().map_or(0, |m| m.len())
    }

    /// Whether it keeps no ramp.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn pool_key(c: &Case) -> String {
    let p = c.design.params();
    serde_json::json!({
        "n": p.n_bellows,
        "t": p.wall_thickness,
        "mesh": c.mesh,
        "mode": c.mode,
        "contact": c.contact,
    })
    .to_string()
}
