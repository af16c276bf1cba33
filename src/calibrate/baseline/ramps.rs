//! The ramps of a sweep: the bending and blocked-force ramp of every design, read from the
//! cache when it holds them and run otherwise (in parallel, the costliest first, cold or from
//! a warm pool, with sensitivities when asked for).

use std::path::Path;

use super::cache::{BaselineError, RampCache, RampOutcome};
use super::settings::{SweepDesign, SweepSettings};
use crate::fe::campaign::WarmPool;
use crate::fe::sensitivity::{
    sensitivities_with, sensitivities_with_fields, Parameter, Sensitivities,
};
use crate::fe::simulate::{simulate_with, Case, Mode, StepResult};

/// Where a ramp of a sweep came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RampSource {
    /// Run now (and cached, with a cache).
    Run,
    /// Read from the cache.
    Cache,
    /// Neither: not in the cache and not computed ([`cached_ramps`]).
    Missing,
}

/// One ramp of a sweep: the steps reached and the solver's message if it stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRamp {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Bending or blocked force.
    pub mode: Mode,
    /// The steps reached, in pressure order.
    pub steps: Vec<StepResult>,
    /// Why the ramp stopped early (empty if it did not).
    pub error: String,
    /// Run now or read from the cache.
    pub source: RampSource,
    /// The sensitivities of the steps, if the sweep asked for them and the ramp finished.
    pub sensitivities: Option<Sensitivities>,
}

impl SweepRamp {
    /// The step at pressure `p` (bar), if reached.
    pub fn at(&self, p: f64) -> Option<&StepResult> {
        self.steps
            .iter()
            .find(|s| (s.pressure_bar - p).abs() < 1e-9)
    }
}

/// The bending and blocked-force ramps of every design, each read from `cache` when it holds
/// the same ramp (same key) and run otherwise (then written there atomically, so an
/// interrupted sweep resumes); `progress(done, total)` after every ramp. Ramps run in
/// parallel (rayon); the result lists each design's bending ramp, then its force ramp.
///
/// # Errors
/// An invalid design; a cache directory that cannot be written.
pub fn run_ramps(
    settings: &SweepSettings,
    designs: &[SweepDesign],
    cache: Option<&Path>,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<Vec<SweepRamp>, BaselineError> {
    sweep(settings, designs, cache, true, progress)
}

/// [`run_ramps`] from `cache` only: a ramp not there is [`RampSource::Missing`] with no step
/// and the error `not in the cache`.
///
/// # Errors
/// An invalid design.
pub fn cached_ramps(
    settings: &SweepSettings,
    designs: &[SweepDesign],
    cache: &Path,
) -> Result<Vec<SweepRamp>, BaselineError> {
    sweep(settings, designs, Some(cache), false, |_, _| {})
}

fn sweep(
    settings: &SweepSettings,
    designs: &[SweepDesign],
    cache: Option<&Path>,
    compute: bool,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<Vec<SweepRamp>, BaselineError> {
    if let (Some(dir), true) = (cache, compute) {
        std::fs::create_dir_all(dir).map_err(|e| BaselineError::cache(dir, e))?;
    }
    let jobs: Vec<(&SweepDesign, Mode)> = designs
        .iter()
        .flat_map(|d| [(d, Mode::Bending), (d, Mode::Force)])
        .collect();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<Result<SweepRamp, BaselineError>> =
        longest_first(&jobs, &cost_order(&jobs), |&(d, mode)| {
            let case = settings.case(
                d.n_bellows,
                d.wall_thickness_mm,
                d.pressures_bar.clone(),
                mode,
            )?;
            let cached = cache.map(|dir| RampCache::at(dir, &case, &settings.sensitivities));
            let (steps, error, sensitivities, source) =
                match cached.as_ref().and_then(RampCache::load) {
                    Some((steps, error, sens)) => (steps, error, sens, RampSource::Cache),
                    None if !compute => (
                        Vec::new(),
                        "not in the cache".to_string(),
                        None,
                        RampSource::Missing,
                    ),
                    None => {
                        let r = match &settings.warm {
                            Some(pool) => run_warm_ramp(&case, settings, pool),
                            None => run_ramp(&case, &settings.sensitivities),
                        };
                        if let Some(c) = &cached {
                            c.store(&r)?;
                        }
                        (r.0, r.1, r.2, RampSource::Run)
                    }
                };
            let k = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
            progress(k, jobs.len());
            Ok(SweepRamp {
                n_bellows: d.n_bellows,
                wall_thickness_mm: d.wall_thickness_mm,
                mode,
                steps,
                error,
                source,
                sensitivities,
            })
        });
    results.into_iter().collect()
}

/// The ramps of a sweep in the order their FE is expected to cost, largest first: thin walls
/// first (their bellows touch earliest and longest), then more bellows, the blocked force
/// before the bending of a design. Starting the longest ramps first keeps both cores busy to
/// the end of a sweep instead of leaving one ramp running alone.
pub(super) fn cost_order(jobs: &[(&SweepDesign, Mode)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| {
        let (da, ma) = jobs[a];
        let (db, mb) = jobs[b];
        da.wall_thickness_mm
            .total_cmp(&db.wall_thickness_mm)
            .then(db.n_bellows.cmp(&da.n_bellows))
            .then((mb == Mode::Force).cmp(&(ma == Mode::Force)))
            .then(a.cmp(&b))
    });
    order
}

/// `f` of every item on the threads of the current rayon pool, started in the order `order`
/// (a shared queue: each thread takes the next item when it is free), the results in item
/// order. Each item's result does not depend on which thread ran it or when.
pub(super) fn longest_first<T: Sync, R: Send>(
    items: &[T],
    order: &[usize],
    f: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    let workers = rayon::current_num_threads().clamp(1, items.len().max(1));
    rayon::scope(|s| {
        for _ in 0..workers {
            s.spawn(|_| loop {
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some(&i) = order.get(k) else { break };
                let r = f(&items[i]);
                *slots[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
            });
        }
    });
    slots
        .into_iter()
        .map(|m| {
            m.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every item of the queue ran")
        })
        .collect()
}

/// One ramp of a sweep: the steps it reached and why it stopped, with the sensitivities to
/// `parameters` if any are asked for (and the ramp finished).
fn run_ramp(case: &Case, parameters: &[Parameter]) -> RampOutcome {
    let mut steps = Vec::new();
    if parameters.is_empty() {
        let outcome = simulate_with(case, |_, _| {}, |_, r, _| steps.push(r.clone()));
        return (
            steps,
            outcome.err().map_or(String::new(), |e| e.to_string()),
            None,
        );
    }
    match sensitivities_with(case, parameters, |_, _| {}, |_, r, _| steps.push(r.clone())) {
        Ok((_, sens)) => (steps, String::new(), Some(sens)),
        Err(e) => (steps, e.to_string(), None),
    }
}

/// [`run_ramp`] started from `pool`'s ramp of the same design and rig, kept there for the
/// next iteration.
fn run_warm_ramp(case: &Case, settings: &SweepSettings, pool: &WarmPool) -> RampOutcome {
    let warm = pool.start_for(case, &settings.warm_point);
    let mut steps = Vec::new();
    match sensitivities_with_fields(
        case,
        &settings.sensitivities,
        warm.as_ref(),
        |_, _| {},
        |_, r, _| steps.push(r.clone()),
    ) {
        Ok(ran) => {
            let sens = (!settings.sensitivities.is_empty()).then(|| ran.sensitivities.clone());
            pool.keep(case, settings.warm_point.clone(), ran);
            (steps, String::new(), sens)
        }
        Err(e) => (steps, e.to_string(), None),
    }
}
