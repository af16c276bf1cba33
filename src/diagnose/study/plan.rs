//! The study's plan: groups of twins (effects and a material each), their seeds and mesh;
//! the standard plan, and each twin's noise seed.

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use crate::calibrate::twin::{TwinKey, TwinSettings};
use crate::calibrate::ParamSpace;
use crate::case::OgdenSet;
use crate::diagnose::approx_error::lhs;
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effects;
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::mesh::{MeshLevel, MeshOptions};
use crate::random::splitmix64;

/// The `format` field of a study plan.
pub const PLAN_FORMAT: &str = "surrogate.twin-study-plan";

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
