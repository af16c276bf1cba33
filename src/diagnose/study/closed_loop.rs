//! Closing the loop: does the measurement plan work? Each twin is diagnosed, the diagnosis
//! plans up to `k` measurements that would separate the candidates it cannot tell apart
//! ([`crate::diagnose::measure_design`]), those measurements are "made" on the twin's own FE
//! with fresh noise, and the twin is diagnosed again with them added. As a control, the same
//! number of measurements is drawn at random from the same menu, made and diagnosed the same
//! way.
//!
//! ```text
//!   twin recordings ──► diagnose ──► score (before)
//!                          │ plan k ≤ 3 measurements (T-optimal, the menu below)
//!                          ▼
//!   twin's FE ramps (cache) + noise(seed of the twin, "planned") ──► recordings + items
//!                          ──► diagnose ──► score (planned)
//!   the same number drawn at random from the menu (seed of the twin, "random")
//!                          ──► recordings + items ──► diagnose ──► score (random)
//! ```
//!
//! **At once or one at a time.** By default the `k` measurements are planned together on
//! the twin's recordings. With [`LoopSettings::sequential`] they are planned one at a time:
//! each on the diagnosis with the measurements before it, which has re-ranked the candidates
//! and may tie the leader with others (a sequential design, as a lab that can measure, look
//! and measure again would work). The random control adds as many as the plan did, at once.
//!
//! **The menu.** The measurements the twins' FE holds: the group's ramps are the recorded
//! designs at the sweep's levels (0, 1, 2, 3 bar), with the markers. So a plan may propose a
//! marker at a recorded configuration ([`MeasurementKind::Marker`]), the tip, angle or force
//! at a level the design was not recorded at ([`MeasurementKind::Pressure`]: 0 bar, the
//! self-weight alone), or a blocked force missing at a recorded configuration
//! ([`MeasurementKind::Force`]). New designs and moved plates need FE ramps the study does not
//! run; they are left off the menu of both the plan and the control.
//!
//! **What a measurement adds.** What a lab records when it takes it: a marker's position (both
//! components, one σ), a photograph of the pose at a pressure (tip `Uz`, `Uy` and the angle,
//! the angle's σ that of the nearest recorded angle and the tip's the calibrator's
//! `chord × σ_α`), or a force reading. The plan chooses whole records
//! ([`crate::diagnose::measure_design::records`]), and the random control draws among records
//! too. The noise is drawn from the twin's noise seed and the chooser
//! (`splitmix64(seed ⊕ tag)`), independent of the twin's own draws and of the other chooser.
//!
//! **Scoring.** As the study scores ([`super::score_twin`]), against the twin's key; whether a
//! twin's effect is visible is judged on its recordings before any measurement is added, so
//! the three columns count the same twins.

use std::path::Path;

use rand::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use super::diagnosis::{diagnose_recordings, twin_recordings, Diagnoser};
use super::plan::{StudyPlan, VERSION};
use super::results::{read_key, summarise, tip_at, without_own_group, StudySummary};
use super::score::{score_twin, truth_tips, TwinScore};
use super::twins::StudyDirs;
use crate::calibrate::baseline::{cached_ramps, recorded_designs, SweepRamp};
use crate::calibrate::experiments::{BendingRecord, ForceRecord, MarkerRecord};
use crate::calibrate::objective::{Output, FREE_LENGTH_MM};
use crate::calibrate::Recordings;
use crate::diagnose::cells::Cell;
use crate::diagnose::measure_design::{menu, records, PlanSettings};
use crate::diagnose::measurements::{sigma_for, Measurement, MeasurementKind};
use crate::diagnose::name::sweep_parameters;
use crate::diagnose::report::Diagnosis;
use crate::diagnose::DiagnoseError;
use crate::fe::simulate::{Mode, StepResult};
use crate::random::{splitmix64, standard_normal};

/// The `format` field of the closed-loop results.
pub const LOOP_FORMAT: &str = "surrogate.twin-study-closed-loop";

/// The kinds of measurement the twins' FE holds (module docs).
pub const LOOP_KINDS: [MeasurementKind; 3] = [
    MeasurementKind::Marker,
    MeasurementKind::Pressure,
    MeasurementKind::Force,
];

/// Seed tags of the two choosers' noise (and the random chooser's draws).
const TAG_PLANNED: u64 = 0x504C_414E_4E45_4400;
const TAG_RANDOM: u64 = 0x5241_4E44_4F4D_0000;

/// Settings of [`close_loop`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LoopSettings {
    /// Measurements per twin, at most (1 to 3).
    pub k: usize,
    /// One at a time, each planned on the diagnosis with the ones before (else all `k`
    /// planned at once on the recordings).
    pub sequential: bool,
}

/// Who chose the added measurements.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Chooser {
    /// The diagnosis's measurement plan.
    Planned,
    /// Drawn at random from the same menu.
    Random,
}

/// One measurement added to a twin's recordings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AddedMeasurement {
    /// What was measured, with its σ.
    pub measurement: Measurement,
    /// The FE's noise-free value of its output.
    pub truth: f64,
    /// The value recorded (with noise); `None` when an earlier item's record holds it.
    pub recorded: Option<f64>,
}

/// One twin: its score before, and after each chooser's measurements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwinLoop {
    /// The twin.
    pub twin: String,
    /// Scored on its recordings.
    pub before: TwinScore,
    /// The planned measurements, as made.
    pub planned: Vec<AddedMeasurement>,
    /// Scored with them added (the score before when the plan is empty).
    pub after_planned: TwinScore,
    /// As many measurements drawn at random from the menu, as made.
    pub random: Vec<AddedMeasurement>,
    /// Scored with those added.
    pub after_random: TwinScore,
    /// Why the plan is empty or short, when it is.
    pub note: String,
}

/// The closed loop over every twin whose FE is complete.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoopResults {
    /// [`LOOP_FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// Measurements planned per twin, at most.
    pub k: usize,
    /// Whether they were planned one at a time.
    #[serde(default)]
    pub sequential: bool,
    /// The menu's kinds.
    pub kinds: Vec<MeasurementKind>,
    /// Whether the diagnoses used the twins' marker recordings.
    pub markers: bool,
    /// Every twin.
    pub twins: Vec<TwinLoop>,
    /// Twins not diagnosed (their FE is not in the cache).
    pub pending: Vec<String>,
    /// The study's numbers before any measurement is added.
    pub before: StudySummary,
    /// … with the planned measurements.
    pub planned: StudySummary,
    /// … with as many random ones.
    pub random: StudySummary,
}

/// Runs the closed loop (module docs) over the twins of `plan`, `settings.k` measurements at
/// most per twin, planned at once or one at a time; `progress` gets a line per twin.
///
/// # Errors
/// `k` outside `1..=3`; as [`super::run_diagnoses`]; a measurement the twin's FE cannot give.
pub fn close_loop(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
    by: &Diagnoser<'_>,
    settings: &LoopSettings,
    progress: &dyn Fn(&str),
) -> Result<LoopResults, DiagnoseError> {
    PlanSettings::new(settings.k).validate()?;
    plan.check_noise_seeds()?;
    let designs = recorded_designs(&noise_from.bending);
    let (mut twins, mut pending) = (Vec::new(), Vec::new());
    for (g, replicate, name) in plan.twins() {
        let dir = dirs.twins.join(&name);
        let key_path = dirs.keys.join(format!("{name}.json"));
        if !dir.is_dir() || !key_path.exists() {
            pending.push(name);
            continue;
        }
        let group = &plan.groups[g];
        let own = without_own_group(by, &group.id)?;
        let by_here = Diagnoser {
            approximation: own.as_ref().or(by.approximation),
            ..*by
        };
        let key = read_key(plan, g, replicate, &key_path)?;
        let tips = truth_tips(plan, group, noise_from, dirs)?;
        let s = group.settings(plan, 0, &dirs.cache)?;
        let ramps = cached_ramps(&s.sweep, &designs, &s.ramp_dir())
            .map_err(crate::calibrate::CalibrateError::from)?;
        let twin = Twin {
            name: &name,
            dir: &dir,
            by: &by_here,
            ramps: &ramps,
            seed: key.seed,
        };
        let score = |d: &Diagnosis, before: Option<&TwinScore>| {
            let mut s = score_twin(&name, d, &key, by.model, &|n, t, p| tip_at(&tips, n, t, p))?;
            if let Some(b) = before {
                s.tip_move_sigma = b.tip_move_sigma;
            }
            Ok::<_, DiagnoseError>(s)
        };
        let row = twin.close(settings, &score)?;
        progress(&format!(
            "{name}: concealed {}; first {} → {} (planned: {}) / {} (random)",
            row.before.truth.as_deref().unwrap_or("nothing"),
            row.before.first.as_deref().unwrap_or("—"),
            row.after_planned.first.as_deref().unwrap_or("—"),
            row.planned
                .iter()
                .map(|m| m.measurement.text())
                .collect::<Vec<_>>()
                .join("; "),
            row.after_random.first.as_deref().unwrap_or("—"),
        ));
        twins.push(row);
    }
    let column = |f: fn(&TwinLoop) -> &TwinScore| {
        summarise(&twins.iter().map(|t| f(t).clone()).collect::<Vec<_>>())
    };
    Ok(LoopResults {
        format: LOOP_FORMAT.into(),
        version: VERSION,
        k: settings.k,
        sequential: settings.sequential,
        kinds: LOOP_KINDS.to_vec(),
        markers: by.markers,
        before: column(|t| &t.before),
        planned: column(|t| &t.after_planned),
        random: column(|t| &t.after_random),
        twins,
        pending,
    })
}

/// One twin of the loop: its recordings, its diagnoser, its group's FE.
struct Twin<'a> {
    name: &'a str,
    dir: &'a Path,
    by: &'a Diagnoser<'a>,
    ramps: &'a [SweepRamp],
    seed: u64,
}

type Score<'s> = dyn Fn(&Diagnosis, Option<&TwinScore>) -> Result<TwinScore, DiagnoseError> + 's;

impl Twin<'_> {
    /// Diagnosed before, planned, measured and diagnosed again; the random control.
    fn close(&self, s: &LoopSettings, score: &Score<'_>) -> Result<TwinLoop, DiagnoseError> {
        let rec = twin_recordings(self.dir, self.by)?;
        let d = diagnose_recordings(rec.clone(), self.by)?;
        let before = score(&d, None)?;
        let cells = d.locate.cells.clone();
        let (planned, after_planned, note) = if s.sequential {
            self.sequential(s.k, &rec, d, score, &before)?
        } else {
            self.batch(s.k, &rec, d, score, &before)?
        };
        if planned.is_empty() {
            return Ok(TwinLoop {
                twin: self.name.into(),
                after_planned: before.clone(),
                after_random: before.clone(),
                before,
                planned,
                random: Vec::new(),
                note,
            });
        }
        let params = sweep_parameters(self.by.sens);
        // one option per record, as the plan chooses records
        let all = menu(&cells, self.by.sens, &params, &LOOP_KINDS);
        let recs = records(&all);
        let options: Vec<Measurement> = all
            .into_iter()
            .enumerate()
            .filter(|(i, _)| !recs[..*i].contains(&recs[*i]))
            .map(|(_, (m, _))| m)
            .collect();
        let chosen = draw(&options, planned.len(), splitmix64(self.seed ^ TAG_RANDOM));
        let (with_random, random) = self.measured(&rec, &cells, &chosen, TAG_RANDOM)?;
        let after_random = score(&diagnose_recordings(with_random, self.by)?, Some(&before))?;
        Ok(TwinLoop {
            twin: self.name.into(),
            before,
            planned,
            after_planned,
            random,
            after_random,
            note,
        })
    }

    /// The plan of up to `k` measurements of diagnosis `d` (recorded in it), and its note.
    fn plan_next(
        &self,
        d: &mut Diagnosis,
        k: usize,
    ) -> Result<(Vec<Measurement>, String), DiagnoseError> {
        if d.naming().is_none() {
            return Ok((Vec::new(), "the Name stage did not run".into()));
        }
        let settings = PlanSettings {
            error_spread: self.by.approximation.map(|a| a.spread(&d.locate.cells)),
            kinds: LOOP_KINDS.to_vec(),
            ..PlanSettings::new(k)
        };
        let p = d.plan_with(self.by.sens, &settings)?;
        let items = p.items.iter().map(|i| i.measurement.clone()).collect();
        Ok((items, p.note.clone()))
    }

    /// The `k` measurements planned at once, made, and the twin diagnosed again.
    fn batch(
        &self,
        k: usize,
        rec: &Recordings,
        mut d: Diagnosis,
        score: &Score<'_>,
        before: &TwinScore,
    ) -> Result<(Vec<AddedMeasurement>, TwinScore, String), DiagnoseError> {
        let (items, note) = self.plan_next(&mut d, k)?;
        if items.is_empty() {
            return Ok((Vec::new(), before.clone(), note));
        }
        let (with, added) = self.measured(rec, &d.locate.cells, &items, TAG_PLANNED)?;
        let after = score(&diagnose_recordings(with, self.by)?, Some(before))?;
        Ok((added, after, note))
    }

    /// One measurement at a time: planned on the diagnosis so far, made, the twin diagnosed
    /// again with it, up to `k`.
    fn sequential(
        &self,
        k: usize,
        rec: &Recordings,
        mut d: Diagnosis,
        score: &Score<'_>,
        before: &TwinScore,
    ) -> Result<(Vec<AddedMeasurement>, TwinScore, String), DiagnoseError> {
        let mut rec = rec.clone();
        let (mut added, mut note) = (Vec::new(), String::new());
        for step in 0..k {
            let (items, why) = self.plan_next(&mut d, 1)?;
            if items.is_empty() {
                note = why;
                break;
            }
            let tag = TAG_PLANNED.wrapping_add(step as u64 + 1);
            let (with, one) = self.measured(&rec, &d.locate.cells, &items, tag)?;
            rec = with;
            added.extend(one);
            d = diagnose_recordings(rec.clone(), self.by)?;
        }
        let after = if added.is_empty() {
            before.clone()
        } else {
            score(&d, Some(before))?
        };
        Ok((added, after, note))
    }

    /// `rec` with `chosen` made on the twin's FE, noise seeded by the twin and `tag`.
    fn measured(
        &self,
        rec: &Recordings,
        cells: &[Cell],
        chosen: &[Measurement],
        tag: u64,
    ) -> Result<(Recordings, Vec<AddedMeasurement>), DiagnoseError> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(splitmix64(self.seed ^ tag));
        let mut out = rec.clone();
        let mut added = Vec::with_capacity(chosen.len());
        for m in chosen {
            let step = self.step(m)?;
            let truth = value(step, m.output).ok_or_else(|| unavailable(m, "no such value"))?;
            let recorded = add_record(&mut out, cells, m, step, &mut rng)?;
            added.push(AddedMeasurement {
                measurement: m.clone(),
                truth,
                recorded: if recorded { last_value(&out, m) } else { None },
            });
        }
        out.bending_source = format!("{} + {} measurements", rec.bending_source, chosen.len());
        Ok((out, added))
    }

    /// The step of the twin's FE that `m` reads.
    fn step(&self, m: &Measurement) -> Result<&StepResult, DiagnoseError> {
        let mode = match m.output {
            Output::Force => Mode::Force,
            _ => Mode::Bending,
        };
        self.ramps
            .iter()
            .find(|r| {
                r.mode == mode
                    && r.n_bellows as u32 == m.n_bellows
                    && (r.wall_thickness_mm - m.wall_thickness_mm).abs() < 1e-9
            })
            .and_then(|r| r.at(m.pressure_bar))
            .ok_or_else(|| unavailable(m, "the twin's FE has no such step"))
    }
}

/// The error of a measurement the twin's FE cannot give.
fn unavailable(m: &Measurement, why: &str) -> DiagnoseError {
    DiagnoseError::input(
        "closed-loop measurement",
        m.text(),
        &format!("a measurement the twin's FE holds ({why})"),
    )
}

/// The FE value of `output` at `step`.
fn value(step: &StepResult, output: Output) -> Option<f64> {
    let marker = |k: u8, c: usize| {
        step.markers
            .get(usize::from(k).checked_sub(1)?)
            .map(|m| m[c])
    };
    match output {
        Output::TipUz => Some(step.tip_uz_mm),
        Output::TipUy => Some(step.tip_uy_mm),
        Output::Angle => Some(step.angle_deg),
        Output::Force => step.force_n,
        Output::MarkerUz(k) => marker(k, 0),
        Output::MarkerUy(k) => marker(k, 1),
    }
}

/// The value `out` now records for `m`'s output (the record just added).
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn last_value(out: &Recordings, m: &Measurement) -> Option<f64> {
    let at = |n: usize, t: f64, p: f64| {
        n as u32 == m.n_bellows
            && (t - m.wall_thickness_mm).abs() < 1e-9
            && (p - m.pressure_bar).abs() < 1e-9
    };
    match m.output {
        Output::Force => out
            .force
            .iter()
            .rfind(|r| at(r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
            .map(|r| r.force_n),
        Output::TipUz | Output::TipUy | Output::Angle => out
            .bending
            .iter()
            .rfind(|r| at(r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
            .map(|r| match m.output {
                Output::TipUz => r.tip_uz_mm,
                Output::TipUy => r.tip_uy_mm,
                _ => r.angle_deg,
            }),
        Output::MarkerUz(k) | Output::MarkerUy(k) => out
            .markers
            .iter()
            .rfind(|r| {
                at(r.n_bellows, r.wall_thickness_mm, r.pressure_bar) && r.marker == usize::from(k)
            })
            .map(|r| match m.output {
                Output::MarkerUz(_) => r.uz_mm,
                _ => r.uy_mm,
            }),
    }
}

/// Adds the record that measuring `m` makes (module docs) to `out`, with noise from `rng`;
/// false when `out` already holds it.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn add_record(
    out: &mut Recordings,
    cells: &[Cell],
    m: &Measurement,
    step: &StepResult,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<bool, DiagnoseError> {
    let (n, t, p) = (m.n_bellows as usize, m.wall_thickness_mm, m.pressure_bar);
    let at =
        |rn: usize, rt: f64, rp: f64| rn == n && (rt - t).abs() < 1e-9 && (rp - p).abs() < 1e-9;
    match m.output {
        Output::Force => {
            if out
                .force
                .iter()
                .any(|r| at(r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
            {
                return Ok(false);
            }
            let f = step.force_n.ok_or_else(|| unavailable(m, "no force"))?;
            out.force.push(ForceRecord {
                n_bellows: n,
                wall_thickness_mm: t,
                pressure_bar: p,
                force_n: f + m.sigma * standard_normal(rng),
                force_std_n: m.sigma,
            });
        }
        Output::MarkerUz(k) | Output::MarkerUy(k) => {
            let marker = usize::from(k);
            if out
                .markers
                .iter()
                .any(|r| at(r.n_bellows, r.wall_thickness_mm, r.pressure_bar) && r.marker == marker)
            {
                return Ok(false);
            }
            let (uz, uy) = (
                value(step, Output::MarkerUz(k)).ok_or_else(|| unavailable(m, "no marker"))?,
                value(step, Output::MarkerUy(k)).ok_or_else(|| unavailable(m, "no marker"))?,
            );
            out.markers.push(MarkerRecord {
                n_bellows: n,
                wall_thickness_mm: t,
                pressure_bar: p,
                marker,
                uz_mm: uz + m.sigma * standard_normal(rng),
                uy_mm: uy + m.sigma * standard_normal(rng),
                std_mm: m.sigma,
            });
            if out.markers_source.is_empty() {
                out.markers_source = "closed-loop measurements (markers)".into();
            }
        }
        Output::TipUz | Output::TipUy | Output::Angle => {
            if out
                .bending
                .iter()
                .any(|r| at(r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
            {
                return Ok(false);
            }
            let values = crate::fe::sensitivity::Outputs {
                tip_uz_mm: step.tip_uz_mm,
                tip_uy_mm: step.tip_uy_mm,
                angle_deg: step.angle_deg,
                markers: step.markers.clone(),
                force_n: step.force_n,
            };
            let (sa, _) = sigma_for(cells, (m.n_bellows, t, p), Output::Angle, &values)
                .ok_or_else(|| unavailable(m, "no recorded angle to take the σ from"))?;
            let st = (FREE_LENGTH_MM - step.tip_uz_mm).hypot(step.tip_uy_mm) * sa.to_radians();
            out.bending.push(BendingRecord {
                n_bellows: n,
                wall_thickness_mm: t,
                pressure_bar: p,
                tip_uz_mm: step.tip_uz_mm + st * standard_normal(rng),
                tip_uy_mm: step.tip_uy_mm + st * standard_normal(rng),
                angle_deg: step.angle_deg + sa * standard_normal(rng),
                angle_std_deg: sa,
            });
        }
    }
    Ok(true)
}

/// `count` distinct items of `options`, drawn uniformly with `seed` (a partial
/// Fisher–Yates shuffle).
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn draw(options: &[Measurement], count: usize, seed: u64) -> Vec<Measurement> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut idx: Vec<usize> = (0..options.len()).collect();
    let count = count.min(idx.len());
    for i in 0..count {
        let j = i + (rng.next_u64() % (idx.len() - i) as u64) as usize;
        idx.swap(i, j);
    }
    idx[..count].iter().map(|&i| options[i].clone()).collect()
}
