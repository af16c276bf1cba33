//! The literature baseline: the full FE model (with contact) against every experimental
//! configuration, for one material set.
//!
//! For each design (N, T) of the shipped experiments, one bending ramp and one blocked-force
//! ramp through 0 and the measured pressures; per (N, T, P) the simulated and measured tip
//! Uz, Uy, angle, the tip bending error `BE` and the force error `F_sim − F_exp`.
//!
//! The settings shared by every ramp ([`SweepSettings`]: material, mesh, contact, effects,
//! solver, gravity) travel together, so an effect of the library ([`crate::fe::effects`])
//! reaches every case of the sweep. [`run_ramps`] is the sweep itself (designs and pressures
//! in, ramps out), for other users of the same cached ramps (twin recordings,
//! [`crate::calibrate::twin`]).
//!
//! With a cache directory every finished ramp is written there atomically (one JSON per design
//! and mode, keyed by everything that defines the ramp), and a later run with the same
//! settings takes it from there: a long standard-mesh sweep resumes after an interruption. A
//! sweep without effects has the key it had before effects existed (the committed caches
//! under `fe_reference/` are read as they are; tested).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::experiments::{bending_error, BendingRecord, ForceRecord};
use crate::fe::campaign::WarmPool;
use crate::fe::effects::Effects;
use crate::fe::geometry::DesignParams;
use crate::fe::material::Material;
use crate::fe::mesh::MeshOptions;
use crate::fe::preset::Geometry;
use crate::fe::sensitivity::{
    sensitivities_with, sensitivities_with_fields, Parameter, Sensitivities,
    SENSITIVITY_FORMAT_VERSION, SENSITIVITY_METHOD,
};
use crate::fe::simulate::{
    simulate_with, Case, ContactSettings, Mode, SimulateError, StepResult, FORCE_MODEL_REVISION,
};
use crate::fe::solver::SolverSettings;

/// One row of the baseline table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaselineRow {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Measured tip Uz (mm).
    pub uz_exp_mm: f64,
    /// Simulated tip Uz (mm).
    pub uz_sim_mm: f64,
    /// Measured tip Uy (mm).
    pub uy_exp_mm: f64,
    /// Simulated tip Uy (mm).
    pub uy_sim_mm: f64,
    /// Measured angle (deg).
    pub angle_exp_deg: f64,
    /// Simulated angle (deg).
    pub angle_sim_deg: f64,
    /// Tip bending error (mm).
    pub be_mm: f64,
    /// Measured blocked force (N).
    pub force_exp_n: f64,
    /// Simulated blocked force (N).
    pub force_sim_n: f64,
    /// `F_sim − F_exp` (N).
    pub force_error_n: f64,
    /// Solver message if a ramp stopped before this pressure (its values are then `NaN`);
    /// empty when absent from a table (tables written before the column existed).
    #[serde(default)]
    pub error: String,
}

/// Summary of a baseline table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaselineSummary {
    /// Configurations.
    pub configurations: usize,
    /// Configurations the FE did not reach (bending or force).
    pub failed: usize,
    /// Mean BE (mm).
    pub mean_be_mm: f64,
    /// Median BE (mm).
    pub median_be_mm: f64,
    /// Mean |F_sim − F_exp| (N).
    pub mean_abs_force_error_n: f64,
    /// Mean F_sim − F_exp (N): positive = over-prediction.
    pub mean_force_error_n: f64,
    /// Mean F_sim − F_exp (N) at the highest measured pressure (3 bar in the shipped data).
    pub mean_force_error_top_pressure_n: f64,
    /// The highest measured pressure (bar).
    pub top_pressure_bar: f64,
    /// Configurations of the reference study's nine found in the table (see
    /// [`in_paper_nine`]).
    #[serde(alias = "l9_configurations")]
    pub paper_nine_configurations: usize,
    /// Mean BE over the reference study's nine (mm).
    #[serde(alias = "l9_mean_be_mm")]
    pub paper_nine_mean_be_mm: f64,
    /// Median BE over the reference study's nine (mm).
    #[serde(alias = "l9_median_be_mm")]
    pub paper_nine_median_be_mm: f64,
}

/// Whether a configuration is one of the reference study's nine: the study compared its model
/// on nine of the 27 configurations in which T and P move together (T at its lowest level with
/// P at its lowest, the middle with the middle, the highest with the highest: T 1.6 mm at
/// 1 bar, 2.0 at 2 bar, 2.4 at 3 bar), for each N (its Fig. 8 and Table 8). With level
/// indices `j` of T and `k` of P in increasing order: `k = j`. `None` when a value is not one
/// of three levels.
pub fn in_paper_nine(
    levels_n: &[usize],
    levels_t: &[f64],
    levels_p: &[f64],
    n: usize,
    t: f64,
    p: f64,
) -> Option<bool> {
    if levels_n.len() != 3 || levels_t.len() != 3 || levels_p.len() != 3 {
        return None;
    }
    levels_n.iter().position(|&v| v == n)?;
    let j = levels_t.iter().position(|&v| (v - t).abs() < 1e-9)?;
    let k = levels_p.iter().position(|&v| (v - p).abs() < 1e-9)?;
    Some(k == j)
}

fn sorted_levels(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Errors of [`run_baseline`].
#[derive(Debug, Error)]
pub enum BaselineError {
    /// A design or solver setting error.
    #[error(transparent)]
    Simulate(#[from] SimulateError),
    /// The ramp cache could not be written.
    #[error("ramp cache {path}: {message}")]
    Cache {
        /// File or directory.
        path: String,
        /// What failed.
        message: String,
    },
}

impl BaselineError {
    fn cache(path: &Path, e: impl std::fmt::Display) -> Self {
        BaselineError::Cache {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    }
}

/// Format name of a sweep's sensitivities file ([`SweepSensitivities`]).
pub const SWEEP_SENSITIVITY_FORMAT: &str = "surrogate-sweep-sensitivities";

/// Version of that file.
pub const SWEEP_SENSITIVITY_VERSION: u32 = 1;

/// The sensitivities of one ramp of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignSensitivities {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Bending or blocked force.
    pub mode: Mode,
    /// Every reported step's outputs and their derivatives.
    pub sensitivities: Sensitivities,
}

/// The sensitivities of a sweep's ramps: what the discrepancy diagnoser reads (its
/// signatures of the effects, at the material of the sweep). Written by
/// `surrogate validate --sensitivities`, versioned and checked on load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepSensitivities {
    /// [`SWEEP_SENSITIVITY_FORMAT`].
    pub format: String,
    /// [`SWEEP_SENSITIVITY_VERSION`].
    pub version: u32,
    /// The material of every ramp.
    pub material: Material,
    /// The mesh.
    pub mesh: MeshOptions,
    /// The effects of every ramp (neutral: none).
    pub effects: Effects,
    /// One per ramp that finished.
    pub designs: Vec<DesignSensitivities>,
    /// Ramps without sensitivities, and why (not in the cache, stopped early).
    pub missing: Vec<String>,
}

impl SweepSensitivities {
    /// The sensitivities of `ramps`, run with `settings`.
    pub fn of(settings: &SweepSettings, ramps: &[SweepRamp]) -> Self {
        let mut designs = Vec::new();
        let mut missing = Vec::new();
        for r in ramps {
            match &r.sensitivities {
                Some(s) => designs.push(DesignSensitivities {
                    n_bellows: r.n_bellows,
                    wall_thickness_mm: r.wall_thickness_mm,
                    mode: r.mode,
                    sensitivities: s.clone(),
                }),
                None => missing.push(format!(
                    "N = {}, T = {} mm, {:?}: {}",
                    r.n_bellows,
                    r.wall_thickness_mm,
                    r.mode,
                    if r.error.is_empty() {
                        "no sensitivities"
                    } else {
                        &r.error
                    }
                )),
            }
        }
        Self {
            format: SWEEP_SENSITIVITY_FORMAT.into(),
            version: SWEEP_SENSITIVITY_VERSION,
            material: settings.material.clone(),
            mesh: settings.mesh,
            effects: settings.effects.clone(),
            designs,
            missing,
        }
    }

    /// Reads a file written from [`Self::of`].
    ///
    /// # Errors
    /// [`BaselineError::Cache`] naming the file if it cannot be read or parsed, or is not
    /// this format and version.
    pub fn read(path: &Path) -> Result<Self, BaselineError> {
        let text = std::fs::read_to_string(path).map_err(|e| BaselineError::cache(path, e))?;
        let s: Self = serde_json::from_str(&text).map_err(|e| BaselineError::cache(path, e))?;
        if s.format != SWEEP_SENSITIVITY_FORMAT || s.version != SWEEP_SENSITIVITY_VERSION {
            return Err(BaselineError::cache(
                path,
                format!(
                    "format {} version {}: expected {SWEEP_SENSITIVITY_FORMAT} version                      {SWEEP_SENSITIVITY_VERSION}",
                    s.format, s.version
                ),
            ));
        }
        Ok(s)
    }

    /// The sensitivities of design `(n, t)` in `mode`, if there.
    pub fn design(&self, n: usize, t: f64, mode: Mode) -> Option<&Sensitivities> {
        self.designs
            .iter()
            .find(|d| d.n_bellows == n && d.wall_thickness_mm == t && d.mode == mode)
            .map(|d| &d.sensitivities)
    }
}

/// A cached ramp: the key (everything that defines it) and its outcome.
#[derive(Serialize, Deserialize)]
struct CachedRamp {
    key: String,
    steps: Vec<StepResult>,
    error: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    sensitivities: Option<Sensitivities>,
}

/// What a cached ramp holds: its steps, the solver's message if it stopped, its
/// sensitivities if asked for.
type RampOutcome = (Vec<StepResult>, String, Option<Sensitivities>);

/// Where one ramp of the baseline is cached, and its key.
struct RampCache {
    path: PathBuf,
    key: String,
}

impl RampCache {
    fn at(dir: &Path, case: &Case, sensitivities: &[Parameter]) -> Self {
        let mode = match case.mode {
            Mode::Bending => "bending",
            Mode::Force => "force",
        };
        let p = case.design.params();
        let mut key = serde_json::json!({
            "code_version": env!("CARGO_PKG_VERSION"),
            "design": [p.n_bellows, p.wall_thickness],
            "material": case.material,
            "pressures_bar": case.pressures_bar,
            "gravity": case.gravity,
            "mesh": case.mesh,
            "solver": case.solver,
            "mode": mode,
            "contact": case.contact,
        });
        if case.mode == Mode::Force {
            key["plate_revision"] = FORCE_MODEL_REVISION.into();
        }
        // a design of another geometry than the historical one ([`Geometry`]) is keyed by
        // every dimension; the historical designs keep their key (and the committed caches)
        if *p != DesignParams::new(p.n_bellows, p.wall_thickness) {
            key["design_params"] = serde_json::to_value(p).unwrap_or_default();
        }
        // a neutral case keeps the key (and the cache) it had before effects existed
        if !case.effects.is_neutral() {
            key["effects"] = serde_json::to_value(&case.effects).unwrap_or_default();
        }
        // a ramp with sensitivities has its own file and key (a plain one keeps its own)
        let suffix = if sensitivities.is_empty() {
            String::new()
        } else {
            key["sensitivities"] = serde_json::to_value(sensitivities).unwrap_or_default();
            key["sensitivity_version"] = SENSITIVITY_FORMAT_VERSION.into();
            key["sensitivity_method"] = SENSITIVITY_METHOD.into();
            "_sensitivities".into()
        };
        let key = key.to_string();
        RampCache {
            path: dir.join(format!(
                "n{}_t{}_{mode}{suffix}.json",
                p.n_bellows, p.wall_thickness
            )),
            key,
        }
    }

    /// The cached outcome if the file exists, parses and carries the same key.
    fn load(&self) -> Option<RampOutcome> {
        let text = std::fs::read_to_string(&self.path).ok()?;
        let c: CachedRamp = serde_json::from_str(&text).ok()?;
        (c.key == self.key).then_some((c.steps, c.error, c.sensitivities))
    }

    fn store(&self, r: &RampOutcome) -> Result<(), BaselineError> {
        let c = CachedRamp {
            key: self.key.clone(),
            steps: r.0.clone(),
            error: r.1.clone(),
            sensitivities: r.2.clone(),
        };
        let text = serde_json::to_string(&c).map_err(|e| BaselineError::cache(&self.path, e))?;
        crate::io::write_atomic(&self.path, text.as_bytes())
            .map_err(|e| BaselineError::cache(&self.path, e))
    }
}

/// Largest pressure increment of a sensitivity sweep's load steps (bar; the diagnoser's sweep
/// at the calibrated state and the identification's sweeps), four times the solver's
/// default: only the states at the recorded pressures are used, and a converged state does
/// not depend on the path to it. Measured on the coarse N = 11, T = 2.0 actuator, 0 → 3 bar
/// with all 20 sensitivities, one core each: bending 96.6 → 60.5 s, blocked force 102.6 →
/// 65.7 s; tip, force and every derivative the same to 10⁻⁸ relative. Over the whole sweep
/// at the calibrated state every derivative of tip, angle and force is within 2.8 % of the
/// committed sweep in steps of 0.05 bar (`fe_reference/sensitivities/calibrated_coarse/`)
/// and the verdict is the same: `fe_reference/diagnosis/bench.md`.
pub const SWEEP_MAX_PRESSURE_INCREMENT: f64 = 0.2;

/// Newton tolerance of a sensitivity sweep's ramps (normalised residual), ten times the
/// solver's default: the last Newton iteration of a load step takes the residual from about
/// 10⁻⁶ to 10⁻¹⁰, and the sensitivities do not need it. Measured on the coarse N = 13,
/// T = 1.6 mm actuator at the shipped experiments' calibrated set, 0 → 3 bar with all 20
/// sensitivities: bending 210 → 206 Newton iterations, blocked force 218 → 201; tip and force
/// the same to 10⁻⁵, every derivative of tip, angle and markers within 6·10⁻⁶ relative, of the
/// force within 0.05 % (one derivative of −1.5·10⁻⁴ N per unit within 0.5 %).
pub const SWEEP_RTOL: f64 = 1e-6;

/// The settings of a sweep, shared by every ramp: everything but the design and the pressures.
///
/// [`SweepSettings::new`] gives the baseline's own (gravity, default contact and solver, no
/// effect); a cached ramp is keyed by every field, and a neutral [`Effects`] leaves the key
/// as it was before effects existed, so committed caches stay valid.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSettings {
    /// The material.
    pub material: Material,
    /// The dimensions the reference study leaves unstated ([`Geometry`]); the historical
    /// [`Geometry::as_modelled`] leaves every design, and so every cache key, as it was.
    pub geometry: Geometry,
    /// Mesh level and options.
    pub mesh: MeshOptions,
    /// Contact settings (bellows, clamp, force plate).
    pub contact: ContactSettings,
    /// Physics beyond the nominal model, the same for every ramp.
    pub effects: Effects,
    /// Nonlinear solver settings.
    pub solver: SolverSettings,
    /// Self-weight on/off.
    pub gravity: bool,
    /// Differentiate every ramp's outputs with respect to these parameters
    /// ([`crate::fe::sensitivity`]; none by default). Such ramps are cached apart from the
    /// plain ones (their key names the parameters).
    pub sensitivities: Vec<Parameter>,
    /// Start each ramp that is not in the cache from the pool's ramp of the same design and
    /// rig (an earlier iteration of a calibration), moved to [`Self::warm_point`] by its
    /// displacement sensitivities ([`crate::fe::campaign::WarmPool`]), and keep it there for
    /// the next; `None`: every ramp starts cold. Not part of the cache key: a warm ramp gives
    /// the cold one's answers to the solver's tolerance.
    pub warm: Option<WarmPool>,
    /// The sweep's parameter point, one value per entry of [`Self::sensitivities`] (the step
    /// of a warm start is this minus the pooled ramp's point).
    pub warm_point: Vec<f64>,
}

impl SweepSettings {
    /// The baseline's settings for `material` on `mesh`: gravity, default contact and solver,
    /// no effect.
    pub fn new(material: Material, mesh: MeshOptions) -> Self {
        Self {
            material,
            geometry: Geometry::as_modelled(),
            mesh,
            contact: ContactSettings::default(),
            effects: Effects::default(),
            solver: SolverSettings::default(),
            gravity: true,
            sensitivities: Vec::new(),
            warm: None,
            warm_point: Vec::new(),
        }
    }

    /// The FE case of design `(n, t)` in `mode` through `pressures_bar`.
    ///
    /// # Errors
    /// [`SimulateError`] for a design outside the model's range or one the geometry cannot
    /// build.
    pub fn case(
        &self,
        n: usize,
        t: f64,
        pressures_bar: Vec<f64>,
        mode: Mode,
    ) -> Result<Case, SimulateError> {
        let design = if self.geometry.is_as_modelled() {
            DesignParams::new(n, t)
                .validate()
                .map_err(SimulateError::from)?
        } else {
            self.geometry.design(n, t).map_err(SimulateError::from)?
        };
        Ok(Case {
            design,
            material: self.material.clone(),
            pressures_bar,
            gravity: self.gravity,
            mesh: self.mesh,
            solver: self.solver.clone(),
            mode,
            contact: self.contact,
            effects: self.effects.clone(),
        })
    }
}

/// One design of a sweep and the pressures of its ramps (bar, increasing, from 0).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepDesign {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// The ramp's pressures (bar): 0 and the recorded ones.
    pub pressures_bar: Vec<f64>,
}

/// The designs of `bending` (sorted by N, then T), each with 0 and its recorded pressures.
pub fn recorded_designs(bending: &[BendingRecord]) -> Vec<SweepDesign> {
    let mut designs: Vec<(usize, f64)> = bending
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    designs
        .into_iter()
        .map(|(n, t)| {
            let mut pressures: Vec<f64> = bending
                .iter()
                .filter(|r| r.n_bellows == n && r.wall_thickness_mm == t)
                .map(|r| r.pressure_bar)
                .collect();
            pressures.sort_by(f64::total_cmp);
            pressures.insert(0, 0.0);
            pressures.dedup();
            SweepDesign {
                n_bellows: n,
                wall_thickness_mm: t,
                pressures_bar: pressures,
            }
        })
        .collect()
}

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

/// Runs the sweep for one material; `progress(done, total)` after every FE ramp. A ramp that
/// stops keeps the pressures it reached; the others get `NaN` values and the solver's message
/// in [`BaselineRow::error`].
///
/// # Errors
/// An invalid experimental design (N or T out of the model's range); a cache directory that
/// cannot be written.
pub fn run_baseline(
    settings: &SweepSettings,
    bending: &[BendingRecord],
    force: &[ForceRecord],
    cache: Option<&Path>,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<Vec<BaselineRow>, BaselineError> {
    let ramps = run_ramps(settings, &recorded_designs(bending), cache, progress)?;
    Ok(rows(&ramps, bending, force))
}

/// The rows of the ramps already in `cache`, without running any FE: a ramp that is not
/// cached gives `NaN` values and `not in the cache` in [`BaselineRow::error`] (a quick look
/// at a sweep that is still running, or at a committed one).
///
/// # Errors
/// An invalid experimental design.
pub fn cached_baseline(
    settings: &SweepSettings,
    bending: &[BendingRecord],
    force: &[ForceRecord],
    cache: &Path,
) -> Result<Vec<BaselineRow>, BaselineError> {
    let ramps = cached_ramps(settings, &recorded_designs(bending), cache)?;
    Ok(rows(&ramps, bending, force))
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
fn cost_order(jobs: &[(&SweepDesign, Mode)]) -> Vec<usize> {
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
fn longest_first<T: Sync, R: Send>(
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

/// The baseline table: one row per bending record, from the ramps of its design.
fn rows(ramps: &[SweepRamp], bending: &[BendingRecord], force: &[ForceRecord]) -> Vec<BaselineRow> {
    let mut rows = Vec::new();
    for rec in bending {
        let find = |mode: Mode| {
            ramps
                .iter()
                .find(|r| {
                    r.mode == mode
                        && r.n_bellows == rec.n_bellows
                        && r.wall_thickness_mm == rec.wall_thickness_mm
                })
                .map(|r| (r.at(rec.pressure_bar), r.error.as_str()))
                .unwrap_or((None, "not run"))
        };
        let ((b, eb), (f, ef)) = (find(Mode::Bending), find(Mode::Force));
        let nan = f64::NAN;
        let (uz, uy, angle) =
            b.map_or((nan, nan, nan), |b| (b.tip_uz_mm, b.tip_uy_mm, b.angle_deg));
        let mut error = Vec::new();
        if b.is_none() {
            error.push(format!("bending: {eb}"));
        }
        if f.is_none() {
            error.push(format!("force: {ef}"));
        }
        let f_exp = force
            .iter()
            .find(|r| {
                r.n_bellows == rec.n_bellows
                    && r.wall_thickness_mm == rec.wall_thickness_mm
                    && r.pressure_bar == rec.pressure_bar
            })
            .map_or(f64::NAN, |r| r.force_n);
        let f_sim = f.and_then(|f| f.force_n).unwrap_or(f64::NAN);
        rows.push(BaselineRow {
            n_bellows: rec.n_bellows,
            wall_thickness_mm: rec.wall_thickness_mm,
            pressure_bar: rec.pressure_bar,
            uz_exp_mm: rec.tip_uz_mm,
            uz_sim_mm: uz,
            uy_exp_mm: rec.tip_uy_mm,
            uy_sim_mm: uy,
            angle_exp_deg: rec.angle_deg,
            angle_sim_deg: angle,
            be_mm: bending_error(rec.tip_uz_mm, rec.tip_uy_mm, uz, uy),
            force_exp_n: f_exp,
            force_sim_n: f_sim,
            force_error_n: f_sim - f_exp,
            error: error.join("; "),
        });
    }
    rows
}

/// Mean / median BE and force errors of a table, over the configurations the FE reached; the
/// same over the reference study's nine ([`in_paper_nine`]), and the force error at the top pressure.
pub fn summarize(rows: &[BaselineRow]) -> BaselineSummary {
    let mut be: Vec<f64> = rows
        .iter()
        .map(|r| r.be_mm)
        .filter(|v| v.is_finite())
        .collect();
    let fe: Vec<f64> = rows
        .iter()
        .map(|r| r.force_error_n)
        .filter(|v| v.is_finite())
        .collect();
    let levels_n: Vec<usize> = sorted_levels(rows.iter().map(|r| r.n_bellows as f64))
        .into_iter()
        .map(|v| v as usize)
        .collect();
    let levels_t = sorted_levels(rows.iter().map(|r| r.wall_thickness_mm));
    let levels_p = sorted_levels(rows.iter().map(|r| r.pressure_bar));
    let nine: Vec<&BaselineRow> = rows
        .iter()
        .filter(|r| {
            in_paper_nine(
                &levels_n,
                &levels_t,
                &levels_p,
                r.n_bellows,
                r.wall_thickness_mm,
                r.pressure_bar,
            ) == Some(true)
        })
        .collect();
    let mut nine_be: Vec<f64> = nine
        .iter()
        .map(|r| r.be_mm)
        .filter(|v| v.is_finite())
        .collect();
    let top = levels_p.last().copied().unwrap_or(f64::NAN);
    let fe_top: Vec<f64> = rows
        .iter()
        .filter(|r| (r.pressure_bar - top).abs() < 1e-9)
        .map(|r| r.force_error_n)
        .filter(|v| v.is_finite())
        .collect();
    BaselineSummary {
        configurations: rows.len(),
        failed: rows.iter().filter(|r| !r.error.is_empty()).count(),
        mean_be_mm: mean(&be),
        median_be_mm: median(&mut be),
        mean_abs_force_error_n: mean(&fe.iter().map(|v| v.abs()).collect::<Vec<_>>()),
        mean_force_error_n: mean(&fe),
        mean_force_error_top_pressure_n: mean(&fe_top),
        top_pressure_bar: top,
        paper_nine_configurations: nine.len(),
        paper_nine_mean_be_mm: mean(&nine_be),
        paper_nine_median_be_mm: median(&mut nine_be),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::material::DEFAULT_BULK_RATIO;
    use crate::fe::mesh::MeshLevel;

    #[test]
    fn the_queue_starts_thin_walls_and_forces_first_and_returns_in_item_order() {
        let designs: Vec<SweepDesign> = [(9, 2.4), (13, 1.6), (11, 2.0), (13, 2.4)]
            .iter()
            .map(|&(n, t)| SweepDesign {
                n_bellows: n,
                wall_thickness_mm: t,
                pressures_bar: vec![0.0, 1.0],
            })
            .collect();
        let jobs: Vec<(&SweepDesign, Mode)> = designs
            .iter()
            .flat_map(|d| [(d, Mode::Bending), (d, Mode::Force)])
            .collect();
        let order = cost_order(&jobs);
        let first: Vec<(usize, f64, Mode)> = order
            .iter()
            .take(3)
            .map(|&i| (jobs[i].0.n_bellows, jobs[i].0.wall_thickness_mm, jobs[i].1))
            .collect();
        assert_eq!(
            first,
            vec![
                (13, 1.6, Mode::Force),
                (13, 1.6, Mode::Bending),
                (11, 2.0, Mode::Force)
            ]
        );
        let started = std::sync::Mutex::new(Vec::new());
        let out = longest_first(&jobs, &order, |&(d, m)| {
            started
                .lock()
                .unwrap()
                .push((d.n_bellows, m == Mode::Force));
            (d.n_bellows, d.wall_thickness_mm, m)
        });
        let expected: Vec<(usize, f64, Mode)> = jobs
            .iter()
            .map(|&(d, m)| (d.n_bellows, d.wall_thickness_mm, m))
            .collect();
        assert_eq!(out, expected);
        assert_eq!(started.into_inner().unwrap().len(), jobs.len());
    }

    fn case(stiffness: f64) -> Case {
        Case {
            design: DesignParams::new(11, 2.0).validate().unwrap(),
            material: Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap(),
            pressures_bar: vec![0.0, 1.0, 2.0],
            gravity: true,
            mesh: MeshOptions::level(MeshLevel::Standard),
            solver: SolverSettings::default(),
            mode: Mode::Force,
            contact: ContactSettings {
                stiffness,
                ..ContactSettings::default()
            },
            effects: Effects::default(),
        }
    }

    fn committed(path: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
    }

    /// The committed literature baseline is read from its cache: every ramp's key is the one
    /// written before the settings were gathered and effects existed; an effect changes the
    /// key (nothing read), a neutral one given explicitly does not.
    #[test]
    fn committed_baseline_ramps_keep_their_keys() {
        let bending = crate::calibrate::experiments::shipped_bending().unwrap();
        let designs = recorded_designs(&bending);
        assert_eq!(designs.len(), 9);
        assert_eq!(designs[0].pressures_bar, [0.0, 1.0, 2.0, 3.0]);
        let dir = committed("fe_reference/baseline/ogden_002_standard_ramps");
        let material = Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap();
        let mut settings = SweepSettings::new(material, MeshOptions::level(MeshLevel::Standard));
        let sources = |s: &SweepSettings| -> Vec<RampSource> {
            cached_ramps(s, &designs, &dir)
                .unwrap()
                .iter()
                .map(|r| r.source)
                .collect()
        };
        assert_eq!(sources(&settings), vec![RampSource::Cache; 18]);
        settings.effects = Effects::parse(["wall_bias=0"]).unwrap();
        assert_eq!(sources(&settings), vec![RampSource::Cache; 18]);
        settings.effects = Effects::parse(["wall_bias=0.1"]).unwrap();
        assert_eq!(sources(&settings), vec![RampSource::Missing; 18]);
        // another geometry: every dimension is in the key, nothing read; the historical one
        // given explicitly keeps the keys
        settings.effects = Effects::default();
        settings.geometry = Geometry {
            name: "other".into(),
            side_wall_mm: Some(2.0),
            ..Geometry::as_modelled()
        };
        assert_eq!(sources(&settings), vec![RampSource::Missing; 18]);
        settings.geometry = Geometry::as_modelled();
        assert_eq!(sources(&settings), vec![RampSource::Cache; 18]);
        // the rows of the table: every configuration reached
        let force = crate::calibrate::experiments::shipped_force().unwrap();
        settings.effects = Effects::default();
        let rows = cached_baseline(&settings, &bending, &force, &dir).unwrap();
        assert!(rows
            .iter()
            .all(|r| r.error.is_empty() && r.be_mm.is_finite()));
    }

    /// The committed standard-mesh verification of the calibrated set (what `demo` and
    /// `calibrate --verify-fe standard --fe-cache …` read) is found whole in its cache.
    #[test]
    fn committed_verification_ramps_keep_their_keys() {
        let set = crate::calibrate::OgdenSet::new(0.03821, 5.996, -5.195, -1.996).unwrap();
        let material = crate::calibrate::verify::fe_material(&set).unwrap();
        let settings = SweepSettings::new(material, MeshOptions::level(MeshLevel::Standard));
        let bending = crate::calibrate::experiments::shipped_bending().unwrap();
        let dir = committed("fe_reference/calibration/standard/fe_standard_ramps");
        let ramps = cached_ramps(&settings, &recorded_designs(&bending), &dir).unwrap();
        assert_eq!(ramps.len(), 18);
        assert!(ramps.iter().all(|r| r.source == RampSource::Cache));
    }

    #[test]
    fn cached_ramps_are_reused_only_for_the_same_settings() {
        let dir = std::env::temp_dir().join(format!("surrogate_ramps_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let c = RampCache::at(&dir, &case(20.0), &[]);
        assert!(
            c.path.ends_with("n11_t2_force.json"),
            "{}",
            c.path.display()
        );
        assert!(c.load().is_none(), "nothing cached yet");
        let ramp = (Vec::new(), "stopped at 1.5 bar".to_string(), None);
        c.store(&ramp).unwrap();
        assert_eq!(c.load(), Some(ramp));
        // another setting: same file name, other key, not reused
        let other = RampCache::at(&dir, &case(40.0), &[]);
        assert_eq!(other.path, c.path);
        assert!(other.load().is_none());
        // a ramp with sensitivities: its own file and key
        let sens = RampCache::at(&dir, &case(20.0), &Parameter::all());
        assert!(sens.path.ends_with("n11_t2_force_sensitivities.json"));
        assert!(sens.load().is_none());
        // a damaged file is recomputed, not trusted
        std::fs::write(&c.path, "{\"key\": ").unwrap();
        assert!(c.load().is_none());
        std::fs::remove_dir_all(dir).unwrap();
    }

    fn row(n: usize, t: f64, p: f64, be: f64, force_error: f64) -> BaselineRow {
        BaselineRow {
            n_bellows: n,
            wall_thickness_mm: t,
            pressure_bar: p,
            uz_exp_mm: 0.0,
            uz_sim_mm: 0.0,
            uy_exp_mm: 0.0,
            uy_sim_mm: 0.0,
            angle_exp_deg: 0.0,
            angle_sim_deg: 0.0,
            be_mm: be,
            force_exp_n: 0.0,
            force_sim_n: 0.0,
            force_error_n: force_error,
            error: String::new(),
        }
    }

    #[test]
    fn the_paper_nine_move_t_and_p_together_for_each_n() {
        let (ns, ts, ps) = ([9, 11, 13], [1.6, 2.0, 2.4], [1.0, 2.0, 3.0]);
        let mut chosen = Vec::new();
        for &n in &ns {
            for &t in &ts {
                for &p in &ps {
                    if in_paper_nine(&ns, &ts, &ps, n, t, p).unwrap() {
                        chosen.push((n, t, p));
                    }
                }
            }
        }
        assert_eq!(chosen.len(), 9);
        for &n in &ns {
            for (t, p) in [(1.6, 1.0), (2.0, 2.0), (2.4, 3.0)] {
                assert!(chosen.contains(&(n, t, p)), "N = {n}, T = {t}, P = {p}");
            }
        }
        assert_eq!(in_paper_nine(&ns, &ts, &ps, 10, 2.0, 1.0), None);
        assert!(!in_paper_nine(&ns, &ts, &ps, 9, 1.6, 2.0).unwrap());
    }

    #[test]
    fn summary_separates_the_paper_nine_and_the_top_pressure() {
        let mut rows = Vec::new();
        for n in [9, 11, 13] {
            for t in [1.6, 2.0, 2.4] {
                for p in [1.0, 2.0, 3.0] {
                    // BE 1 inside the L9 subset and 4 outside; force error p − 2
                    let l9 =
                        in_paper_nine(&[9, 11, 13], &[1.6, 2.0, 2.4], &[1.0, 2.0, 3.0], n, t, p)
                            .unwrap();
                    rows.push(row(n, t, p, if l9 { 1.0 } else { 4.0 }, p - 2.0));
                }
            }
        }
        rows[0].be_mm = f64::NAN;
        rows[0].error = "stopped".into();
        let s = summarize(&rows);
        assert_eq!(
            (s.configurations, s.failed, s.paper_nine_configurations),
            (27, 1, 9)
        );
        assert!((s.paper_nine_mean_be_mm - 1.0).abs() < 1e-12);
        assert!((s.mean_be_mm - (8.0 * 1.0 + 18.0 * 4.0) / 26.0).abs() < 1e-12);
        assert!((s.mean_force_error_top_pressure_n - 1.0).abs() < 1e-12);
        assert!(s.mean_force_error_n.abs() < 1e-12);
        assert_eq!(s.top_pressure_bar, 3.0);
    }
}
