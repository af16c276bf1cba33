//! The blind study of the diagnoser: twins with concealed effects (and null twins without),
//! each diagnosed without its key, then scored against the keys.
//!
//! ```text
//!   StudyPlan (groups: effects + material; seeds; the twins' mesh)
//!     │  per group: one FE sweep (cached), a twin per seed      ──► twins/<id>_s<seed>/
//!     │                                    the keys, apart      ──► keys/<id>_s<seed>.json
//!     ▼
//!   diagnose each twin directory (calibrate, locate, name, refit the named effect),
//!   seeing only its recordings                                  ──► diagnoses/<id>_s<seed>.json
//!     ▼
//!   score against the keys: confusion matrix, rank of the concealed effect, recovered
//!   sizes, false alarms, held-out tip error                     ──► results.json, results.md
//! ```
//!
//! **The standard plan** ([`StudyPlan::standard`]): six effects of the library at two sizes
//! each, each group with its own material drawn uniformly in the ±10 % box around Ogden 002
//! (the reference study's box), and six null groups (no effect) with materials drawn by a
//! Latin hypercube over the central 80 % of the surrogate's training domain; three noise
//! seeds per group; the twins on elements of 5 mm (one through a wall), which is not the
//! discretisation of the coarse mesh (6 mm) that the diagnosing surrogate and the
//! sensitivities come from.
//!
//! **Noise** ([`StudyPlan::noise_seed`]): a twin's noise seed is a function of its identity
//! in the whole plan, `s = m(m(h ⊕ |id|) ⊕ replicate)`, `m` the SplitMix64 finaliser and `h`
//! the draw seed and the bytes of the group's id folded through it, so every twin draws its own noise and a run given only some groups
//! (`--groups`, to split the FE between processes) draws exactly what one run of the whole
//! plan draws. The derivation is versioned ([`NOISE_SEEDS`], in the plan and every key).
//!
//! **Scoring** ([`score_twin`]): a twin's effect *moves the tip* by `max |(ΔUz, ΔUy)| / σ_tip`
//! over its configurations, the difference between its noise-free FE tip and the
//! diagnosing surrogate's prediction at the twin's true material (what the effect adds, up
//! to the two discretisations and the surrogate's own error, which the null twins measure).
//! The targets count the twins whose effect moves the tip by more than 2 σ.

use std::path::{Path, PathBuf};

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use super::approx_error::{lhs, sample, ApproximationError, SampleSettings};
use super::refit::RefitSettings;
use super::report::{diagnose, DiagnoseSettings, Diagnosis};
use super::DiagnoseError;
use crate::calibrate::baseline::{cached_ramps, recorded_designs, RampSource, SweepSensitivities};
use crate::calibrate::objective::Output;
use crate::calibrate::twin::{write_twin, TwinKey, TwinSettings};
use crate::calibrate::{OgdenSet, ParamSpace, Recordings};
use crate::fe::effects::{Effect, Effects};
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::mesh::{MeshLevel, MeshOptions};
use crate::fe::simulate::Mode;
use crate::rom::{Query, Surrogate};

/// The `format` field of a study plan.
pub const PLAN_FORMAT: &str = "surrogate.twin-study-plan";
/// The `format` field of the study's results.
pub const RESULTS_FORMAT: &str = "surrogate.twin-study-results";
/// The version this code writes and reads.
pub const VERSION: u32 = 1;
/// The derivation of the twins' noise seeds this code uses ([`StudyPlan::noise_seed`]),
/// recorded in the plan (`noise_seeds`) and in every key (`seed_origin`).
///
/// Earlier derivations: 1 mixed the draw seed with the group's *index among the groups a run
/// was given*, so runs split by `--groups` gave their first groups the same seeds; 0 used
/// the replicate alone, the same noise in every group.
pub const NOISE_SEEDS: u32 = 2;

/// The effects and sizes of the standard plan (value of the effect, not offset).
pub const STANDARD_EFFECTS: [(&str, [f64; 2]); 6] = [
    ("wall_bias_bellows", [0.1, 0.25]),
    ("gap_bias", [-0.1, -0.3]),
    ("clamp_compliance", [0.02, 0.08]),
    ("pressure_loss", [0.05, 0.15]),
    ("anisotropy", [0.15, 0.4]),
    ("plate_offset", [-0.6, -1.5]),
];

/// One FE twin: its concealed effects and material (every seed shares its FE runs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwinGroup {
    /// Name of the group (`gap_bias_2`, `null_4`).
    pub id: String,
    /// The concealed effects, `NAME=VALUE` (empty: a null twin).
    pub effects: Vec<String>,
    /// The material, `mu1,alpha1,mu2,alpha2`.
    pub material: String,
}

/// The plan of a study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyPlan {
    /// [`PLAN_FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The twins' discretisation.
    pub mesh: MeshOptions,
    /// Noise seeds of every group.
    pub seeds: Vec<u64>,
    /// Whether the diagnoses use the twins' marker recordings (the shipped experiments have
    /// none; the twins always hold them, so a study with markers needs no other FE).
    pub markers: bool,
    /// The groups.
    pub groups: Vec<TwinGroup>,
    /// The seed the materials were drawn with.
    pub draw_seed: u64,
    /// The derivation of the twins' noise seeds the twins were made with ([`NOISE_SEEDS`]
    /// for this code); plans written before it was recorded read as 1 when they hold
    /// `"independent_noise": true`, else 0.
    pub noise_seeds: u32,
}

impl StudyPlan {
    /// The standard plan (see the [module docs](self)) for the training domain `domain`,
    /// materials drawn with `seed`.
    ///
    /// # Errors
    /// A ±10 % box around Ogden 002 that leaves `domain`.
    pub fn standard(domain: &ParamSpace, seed: u64) -> Result<Self, DiagnoseError> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let reference = OgdenSet::literature("ogden_002")?;
        let near = ParamSpace::raw_box(&reference, 0.1, domain)?;
        let mut groups = Vec::new();
        for (name, sizes) in STANDARD_EFFECTS {
            for (k, v) in sizes.iter().enumerate() {
                let u: [f64; 4] = std::array::from_fn(|_| rng.gen::<f64>());
                groups.push(TwinGroup {
                    id: format!("{name}_{}", k + 1),
                    effects: vec![format!("{name}={v}")],
                    material: near.ogden(&u)?.rounded(4).spec(),
                });
            }
        }
        for (k, u) in lhs(&mut rng, 6, 4).into_iter().enumerate() {
            let u: [f64; 4] = std::array::from_fn(|i| 0.1 + 0.8 * u[i]);
            groups.push(TwinGroup {
                id: format!("null_{}", k + 1),
                effects: Vec::new(),
                material: domain.ogden(&u)?.rounded(4).spec(),
            });
        }
        Ok(StudyPlan {
            format: PLAN_FORMAT.into(),
            version: VERSION,
            mesh: MeshOptions {
                level: MeshLevel::Coarse,
                element_size: Some(5.0),
                wall_elements: None,
            },
            seeds: vec![1, 2, 3],
            markers: false,
            groups,
            draw_seed: seed,
            noise_seeds: NOISE_SEEDS,
        })
    }

    /// Reads a plan written by [`Self::write`], checking its format and version.
    ///
    /// # Errors
    /// An unreadable file, another format or version, or a plan that does not parse.
    pub fn read(path: &Path) -> Result<Self, DiagnoseError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| DiagnoseError::input("plan", path.display(), &e.to_string()))?;
        let mut v: serde_json::Value = serde_json::from_str(&text)?;
        let format = v.get("format").and_then(|f| f.as_str()).unwrap_or("");
        if format != PLAN_FORMAT {
            return Err(DiagnoseError::input(
                &format!("{}: format", path.display()),
                format,
                PLAN_FORMAT,
            ));
        }
        let version = v.get("version").and_then(|f| f.as_u64()).unwrap_or(0);
        if version != u64::from(VERSION) {
            return Err(DiagnoseError::input(
                &format!("{}: version", path.display()),
                version,
                &VERSION.to_string(),
            ));
        }
        if let Some(o) = v.as_object_mut().filter(|o| !o.contains_key("noise_seeds")) {
            let independent = o.remove("independent_noise").and_then(|b| b.as_bool());
            o.insert(
                "noise_seeds".into(),
                u32::from(independent == Some(true)).into(),
            );
        }
        let plan: StudyPlan = serde_json::from_value(v)?;
        for g in &plan.groups {
            g.settings(&plan, 0, Path::new("."))?;
        }
        Ok(plan)
    }

    /// Writes the plan (pretty JSON, atomically).
    ///
    /// # Errors
    /// A file that cannot be written.
    pub fn write(&self, path: &Path) -> Result<(), DiagnoseError> {
        let text = serde_json::to_string_pretty(self)?;
        crate::io::write_atomic(path, text.as_bytes())
            .map_err(|e| DiagnoseError::input("plan", path.display(), &e.to_string()))
    }

    /// The noise seed of replicate `replicate` of the group with id `group`: the SplitMix64
    /// finaliser applied to the draw seed, then to each byte of the id and its length, then
    /// to the replicate. It depends on the twin's identity in the plan only, not on the
    /// groups a run is given, nor on their order.
    pub fn noise_seed(&self, group: &str, replicate: u64) -> u64 {
        let id = group.bytes().fold(splitmix64(self.draw_seed), |h, b| {
            splitmix64(h ^ u64::from(b))
        });
        splitmix64(splitmix64(id ^ group.len() as u64) ^ replicate)
    }

    /// How [`Self::noise_seed`] of `group`, `replicate` was derived, in words, for the key.
    pub fn seed_origin(&self, group: &str, replicate: u64) -> String {
        format!(
            "{PLAN_FORMAT} noise seeds {}: draw seed {}, group {group}, replicate {replicate}",
            self.noise_seeds, self.draw_seed
        )
    }

    /// The plan's twins must be made, or scored, with this code's noise seeds.
    ///
    /// # Errors
    /// A plan of another derivation ([`NOISE_SEEDS`]): its twins are not those this code
    /// makes, and runs split by `--groups` may have shared their noise.
    pub fn check_noise_seeds(&self) -> Result<(), DiagnoseError> {
        if self.noise_seeds == NOISE_SEEDS {
            return Ok(());
        }
        Err(DiagnoseError::input(
            "plan noise_seeds",
            self.noise_seeds,
            &format!(
                "{NOISE_SEEDS} (the twins of an older derivation share noise across groups; \
                 set it to {NOISE_SEEDS} and remake the twins with --stage twins, which reads \
                 the FE from the cache)"
            ),
        ))
    }

    /// A twin's key must hold the seed this plan gives replicate `replicate` of group `group`.
    ///
    /// # Errors
    /// Another seed: the twin was made by an older noise-seed derivation or another plan.
    pub fn check_key(
        &self,
        group: &str,
        replicate: u64,
        key: &TwinKey,
    ) -> Result<(), DiagnoseError> {
        let seed = self.noise_seed(group, replicate);
        if key.seed == seed {
            return Ok(());
        }
        Err(DiagnoseError::input(
            &format!("seed of {group}_s{replicate}"),
            key.seed,
            &format!(
                "{seed}, the plan's (the twin was made by an older noise-seed derivation or \
                 another plan: remake it with --stage twins)"
            ),
        ))
    }

    /// The plan with only the groups `ids` (in plan order; all when `ids` is empty): what a
    /// run given `--groups` makes. The twins keep their noise seeds.
    ///
    /// # Errors
    /// An id that is not a group of the plan.
    pub fn only(&self, ids: &[String]) -> Result<Self, DiagnoseError> {
        if let Some(bad) = ids
            .iter()
            .find(|id| !self.groups.iter().any(|g| &g.id == *id))
        {
            let all: Vec<&str> = self.groups.iter().map(|g| g.id.as_str()).collect();
            return Err(DiagnoseError::input(
                "group",
                bad,
                &format!("a group of the plan (its groups: {})", all.join(", ")),
            ));
        }
        let mut plan = self.clone();
        if !ids.is_empty() {
            plan.groups.retain(|g| ids.contains(&g.id));
        }
        Ok(plan)
    }

    /// The twins' names, `<id>_s<seed>`, in plan order.
    pub fn twins(&self) -> Vec<(usize, u64, String)> {
        self.groups
            .iter()
            .enumerate()
            .flat_map(|(g, grp)| {
                self.seeds
                    .iter()
                    .map(move |&s| (g, s, format!("{}_s{s}", grp.id)))
            })
            .collect()
    }
}

/// The SplitMix64 finaliser (Steele, Lea and Flood 2014): a bijection of `u64` whose
/// outputs for neighbouring inputs look independent.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl TwinGroup {
    /// The twin settings of seed `seed`, FE cache under `cache`.
    ///
    /// # Errors
    /// An effect or material that does not parse.
    pub fn settings(
        &self,
        plan: &StudyPlan,
        seed: u64,
        cache: &Path,
    ) -> Result<TwinSettings, DiagnoseError> {
        let effects = Effects::parse(self.effects.iter().map(String::as_str)).map_err(|e| {
            DiagnoseError::input(&format!("group {} effects", self.id), "", &e.to_string())
        })?;
        let material = Material::from_spec(&self.material, DEFAULT_BULK_RATIO).map_err(|e| {
            DiagnoseError::input(
                &format!("group {} material", self.id),
                &self.material,
                &e.to_string(),
            )
        })?;
        Ok(TwinSettings::new(
            material,
            &self.material,
            plan.mesh,
            effects,
            seed,
            cache,
        ))
    }
}

/// Directories of a study under its output directory.
#[derive(Clone, Debug)]
pub struct StudyDirs {
    /// FE ramps of every group.
    pub cache: PathBuf,
    /// The twins' recordings (one directory each).
    pub twins: PathBuf,
    /// The keys.
    pub keys: PathBuf,
    /// The diagnoses.
    pub diagnoses: PathBuf,
}

impl StudyDirs {
    /// The directories under `out`.
    pub fn under(out: &Path) -> Self {
        StudyDirs {
            cache: out.join("fe_cache"),
            twins: out.join("twins"),
            keys: out.join("keys"),
            diagnoses: out.join("diagnoses"),
        }
    }
}

/// The FE ramps of `plan`'s groups that are not in the cache of `dirs`, by group (`id`,
/// ramps missing), groups with all their ramps cached left out: what [`make_twins`] would
/// run. Reads the cache only.
///
/// # Errors
/// A group whose effects or material do not parse, an invalid design.
pub fn ramps_to_run(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
) -> Result<Vec<(String, usize)>, DiagnoseError> {
    let designs = recorded_designs(&noise_from.bending);
    let mut out = Vec::new();
    for g in &plan.groups {
        let s = g.settings(plan, 0, &dirs.cache)?;
        let missing = cached_ramps(&s.sweep, &designs, &s.ramp_dir())
            .map_err(crate::calibrate::CalibrateError::from)?
            .iter()
            .filter(|r| r.source == RampSource::Missing)
            .count();
        if missing > 0 {
            out.push((g.id.clone(), missing));
        }
    }
    Ok(out)
}

/// Makes every twin of `plan` (FE runs cached and resumable; a group's seeds share them),
/// each with its noise seed [`StudyPlan::noise_seed`] and the seed's origin in its key;
/// `progress` gets a line per twin.
///
/// # Errors
/// A plan of another noise-seed derivation ([`StudyPlan::check_noise_seeds`]); a twin error
/// (a design out of range, an unwritable cache).
pub fn make_twins(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<(), DiagnoseError> {
    plan.check_noise_seeds()?;
    let all = plan.twins();
    for (k, (g, replicate, name)) in all.iter().enumerate() {
        let group = &plan.groups[*g];
        let seed = plan.noise_seed(&group.id, *replicate);
        let mut s = group.settings(plan, seed, &dirs.cache)?;
        s.seed_origin = Some(plan.seed_origin(&group.id, *replicate));
        s.key = Some(dirs.keys.join(format!("{name}.json")));
        let out = dirs.twins.join(name);
        let o = write_twin(&s, noise_from, &out, |done, total| {
            progress(&format!("{name}: FE ramp {done} of {total}"))
        })
        .map_err(|e| DiagnoseError::input(&format!("twin {name}"), "", &e.to_string()))?;
        progress(&format!(
            "twin {} of {}: {name} ({} FE ramps run, {} cached)",
            k + 1,
            all.len(),
            o.ramps_run,
            o.ramps_cached
        ));
    }
    Ok(())
}

/// What diagnoses the twins: the surrogate the calibration uses, the FE sensitivities of
/// the Name and Model stages, and optionally a finer-mesh surrogate whose difference to
/// `model` is the mesh error projected out ([`super::mesh_error`]).
#[derive(Clone, Copy, Debug)]
pub struct Diagnoser<'a> {
    /// The diagnosing surrogate.
    pub model: &'a Surrogate,
    /// The sensitivities.
    pub sens: &'a SweepSensitivities,
    /// The reference surrogate and its name in the reports.
    pub mesh_reference: Option<(&'a Surrogate, &'a str)>,
    /// Whether the twins' marker recordings are used (the shipped experiments have none).
    pub markers: bool,
    /// The diagnosing model's approximation error against the twins' discretisation
    /// ([`super::approx_error`], from [`null_approximation_error`]): the recordings are
    /// corrected by its mean and the Name stage weighs by its covariance. A null twin is
    /// diagnosed without the sample of its own group.
    pub approximation: Option<&'a ApproximationError>,
}

/// Diagnoses one twin directory as a user would: calibrate through `model`, locate,
/// measure the mesh error against the reference (if any), name with `sens`, refit the
/// named effect.
///
/// # Errors
/// As [`diagnose`] and the stages.
pub fn diagnose_twin(dir: &Path, by: &Diagnoser<'_>) -> Result<Diagnosis, DiagnoseError> {
    let (model, sens) = (by.model, by.sens);
    let mut rec = Recordings::read_dir(dir)?;
    if !by.markers {
        rec.markers.clear();
        rec.markers_source.clear();
    }
    if let Some(a) = by.approximation {
        rec = a.correct(&rec);
    }
    let mut d = diagnose(model, &rec, &DiagnoseSettings::default(), &|_| {})?;
    if let Some((reference, name)) = by.mesh_reference {
        d.mesh_error_with(model, reference, name)?;
    }
    let settings = super::name::NameSettings {
        error_spread: by.approximation.map(|a| a.spread(&d.locate.cells)),
        ..Default::default()
    };
    d.name_with(sens, model, &settings)?;
    let named = d
        .naming()
        .and_then(super::name::Naming::named)
        .map(|c| c.effect.clone());
    if let Some(e) = named {
        let effect = Effect::from_name(&e)
            .map_err(|err| DiagnoseError::input("named effect", &e, &err.to_string()))?;
        d.refit_with(sens, model, &RefitSettings::new(vec![effect]))?;
    }
    Ok(d)
}

/// The diagnosing `model`'s approximation error against the twins' discretisation, one
/// sample per null group of `plan` (its noise-free FE recordings from the cache, no FE run
/// here, against `model` at the group's material); `model_name` names the model.
///
/// # Errors
/// A null group whose FE is not in the cache, fewer than two null groups, a material
/// outside the model's domain.
pub fn null_approximation_error(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
    model: &Surrogate,
    model_name: &str,
) -> Result<ApproximationError, DiagnoseError> {
    let nulls: Vec<&TwinGroup> = plan
        .groups
        .iter()
        .filter(|g| g.effects.is_empty())
        .collect();
    let settings = SampleSettings {
        mesh: plan.mesh,
        materials: nulls
            .iter()
            .map(|g| OgdenSet::literature(&g.material))
            .collect::<Result<_, _>>()?,
        cache: dirs.cache.clone(),
        run_fe: false,
    };
    let mut e = sample(model, model_name, &settings, noise_from, &|_, _, _| {})?;
    // the samples are named by their groups
    for (s, g) in e.samples.iter_mut().zip(&nulls) {
        s.source.clone_from(&g.id);
    }
    e.reference = format!("{} (the null twins)", e.reference);
    Ok(e)
}

/// One twin, scored.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwinScore {
    /// `<id>_s<seed>`.
    pub twin: String,
    /// The concealed effect (none: a null twin).
    pub truth: Option<String>,
    /// Its value.
    pub true_value: Option<f64>,
    /// The true material.
    pub material: String,
    /// `max |(ΔUz, ΔUy)| / σ_tip` of the noise-free twin against the surrogate at the true
    /// material (what the effect moves the tip by, in noise units).
    pub tip_move_sigma: f64,
    /// The effect named (none: nothing named).
    pub named: Option<String>,
    /// The first candidate of the ranking.
    pub first: Option<String>,
    /// Rank of the concealed effect among the candidates (1 = first).
    pub rank: Option<usize>,
    /// Whether the concealed effect is reported indistinguishable from the first candidate.
    pub indistinguishable_from_first: bool,
    /// How many other candidates the recordings cannot tell from the first (its tie set),
    /// and how many candidates were ranked.
    #[serde(default)]
    pub tied_with_first: (usize, usize),
    /// The Name stage's estimate of the concealed effect's value and its standard error.
    pub name_estimate: Option<(f64, f64)>,
    /// The refit's value of the named effect and its interval.
    pub refit_value: Option<(f64, f64, f64)>,
    /// Held-out tip BE before and after the refit (mm), and the noise level (mm).
    pub held_out_be: Option<(f64, f64, f64)>,
    /// The Name stage's verdict.
    pub verdict: String,
    /// Whether the model's own mesh error explained the residual best (the verdict then
    /// names no physics).
    #[serde(default)]
    pub model_error_best: bool,
}

/// Scores a diagnosis against its key; `model` gives the tip at the true material and
/// `truth_tip(n, t, p)` the twin's noise-free tip.
pub fn score_twin(
    twin: &str,
    d: &Diagnosis,
    key: &TwinKey,
    model: &Surrogate,
    truth_tip: &dyn Fn(u32, f64, f64) -> Option<(f64, f64)>,
) -> Result<TwinScore, DiagnoseError> {
    let truth = key
        .effects
        .iter()
        .next()
        .map(|(e, v)| (e.name().to_string(), v));
    let m = key
        .material_parameters
        .ogden_params()
        .ok_or_else(|| DiagnoseError::input("key material", &key.material, "an Ogden material"))?;
    let mut tip_move: f64 = 0.0;
    let mut pred = model.new_prediction();
    for c in d.locate.cells.iter().filter(|c| c.output == Output::TipUz) {
        let Some((uz, uy)) = truth_tip(c.n_bellows, c.wall_thickness_mm, c.pressure_bar) else {
            continue;
        };
        let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, m);
        model
            .predict_scalars_into(&q, &mut pred)
            .map_err(crate::calibrate::CalibrateError::from)?;
        let (sz, sy) = (
            pred.values[crate::rom::Q_TIP_UZ],
            pred.values[crate::rom::Q_TIP_UY],
        );
        tip_move = tip_move.max((uz - sz).hypot(uy - sy) / c.sigma);
    }
    let naming = d.naming();
    let first = naming.and_then(|n| n.candidates.first().map(|c| c.effect.clone()));
    let (mut rank, mut name_estimate, mut indistinguishable) = (None, None, false);
    if let (Some(n), Some((t, _))) = (naming, &truth) {
        if let Some(i) = n.candidates.iter().position(|c| &c.effect == t) {
            rank = Some(i + 1);
            let c = &n.candidates[i];
            let info = Effect::from_name(t)
                .map_err(|e| DiagnoseError::input("key effect", t, &e.to_string()))?
                .info();
            name_estimate = Some((info.neutral + c.estimate, c.std_error));
        }
        if let Some(f) = &first {
            indistinguishable = n
                .indistinguishable
                .iter()
                .any(|p| (&p.a == f && &p.b == t) || (&p.b == f && &p.a == t));
        }
    }
    let tied_with_first = naming.map_or((0, 0), |n| {
        let tied = first.as_ref().map_or(0, |f| {
            n.indistinguishable
                .iter()
                .filter(|p| &p.a == f || &p.b == f)
                .count()
        });
        (tied, n.candidates.len())
    });
    let refit = d.refitted();
    Ok(TwinScore {
        twin: twin.to_string(),
        truth: truth.as_ref().map(|t| t.0.clone()),
        true_value: truth.as_ref().map(|t| t.1),
        material: key.material.clone(),
        tip_move_sigma: tip_move,
        named: naming.and_then(|n| n.named().map(|c| c.effect.clone())),
        first,
        rank,
        indistinguishable_from_first: indistinguishable,
        tied_with_first,
        name_estimate,
        refit_value: refit
            .and_then(|r| r.effects.first())
            .map(|e| (e.value, e.interval.0, e.interval.1)),
        held_out_be: refit.and_then(|r| {
            let h = r.held_out.as_ref()?;
            Some((h.mean_be_before_mm?, h.mean_be_after_mm?, r.noise_be_mm?))
        }),
        verdict: naming.map_or(String::new(), |n| n.verdict.clone()),
        model_error_best: naming.is_some_and(|n| n.model_error().is_some()),
    })
}

/// A twin's noise-free tip at one configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrueTip {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Tip Uz (mm).
    pub tip_uz_mm: f64,
    /// Tip Uy (mm).
    pub tip_uy_mm: f64,
}

/// The noise-free tip of a twin group: its cached FE ramps (none run here).
///
/// # Errors
/// A group that does not parse, an invalid design.
pub fn truth_tips(
    plan: &StudyPlan,
    group: &TwinGroup,
    noise_from: &Recordings,
    dirs: &StudyDirs,
) -> Result<Vec<TrueTip>, DiagnoseError> {
    let s = group.settings(plan, 0, &dirs.cache)?;
    let ramps = cached_ramps(
        &s.sweep,
        &recorded_designs(&noise_from.bending),
        &s.ramp_dir(),
    )
    .map_err(crate::calibrate::CalibrateError::from)?;
    let mut out = Vec::new();
    for r in ramps.iter().filter(|r| r.mode == Mode::Bending) {
        for st in &r.steps {
            out.push(TrueTip {
                n_bellows: r.n_bellows as u32,
                wall_thickness_mm: r.wall_thickness_mm,
                pressure_bar: st.pressure_bar,
                tip_uz_mm: st.tip_uz_mm,
                tip_uy_mm: st.tip_uy_mm,
            });
        }
    }
    Ok(out)
}

/// The study's scores and their summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyResults {
    /// [`RESULTS_FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// Every twin diagnosed.
    pub twins: Vec<TwinScore>,
    /// Twins of the plan not diagnosed yet (their FE is not in the cache).
    pub pending: Vec<String>,
    /// Whether the diagnoses used the twins' marker recordings.
    pub markers: bool,
    /// The reference surrogate of the mesh error projected out (none: not projected).
    #[serde(default)]
    pub mesh_reference: Option<String>,
    /// The approximation error the diagnoses used: its reference and samples (none: not
    /// used).
    #[serde(default)]
    pub approximation_error: Option<String>,
    /// The summary.
    pub summary: StudySummary,
}

/// The study's numbers against its targets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudySummary {
    /// Effect twins whose effect moves the tip by more than 2 σ.
    pub visible: usize,
    /// … of which the concealed effect is ranked first.
    pub visible_first: usize,
    /// … ranked first or reported indistinguishable from the first.
    pub visible_first_or_indistinguishable: usize,
    /// … named (the verdict's effect is the concealed one).
    pub visible_named: usize,
    /// Over the visible twins: the mean number of other candidates the recordings cannot
    /// tell from the first, and the mean number ranked.
    #[serde(default)]
    pub visible_mean_tied: (f64, f64),
    /// Every effect twin: ranked first.
    pub effect_twins: usize,
    /// Every effect twin: ranked first (count).
    pub effect_first: usize,
    /// Null twins.
    pub nulls: usize,
    /// Null twins where an effect was named (false alarms).
    pub false_alarms: usize,
    /// Twins (effect, null) where the model's own mesh error explained the residual best.
    #[serde(default)]
    pub model_error_best: (usize, usize),
    /// Correctly named twins whose refitted value is within 25 % of the truth or whose
    /// interval covers it, of the correctly named.
    pub sizes_recovered: (usize, usize),
    /// Correctly named twins whose held-out tip BE after the refit is within 1.2 × the
    /// noise level, of the correctly named with a held-out BE.
    pub held_out_within: (usize, usize),
    /// Confusion matrix: rows the concealed effect (`none`), columns the named one
    /// (`nothing`; `nothing (model's mesh)` when the model's own mesh error explained the
    /// residual best), counts.
    pub confusion: Vec<(String, String, usize)>,
}

/// The summary of `twins`.
pub fn summarise(twins: &[TwinScore]) -> StudySummary {
    let effect: Vec<&TwinScore> = twins.iter().filter(|t| t.truth.is_some()).collect();
    let visible: Vec<&&TwinScore> = effect.iter().filter(|t| t.tip_move_sigma > 2.0).collect();
    let first = |t: &TwinScore| t.rank == Some(1);
    let named_right = |t: &TwinScore| t.named.is_some() && t.named == t.truth;
    let nulls: Vec<&TwinScore> = twins.iter().filter(|t| t.truth.is_none()).collect();
    let right: Vec<&&TwinScore> = effect.iter().filter(|t| named_right(t)).collect();
    let recovered = right
        .iter()
        .filter(|t| match (t.refit_value, t.true_value) {
            (Some((v, lo, hi)), Some(truth)) => {
                (v - truth).abs() <= 0.25 * truth.abs() || (lo <= truth && truth <= hi)
            }
            _ => false,
        })
        .count();
    let with_be: Vec<(f64, f64)> = right
        .iter()
        .filter_map(|t| t.held_out_be.map(|(_, after, noise)| (after, noise)))
        .collect();
    let mut confusion: Vec<(String, String, usize)> = Vec::new();
    for t in twins {
        let row = t.truth.clone().unwrap_or_else(|| "none".into());
        let col = match (&t.named, t.model_error_best) {
            (Some(n), _) => n.clone(),
            (None, true) => "nothing (model's mesh)".into(),
            (None, false) => "nothing".into(),
        };
        match confusion.iter_mut().find(|c| c.0 == row && c.1 == col) {
            Some(c) => c.2 += 1,
            None => confusion.push((row, col, 1)),
        }
    }
    StudySummary {
        visible: visible.len(),
        visible_first: visible.iter().filter(|t| first(t)).count(),
        visible_first_or_indistinguishable: visible
            .iter()
            .filter(|t| first(t) || t.indistinguishable_from_first)
            .count(),
        visible_named: visible.iter().filter(|t| named_right(t)).count(),
        visible_mean_tied: {
            let k = visible.len().max(1) as f64;
            (
                visible
                    .iter()
                    .map(|t| t.tied_with_first.0 as f64)
                    .sum::<f64>()
                    / k,
                visible
                    .iter()
                    .map(|t| t.tied_with_first.1 as f64)
                    .sum::<f64>()
                    / k,
            )
        },
        effect_twins: effect.len(),
        effect_first: effect.iter().filter(|t| first(t)).count(),
        nulls: nulls.len(),
        false_alarms: nulls.iter().filter(|t| t.named.is_some()).count(),
        model_error_best: (
            effect.iter().filter(|t| t.model_error_best).count(),
            nulls.iter().filter(|t| t.model_error_best).count(),
        ),
        sizes_recovered: (recovered, right.len()),
        held_out_within: (
            with_be.iter().filter(|(a, n)| *a <= 1.2 * n).count(),
            with_be.len(),
        ),
        confusion,
    }
}

/// Diagnoses every twin whose FE is complete and scores it; the others are listed as
/// pending. `progress` gets a line per twin.
///
/// # Errors
/// A plan of another noise-seed derivation ([`StudyPlan::check_noise_seeds`]); a key whose
/// seed is not the plan's for its twin (a twin made by an older derivation or another
/// plan: remake the twins); a diagnosis error, an unreadable key.
pub fn run_diagnoses(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
    by: &Diagnoser<'_>,
    progress: &dyn Fn(&str),
) -> Result<StudyResults, DiagnoseError> {
    plan.check_noise_seeds()?;
    let (model, markers) = (by.model, by.markers);
    let mut twins = Vec::new();
    let mut pending = Vec::new();
    for (g, replicate, name) in plan.twins() {
        let dir = dirs.twins.join(&name);
        let key_path = dirs.keys.join(format!("{name}.json"));
        if !dir.is_dir() || !key_path.exists() {
            pending.push(name);
            continue;
        }
        let own;
        let mut by_here = *by;
        if let Some(a) = by.approximation {
            let id = plan.groups[g].id.as_str();
            if a.samples.iter().any(|x| x.source == id) {
                own = a.without(&[id])?;
                by_here.approximation = Some(&own);
            }
        }
        let d = diagnose_twin(&dir, &by_here)?;
        let text = d.to_json()?;
        std::fs::create_dir_all(&dirs.diagnoses).map_err(|e| {
            DiagnoseError::input("diagnoses", dirs.diagnoses.display(), &e.to_string())
        })?;
        let suffix = match (markers == plan.markers, markers) {
            (true, _) => "",
            (false, true) => "_markers",
            (false, false) => "_no_markers",
        };
        let out = dirs.diagnoses.join(format!("{name}{suffix}.json"));
        crate::io::write_atomic(&out, text.as_bytes())
            .map_err(|e| DiagnoseError::input("diagnosis", out.display(), &e.to_string()))?;
        let key: TwinKey = serde_json::from_str(
            &std::fs::read_to_string(&key_path)
                .map_err(|e| DiagnoseError::input("key", key_path.display(), &e.to_string()))?,
        )?;
        plan.check_key(&plan.groups[g].id, replicate, &key)?;
        let tips = truth_tips(plan, &plan.groups[g], noise_from, dirs)?;
        let lookup = |n: u32, t: f64, p: f64| {
            tips.iter()
                .find(|r| {
                    r.n_bellows == n
                        && (r.wall_thickness_mm - t).abs() < 1e-9
                        && (r.pressure_bar - p).abs() < 1e-9
                })
                .map(|r| (r.tip_uz_mm, r.tip_uy_mm))
        };
        let s = score_twin(&name, &d, &key, model, &lookup)?;
        progress(&format!(
            "{name}: concealed {}, named {}, first {}",
            s.truth.as_deref().unwrap_or("nothing"),
            s.named.as_deref().unwrap_or("nothing"),
            s.first.as_deref().unwrap_or("—")
        ));
        twins.push(s);
    }
    let summary = summarise(&twins);
    Ok(StudyResults {
        format: RESULTS_FORMAT.into(),
        version: VERSION,
        twins,
        pending,
        markers,
        mesh_reference: by.mesh_reference.map(|(_, n)| n.to_string()),
        approximation_error: by.approximation.map(|a| {
            format!(
                "the error of `{}` against {}, {} samples ({}); a null twin is diagnosed \
                 without the sample of its own group",
                a.model,
                a.reference,
                a.samples.len(),
                a.samples
                    .iter()
                    .map(|s| s.source.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }),
        summary,
    })
}

/// The results in Markdown: the targets, the confusion matrix, every twin.
pub fn study_markdown(plan: &StudyPlan, r: &StudyResults) -> String {
    use std::fmt::Write;
    let s = &r.summary;
    let mut o = String::new();
    let pct = |a: usize, b: usize| {
        if b == 0 {
            "—".to_string()
        } else {
            format!("{a} of {b} ({:.0} %)", 100.0 * a as f64 / b as f64)
        }
    };
    let _ = writeln!(o, "# Blind twin study: results\n");
    let _ = writeln!(
        o,
        "{} twins diagnosed ({} effect, {} null), {} pending. Twins on {} elements{}; seeds {:?}; markers {}.\n",
        r.twins.len(),
        s.effect_twins,
        s.nulls,
        r.pending.len(),
        plan.mesh.element_size.map_or(plan.mesh.level.name().to_string(), |h| format!("{h} mm")),
        plan.mesh.wall_elements.map_or(String::new(), |k| format!(", {k} through a wall")),
        plan.seeds,
        if r.markers { "used" } else { "left out (as the shipped experiments have none)" }
    );
    let _ = writeln!(
        o,
        "{}\n",
        match &r.mesh_reference {
            Some(m) => format!(
                "The diagnosing model's mesh error is projected out: its direction is the difference \
                 to `{m}` at the calibrated material (`diagnose::mesh_error`)."
            ),
            None => "The diagnosing model's mesh error is not tested as a direction.".to_string(),
        }
    );
    let _ = writeln!(
        o,
        "{}\n",
        match &r.approximation_error {
            Some(a) => format!(
                "Approximation error (`diagnose::approx_error`): {a}. The recordings are \
                 corrected by its mean; the Name stage weighs the residual by its covariance."
            ),
            None => "No approximation error: the recordings' σ alone weigh the residual.".into(),
        }
    );
    let _ = writeln!(o, "| target | result |\n|---|---|");
    let rows = [
        (
            "concealed effect ranked first, twins whose effect moves the tip > 2σ (≥ 90 %)",
            (s.visible_first, s.visible),
        ),
        (
            "… first or reported indistinguishable from the first",
            (s.visible_first_or_indistinguishable, s.visible),
        ),
        ("… named by the verdict", (s.visible_named, s.visible)),
        (
            "concealed effect ranked first, every effect twin",
            (s.effect_first, s.effect_twins),
        ),
        (
            "false alarms on null twins (≤ 10 %)",
            (s.false_alarms, s.nulls),
        ),
        (
            "recovered size within 25 % or interval covering the truth (correctly named)",
            s.sizes_recovered,
        ),
        (
            "held-out tip BE with the named effect ≤ 1.2 × noise (correctly named)",
            s.held_out_within,
        ),
    ];
    for (what, (a, b)) in rows {
        let _ = writeln!(o, "| {what} | {} |", pct(a, b));
    }
    if r.mesh_reference.is_some() {
        let _ = writeln!(
            o,
            "| the model's own mesh error explains the residual best (no physics named): effect twins, null twins | {}; {} |",
            pct(s.model_error_best.0, s.effect_twins),
            pct(s.model_error_best.1, s.nulls)
        );
    }
    let _ = writeln!(
        o,
        "\nOn the visible twins the recordings cannot tell the first candidate from {:.1} others \
         on average (of {:.1} ranked): the pairs whose signatures are collinear, or where the \
         better one adds nothing significant beyond the other, or neither one-effect fit is \
         significantly better (`diagnose::name`). \"First or indistinguishable\" counts those \
         twins too; it says the concealed effect is among what these recordings allow, not \
         that they single it out.",
        s.visible_mean_tied.0, s.visible_mean_tied.1
    );
    let _ = writeln!(
        o,
        "\n## Confusion matrix (rows: concealed, columns: named)\n"
    );
    let mut rows: Vec<String> = s.confusion.iter().map(|c| c.0.clone()).collect();
    rows.sort();
    rows.dedup();
    let mut cols: Vec<String> = s.confusion.iter().map(|c| c.1.clone()).collect();
    cols.sort();
    cols.dedup();
    let _ = writeln!(o, "| concealed \\ named | {} |", cols.join(" | "));
    let _ = writeln!(o, "|---|{}", "---|".repeat(cols.len()));
    for row in &rows {
        let cells: Vec<String> = cols
            .iter()
            .map(|c| {
                s.confusion
                    .iter()
                    .find(|x| &x.0 == row && &x.1 == c)
                    .map_or(String::new(), |x| x.2.to_string())
            })
            .collect();
        let _ = writeln!(o, "| {row} | {} |", cells.join(" | "));
    }
    let _ = writeln!(
        o,
        "\n## Every twin\n\n| twin | concealed | true value | tip move (σ) | named | first | rank | Name estimate | refit value [interval] | held-out BE before → after (noise) mm |"
    );
    let _ = writeln!(o, "|---|---|---|---|---|---|---|---|---|---|");
    for t in &r.twins {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {:.1} | {} | {} | {} | {} | {} | {} |",
            t.twin,
            t.truth.as_deref().unwrap_or("none"),
            t.true_value.map_or(String::new(), |v| format!("{v}")),
            t.tip_move_sigma,
            t.named.as_deref().unwrap_or("nothing"),
            t.first.as_deref().unwrap_or("—"),
            t.rank.map_or(String::new(), |k| k.to_string()),
            t.name_estimate
                .map_or(String::new(), |(v, se)| format!("{v:.4} ± {se:.4}")),
            t.refit_value.map_or(String::new(), |(v, lo, hi)| format!(
                "{v:.4} [{lo:.4}, {hi:.4}]"
            )),
            t.held_out_be.map_or(String::new(), |(b, a, n)| format!(
                "{b:.2} → {a:.2} ({n:.2})"
            ))
        );
    }
    if !r.pending.is_empty() {
        let _ = writeln!(o, "\nPending (FE not run yet): {}.", r.pending.join(", "));
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    fn twin(
        truth: Option<(&str, f64)>,
        named: Option<&str>,
        first: &str,
        rank: Option<usize>,
    ) -> TwinScore {
        TwinScore {
            twin: "t".into(),
            truth: truth.map(|t| t.0.to_string()),
            true_value: truth.map(|t| t.1),
            material: String::new(),
            tip_move_sigma: 3.0,
            named: named.map(str::to_string),
            first: Some(first.into()),
            rank,
            indistinguishable_from_first: false,
            tied_with_first: (0, 16),
            name_estimate: None,
            refit_value: None,
            held_out_be: None,
            verdict: String::new(),
            model_error_best: false,
        }
    }

    #[test]
    fn the_summary_counts_what_each_target_asks() {
        let mut a = twin(
            Some(("gap_bias", -0.3)),
            Some("gap_bias"),
            "gap_bias",
            Some(1),
        );
        a.refit_value = Some((-0.35, -0.4, -0.32)); // 17 % off: recovered
        a.held_out_be = Some((4.0, 3.0, 3.0)); // within 1.2 × noise
        let mut b = twin(
            Some(("gap_bias", -0.1)),
            Some("wall_bias"),
            "wall_bias",
            Some(2),
        );
        b.indistinguishable_from_first = true;
        b.tied_with_first = (3, 16);
        let mut c = twin(
            Some(("pressure_loss", 0.05)),
            Some("pressure_loss"),
            "pressure_loss",
            Some(1),
        );
        c.refit_value = Some((0.08, 0.07, 0.09)); // 60 % off, interval misses: not recovered
        c.held_out_be = Some((4.0, 3.7, 3.0)); // 1.23 × noise: outside
        let mut d = twin(Some(("plate_offset", -0.6)), None, "pressure_loss", Some(4));
        d.tip_move_sigma = 0.5; // invisible in the tip: outside the visible subset
        let mut mesh = twin(None, None, "model_mesh", None);
        mesh.model_error_best = true; // the model's own error, not physics: no false alarm
        let nulls = [
            twin(None, None, "anisotropy", None),
            twin(None, Some("gap_bias"), "gap_bias", None),
            mesh,
        ];
        let mut all = vec![a, b, c, d];
        all.extend(nulls);
        let s = summarise(&all);
        assert_eq!(s.visible, 3);
        assert_eq!(s.visible_first, 2);
        assert_eq!(s.visible_first_or_indistinguishable, 3);
        assert_eq!(s.visible_mean_tied, (1.0, 16.0));
        assert_eq!(s.visible_named, 2);
        assert_eq!((s.effect_twins, s.effect_first), (4, 2));
        assert_eq!((s.nulls, s.false_alarms), (3, 1));
        assert_eq!(s.model_error_best, (0, 1));
        assert_eq!(s.sizes_recovered, (1, 2));
        assert_eq!(s.held_out_within, (1, 2));
        let count = |r: &str, c: &str| {
            s.confusion
                .iter()
                .find(|x| x.0 == r && x.1 == c)
                .map_or(0, |x| x.2)
        };
        assert_eq!(count("gap_bias", "gap_bias"), 1);
        assert_eq!(count("gap_bias", "wall_bias"), 1);
        assert_eq!(count("plate_offset", "nothing"), 1);
        assert_eq!(count("none", "nothing"), 1);
        assert_eq!(count("none", "nothing (model's mesh)"), 1);
        assert_eq!(count("none", "gap_bias"), 1);
    }

    #[test]
    fn the_standard_plan_is_reproducible_and_inside_the_domain() {
        let model = Surrogate::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/actuator_coarse.json"),
        )
        .unwrap();
        let domain = ParamSpace::training_domain(&model).unwrap();
        let a = StudyPlan::standard(&domain, 7).unwrap();
        assert_eq!(a, StudyPlan::standard(&domain, 7).unwrap());
        assert_ne!(a.groups, StudyPlan::standard(&domain, 8).unwrap().groups);
        assert_eq!(a.groups.len(), 18);
        assert_eq!(a.twins().len(), 54);
        for g in &a.groups {
            let m = g
                .material
                .split(',')
                .map(|v| v.parse::<f64>().unwrap())
                .collect::<Vec<_>>();
            let set = OgdenSet::new(m[0], m[1], m[2], m[3]).unwrap();
            assert!(domain.contains(&set), "{}", g.material);
            g.settings(&a, 1, Path::new("/tmp")).unwrap();
        }
        assert_eq!(a.groups.iter().filter(|g| g.effects.is_empty()).count(), 6);
        assert_eq!(a.noise_seeds, NOISE_SEEDS);
    }

    /// The README's two processes: the effect groups in one, the null groups in the other.
    fn readme_split(plan: &StudyPlan) -> [Vec<String>; 2] {
        let (nulls, effects): (Vec<&TwinGroup>, Vec<&TwinGroup>) =
            plan.groups.iter().partition(|g| g.effects.is_empty());
        [effects, nulls].map(|gs| gs.iter().map(|g| g.id.clone()).collect())
    }

    fn seeds(plan: &StudyPlan) -> Vec<(String, u64)> {
        plan.twins()
            .into_iter()
            .map(|(g, r, name)| (name, plan.noise_seed(&plan.groups[g].id, r)))
            .collect()
    }

    #[test]
    fn every_twin_draws_its_own_noise_whichever_groups_a_run_is_given() {
        let model = Surrogate::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/actuator_coarse.json"),
        )
        .unwrap();
        let plan =
            StudyPlan::standard(&ParamSpace::training_domain(&model).unwrap(), 2026).unwrap();
        let all = seeds(&plan);
        let mut distinct: Vec<u64> = all.iter().map(|s| s.1).collect();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 54);
        // two runs split by `--groups`, and one run per group: the seeds of the whole plan
        let [effects, nulls] = readme_split(&plan);
        assert_eq!((effects.len(), nulls.len()), (12, 6));
        let mut split: Vec<(String, u64)> = [effects, nulls]
            .iter()
            .flat_map(|ids| seeds(&plan.only(ids).unwrap()))
            .collect();
        split.sort();
        let mut whole = all.clone();
        whole.sort();
        assert_eq!(split, whole);
        for g in &plan.groups {
            let one = seeds(&plan.only(std::slice::from_ref(&g.id)).unwrap());
            assert!(one.iter().all(|s| all.contains(s)), "{}", g.id);
        }
        // the groups given in another order: the plan's order, the same seeds
        let reversed: Vec<String> = plan.groups.iter().rev().map(|g| g.id.clone()).collect();
        assert_eq!(seeds(&plan.only(&reversed).unwrap()), all);
        // another draw seed, other noise
        let other = StudyPlan {
            draw_seed: 2027,
            ..plan.clone()
        };
        assert!(seeds(&other).iter().all(|s| !distinct.contains(&s.1)));
        // a group the plan lacks is named with the plan's groups
        let e = plan.only(&["null_9".to_string()]).unwrap_err().to_string();
        assert!(e.contains("null_9") && e.contains("null_6"), "{e}");
    }

    #[test]
    fn a_plan_of_an_older_noise_seed_derivation_reads_as_such_and_makes_no_twins() {
        let dir = std::env::temp_dir().join(format!("surrogate_study_plan_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("plan.json");
        let committed = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("fe_reference/diagnosis/blind/plan.json"),
        )
        .unwrap();
        let plan = StudyPlan::read(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("fe_reference/diagnosis/blind/plan.json"),
        )
        .unwrap();
        assert_eq!(plan.noise_seeds, NOISE_SEEDS);
        plan.check_noise_seeds().unwrap();
        let field = format!("\"noise_seeds\": {NOISE_SEEDS}");
        assert!(committed.contains(&field));
        for (old, scheme) in [
            ("\"independent_noise\": true", 1),
            ("\"independent_noise\": false", 0),
        ] {
            std::fs::write(&path, committed.replace(&field, old)).unwrap();
            let p = StudyPlan::read(&path).unwrap();
            assert_eq!(p.noise_seeds, scheme);
            let e = p.check_noise_seeds().unwrap_err().to_string();
            assert!(
                e.contains(&format!(
                    "plan noise_seeds = {scheme}: expected {NOISE_SEEDS}"
                )),
                "{e}"
            );
            let dirs = StudyDirs::under(&dir);
            let shipped = Recordings::shipped().unwrap();
            assert!(make_twins(&p, &shipped, &dirs, &|_| {}).is_err());
            assert!(!dirs.twins.exists() && !dirs.keys.exists());
        }
        // a key holds the plan's seed; one of another derivation is refused, named
        let key_path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fe_reference/diagnosis/blind/keys/null_1_s1.json");
        let mut key: TwinKey =
            serde_json::from_str(&std::fs::read_to_string(key_path).unwrap()).unwrap();
        plan.check_key("null_1", 1, &key).unwrap();
        assert!(plan.check_key("null_1", 2, &key).is_err());
        key.seed = 18_273_785_850_258_396_930; // derivation 1, the first group of a run
        let e = plan.check_key("null_1", 1, &key).unwrap_err().to_string();
        assert!(
            e.starts_with("seed of null_1_s1 = 18273785850258396930: expected"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
