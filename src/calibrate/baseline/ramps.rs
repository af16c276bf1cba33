//! The ramps of a sweep: the bending and blocked-force ramp of every design, read from the
//! cache when it holds them and run otherwise (in parallel, the costliest first, cold or from
//! a warm pool, with sensitivities when asked for), on the FE campaign runner
//! ([`crate::fe::runner`]: its keyed ramp cache, [`Start::Cold`] or [`Start::Pool`]).

use std::path::Path;

use super::cache::BaselineError;
use super::settings::{SweepDesign, SweepSettings};
use crate::fe::runner::{Batch, Link, Obtained, Ramp, RampCase, RampDir, Start};
use crate::fe::sensitivity::Sensitivities;
use crate::fe::simulate::{Mode, SimulateError, StepResult};

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
    let jobs: Vec<(&SweepDesign, Mode)> = designs
        .iter()
        .flat_map(|d| {
            std::iter::once((d, Mode::Bending)).chain(settings.force.then_some((d, Mode::Force)))
        })
        .collect();
    let cases = jobs
        .iter()
        .map(|&(d, mode)| {
            let case = settings.case(
                d.n_bellows,
                d.wall_thickness_mm,
                d.pressures_bar.clone(),
                mode,
            )?;
            Ok(RampCase {
                case,
                point: settings.warm_point.clone(),
                sensitivities: settings.sensitivities.clone(),
            })
        })
        .collect::<Result<Vec<_>, SimulateError>>()?;
    let store = match (cache, compute) {
        (Some(dir), true) => Some(RampDir::create(dir)?),
        (Some(dir), false) => Some(RampDir::at(dir)),
        (None, _) => None,
    };
    let batch = Batch::look_up(&cases, &store)?;
    let sweep_ramp = |i: usize, ramp: Ramp, source: RampSource| SweepRamp {
        n_bellows: jobs[i].0.n_bellows,
        wall_thickness_mm: jobs[i].0.wall_thickness_mm,
        mode: jobs[i].1,
        steps: ramp.steps,
        error: ramp.error.unwrap_or_default(),
        source,
        sensitivities: ramp.sensitivities,
    };
    if !compute {
        let missing = || Ramp {
            error: Some("not in the cache".into()),
            ..Ramp::default()
        };
        return Ok(batch
            .into_held()
            .into_iter()
            .enumerate()
            .map(|(i, held)| match held {
                Some(ramp) => sweep_ramp(i, ramp, RampSource::Cache),
                None => sweep_ramp(i, missing(), RampSource::Missing),
            })
            .collect());
    }
    let held = batch.held_count();
    for k in 1..=held {
        progress(k, jobs.len());
    }
    let start = settings.warm.clone().map_or(Start::Cold, Start::Pool);
    let order = Link::independent(&cost_order(&jobs));
    let reports = batch.run(&order, &start, |t, _| progress(t.held + t.ran, t.cases))?;
    Ok(reports
        .into_iter()
        .map(|r| match r.obtained {
            Obtained::Cache(ramp) => sweep_ramp(r.case, ramp, RampSource::Cache),
            Obtained::Run(ramp) | Obtained::Failed { ramp, .. } => {
                sweep_ramp(r.case, ramp, RampSource::Run)
            }
        })
        .collect())
}

/// The ramps of a sweep in the order their FE is expected to cost, largest first: thin walls
/// first (their bellows touch earliest and longest), then more bellows, the blocked force
/// before the bending of a design. Starting the longest ramps first keeps both cores busy to
/// the end of a sweep instead of leaving one ramp running alone.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn cost_order(jobs: &[(&SweepDesign, Mode)]) -> Vec<usize> {
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
