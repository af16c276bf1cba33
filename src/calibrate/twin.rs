//! Twin recordings: what the rigs would have recorded on actuators whose physics includes a
//! concealed effect, for testing whoever has to find it (the diagnoser, a person).
//!
//! ```text
//!   noise source (bending, force files) ──► designs and pressures, σ_α and σ_F per row
//!        │
//!   TwinSettings (material, mesh, contact, effects) ──► baseline sweep (cached ramps) ──► truth
//!        │                                                                                │
//!        └──────────────── seed ──► noise (synthetic) ──► DIR/bending_experiments.csv ◄───┘
//!                                                         DIR/blocked_force_experiments.csv
//!                                                         DIR/marker_experiments.csv
//!   KEYFILE (optional, outside DIR): effects, material, mesh, seed (and how it was derived),
//!                                    code version and commit
//! ```
//!
//! **Designs and pressures** are those of the noise source's bending rows (the 9 experimental
//! designs at 1, 2, 3 bar for `training_data/`); each design gets one bending and one
//! blocked-force ramp through 0 and its pressures, gravity and contact on, exactly as the
//! literature baseline ([`super::baseline`]) runs them. A noise source without forces gives
//! bending ramps only, and a twin without a force file.
//!
//! **Noise** ([`super::synthetic`]): the angle gets `N(0, σ_α)` and the force `N(0, σ_F)`
//! with the standard deviations of the matching rows of the noise source; the files give none
//! for the tip, so tip Uz and Uy each get `N(0, r σ_α)`, `r = √((L_f − Uz)² + Uy²)` the chord
//! from the support to the tip (σ_α in radians: the angle's scatter moved across the chord,
//! the noise model of [`super::objective`]); marker `k` the same along its own chord. The
//! deviates come from a xoshiro256+ stream seeded with the twin's seed: the same seed gives
//! the same files, byte for byte.
//!
//! **Format**: exactly the columns of the shipped files ([`crate::schema`]: `bending`,
//! `force`, `markers`), rows in the noise source's order, displacements and angles to
//! 0.01 mm / 0.01°, forces to 0.001 N (the precision of the shipped tables), the standard
//! deviation columns as given by the noise source. A configuration whose ramp stopped before
//! its pressure has no row (reported in [`TwinOutcome::missing`]).
//!
//! **Concealment**: the output directory holds those files and nothing else; the settings go
//! to the key file only, which must lie outside it, and so must the FE cache.
//!
//! **Cache**: every ramp is cached as the baseline sweep caches it (keyed by every setting),
//! under `cache/twin_<hash of the settings>/`: an interrupted twin resumes, and a twin with
//! another seed (or another noise source with the same designs and pressures) runs no FE.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::baseline::{recorded_designs, run_ramps, BaselineError, RampSource, SweepSettings};
use super::experiments::{
    BendingRecord, ExperimentError, ForceRecord, MarkerRecord, BENDING_FILE, FORCE_FILE,
    MARKERS_FILE,
};
use super::objective::Recordings;
use super::synthetic::{
    exact_markers, exact_recordings, noisy_markers, noisy_recordings, TrueMarkers, TrueOutputs,
};
use super::CalibrateError;
use crate::fe::effects::Effects;
use crate::fe::material::Material;
use crate::fe::mesh::MeshOptions;
use crate::fe::preset::Geometry;
use crate::fe::simulate::{ContactSettings, Mode};
use crate::schema;

/// Errors of [`write_twin`].
#[derive(Debug, Error)]
pub enum TwinError {
    /// A setting that cannot be used.
    #[error("{field} = {value}: expected {expected}")]
    Input {
        /// The setting.
        field: String,
        /// Its value.
        value: String,
        /// What is allowed.
        expected: String,
    },
    /// A file or directory that cannot be written.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The FE ramps (a design out of range, an unwritable cache).
    #[error(transparent)]
    Baseline(#[from] BaselineError),
    /// The noise source's files.
    #[error(transparent)]
    Experiments(#[from] ExperimentError),
    /// The noise: a configuration without a matching row in the noise source.
    #[error(transparent)]
    Calibrate(#[from] CalibrateError),
}

impl TwinError {
    fn input(field: &str, value: impl std::fmt::Display, expected: &str) -> Self {
        TwinError::Input {
            field: field.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }

    fn io(path: &Path, source: std::io::Error) -> Self {
        TwinError::Io {
            path: path.display().to_string(),
            source,
        }
    }
}

/// What a twin is made of.
#[derive(Clone, Debug)]
pub struct TwinSettings {
    /// The FE settings of every ramp: material, mesh, contact, the concealed effects.
    pub sweep: SweepSettings,
    /// The material as named by the user (`ogden_002`, `mu1,alpha1,mu2,alpha2`), for the key.
    pub material_spec: String,
    /// Seed of the noise.
    pub seed: u64,
    /// How `seed` was derived, for the key, when it was (a study's twin); `None`: given.
    pub seed_origin: Option<String>,
    /// Root of the FE cache (outside the output directory).
    pub cache: PathBuf,
    /// Where the key goes (outside the output directory); `None`: no key file.
    pub key: Option<PathBuf>,
    /// The commit of the model's source, for the key (`None`: unknown).
    pub commit: Option<String>,
}

impl TwinSettings {
    /// A twin of `material` (named `material_spec`) on `mesh` with `effects`, gravity and
    /// default contact, noise seed `seed`, FE cache under `cache`, no key file.
    pub fn new(
        material: Material,
        material_spec: &str,
        mesh: MeshOptions,
        effects: Effects,
        seed: u64,
        cache: &Path,
    ) -> Self {
        Self {
            sweep: SweepSettings {
                effects,
                ..SweepSettings::new(material, mesh)
            },
            material_spec: material_spec.to_string(),
            seed,
            seed_origin: None,
            cache: cache.to_path_buf(),
            key: None,
            commit: None,
        }
    }

    /// The directory of this twin's ramps: `cache/twin_<CRC-32 of the FE settings>`. Twins
    /// that differ only in their seed or noise source share it.
    pub fn ramp_dir(&self) -> PathBuf {
        let s = &self.sweep;
        let mut key = serde_json::json!({
            "material": s.material,
            "mesh": s.mesh,
            "contact": s.contact,
            "effects": s.effects,
            "solver": s.solver,
            "gravity": s.gravity,
        });
        // another geometry, another folder; the geometry as modelled keeps the old names
        if !s.geometry.is_as_modelled() {
            key["geometry"] = serde_json::json!(s.geometry);
        }
        let hash = crc32fast::hash(key.to_string().as_bytes());
        self.cache.join(format!("twin_{hash:08x}"))
    }
}

/// The key of a twin: everything it conceals (written to the key file only).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwinKey {
    /// The concealed effects (`{name: value}`).
    pub effects: Effects,
    /// The material as named.
    pub material: String,
    /// The material's parameters as simulated.
    pub material_parameters: Material,
    /// Mesh level and options.
    pub mesh: MeshOptions,
    /// Contact settings.
    pub contact: ContactSettings,
    /// The dimensions the reference study leaves unstated, as simulated; absent for the
    /// geometry as modelled (so keys written before it keep their bytes).
    #[serde(default, skip_serializing_if = "Geometry::is_as_modelled")]
    pub geometry: Geometry,
    /// Seed of the noise.
    pub seed: u64,
    /// How `seed` was derived, when a study derived it from the twin's place in its plan
    /// (`surrogate.twin-study-plan noise seeds 2: draw seed 2026, group null_1, replicate
    /// 1`, [`crate::diagnose::study::NOISE_SEEDS`]); absent for a seed given as such, and in
    /// study keys written before the derivation was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed_origin: Option<String>,
    /// Where the standard deviations came from.
    pub noise_from: String,
    /// Version of the program ([`crate::snapshots::code_version`]).
    pub code_version: String,
    /// Commit of the model's source, if known.
    pub commit: Option<String>,
}

/// What [`write_twin`] did.
#[derive(Clone, Debug)]
pub struct TwinOutcome {
    /// The files written into the output directory.
    pub files: Vec<PathBuf>,
    /// Rows written (bending, force, markers).
    pub rows: [usize; 3],
    /// FE ramps run now.
    pub ramps_run: usize,
    /// FE ramps read from the cache.
    pub ramps_cached: usize,
    /// Configurations without a row (`N, T, P` and why): their ramp stopped before.
    pub missing: Vec<String>,
    /// The directory of the cached ramps.
    pub ramp_dir: PathBuf,
    /// The key (written to [`TwinSettings::key`] if given).
    pub key: TwinKey,
}

/// Whether `inner` lies in `dir` (both as absolute paths, without resolving links that do
/// not exist yet).
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn lies_in(inner: &Path, dir: &Path) -> bool {
    let abs = |p: &Path| -> PathBuf {
        let p = if p.is_absolute() {
            p.to_path_buf()
        } else {
            std::env::current_dir().unwrap_or_default().join(p)
        };
        // resolve the longest existing prefix
        let mut existing = p.clone();
        let mut rest = Vec::new();
        while !existing.exists() {
            match (existing.file_name(), existing.parent()) {
                (Some(name), Some(parent)) => {
                    rest.push(name.to_os_string());
                    existing = parent.to_path_buf();
                }
                _ => break,
            }
        }
        let mut out = existing.canonicalize().unwrap_or(existing);
        out.extend(rest.iter().rev());
        out
    };
    abs(inner).starts_with(abs(dir))
}

/// Writes the twin recordings of `settings` into `out` (created if needed), with the noise
/// of `noise_from` ([`Recordings::read_dir`] reads `training_data/`), and the key to
/// [`TwinSettings::key`]; `progress(done, total)` after every FE ramp.
///
/// # Errors
/// A key file or cache inside `out` ([`TwinError::Input`]); an invalid design; a cache or
/// output that cannot be written.
pub fn write_twin(
    settings: &TwinSettings,
    noise_from: &Recordings,
    out: &Path,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<TwinOutcome, TwinError> {
    if let Some(key) = settings.key.as_deref().filter(|k| lies_in(k, out)) {
        return Err(TwinError::input(
            "key",
            key.display(),
            &format!(
                "a file outside the twin's directory {} (nothing there may reveal the effect)",
                out.display()
            ),
        ));
    }
    if lies_in(&settings.cache, out) {
        return Err(TwinError::input(
            "cache",
            settings.cache.display(),
            &format!(
                "a directory outside the twin's directory {} (cached ramps name their settings)",
                out.display()
            ),
        ));
    }
    let ramp_dir = settings.ramp_dir();
    let designs = recorded_designs(&noise_from.bending);
    // recordings without forces need no blocked-force ramps
    let sweep = SweepSettings {
        force: !noise_from.force.is_empty(),
        ..settings.sweep.clone()
    };
    let ramps = run_ramps(&sweep, &designs, Some(&ramp_dir), progress)?;
    let ramps_run = ramps.iter().filter(|r| r.source == RampSource::Run).count();
    let (truth, markers, missing) = truth(&ramps, &noise_from.bending);
    let noisy = noisy_recordings(&truth, noise_from, settings.seed, "twin")?;
    let markers = noisy_markers(&markers, noise_from, settings.seed)?;
    std::fs::create_dir_all(out).map_err(|e| TwinError::io(out, e))?;
    let texts = [
        (BENDING_FILE, bending_csv(&noisy.bending)),
        (FORCE_FILE, force_csv(&noisy.force)),
        (MARKERS_FILE, markers_csv(&markers)),
    ];
    let mut files = Vec::new();
    for (name, text) in texts {
        let path = out.join(name);
        // recordings without forces have no force file (the loader says so and goes on);
        // one left by an earlier twin in the same directory would be read as this one's
        if name == FORCE_FILE && noisy.force.is_empty() {
            match std::fs::remove_file(&path) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(TwinError::io(&path, e)),
            }
            continue;
        }
        crate::io::write_atomic(&path, text.as_bytes()).map_err(|e| TwinError::io(&path, e))?;
        files.push(path);
    }
    let s = &settings.sweep;
    let key = TwinKey {
        effects: s.effects.clone(),
        material: settings.material_spec.clone(),
        material_parameters: s.material.clone(),
        mesh: s.mesh,
        contact: s.contact,
        geometry: s.geometry.clone(),
        seed: settings.seed,
        seed_origin: settings.seed_origin.clone(),
        noise_from: noise_from.bending_source.clone(),
        code_version: crate::snapshots::code_version(),
        commit: settings.commit.clone(),
    };
    if let Some(path) = &settings.key {
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(|e| TwinError::io(parent, e))?;
        }
        let text = serde_json::to_string_pretty(&key)
            .map_err(|e| TwinError::input("key", path.display(), &e.to_string()))?;
        crate::io::write_atomic(path, text.as_bytes()).map_err(|e| TwinError::io(path, e))?;
    }
    Ok(TwinOutcome {
        files,
        rows: [noisy.bending.len(), noisy.force.len(), markers.len()],
        ramps_run,
        ramps_cached: ramps.len() - ramps_run,
        missing,
        ramp_dir,
        key,
    })
}

/// The noise-free recordings of `ramps` (bending, force and markers) at the designs,
/// pressures and standard deviations of `noise_from`, named `source`: what the FE model
/// says exactly, in the recordings' format. Rows whose ramps stopped short are left out.
///
/// # Errors
/// A configuration without a matching row in `noise_from`.
pub fn exact_twin_recordings(
    ramps: &[super::baseline::SweepRamp],
    noise_from: &Recordings,
    source: &str,
) -> Result<Recordings, CalibrateError> {
    let (truth, markers, _) = truth(ramps, &noise_from.bending);
    let mut rec = exact_recordings(&truth, noise_from, source)?;
    rec.markers = exact_markers(&markers, noise_from)?;
    rec.markers_source = format!("{source} (markers)");
    Ok(rec)
}

/// The noise-free outputs of every bending row reached by both ramps of its design, its
/// markers, and the rows left out (with the reason).
fn truth(
    ramps: &[super::baseline::SweepRamp],
    bending: &[BendingRecord],
) -> (Vec<TrueOutputs>, Vec<TrueMarkers>, Vec<String>) {
    let (mut truth, mut markers, mut missing) = (Vec::new(), Vec::new(), Vec::new());
    // a sweep of bending ramps only (recordings without forces): no force in the truth
    let with_force = ramps.iter().any(|r| r.mode == Mode::Force);
    for rec in bending {
        let (n, t, p) = (rec.n_bellows, rec.wall_thickness_mm, rec.pressure_bar);
        let ramp = |mode: Mode| {
            ramps
                .iter()
                .find(|r| r.mode == mode && r.n_bellows == n && r.wall_thickness_mm == t)
        };
        let (b, f) = (ramp(Mode::Bending), ramp(Mode::Force));
        let (bs, fs) = (b.and_then(|r| r.at(p)), f.and_then(|r| r.at(p)));
        let force = if with_force {
            fs.and_then(|s| s.force_n)
        } else {
            Some(f64::NAN)
        };
        match (bs, force) {
            (Some(s), Some(force_n)) => {
                truth.push(TrueOutputs {
                    n_bellows: n,
                    wall_thickness_mm: t,
                    pressure_bar: p,
                    tip_uz_mm: s.tip_uz_mm,
                    tip_uy_mm: s.tip_uy_mm,
                    angle_deg: s.angle_deg,
                    force_n,
                });
                markers.push(TrueMarkers {
                    n_bellows: n,
                    wall_thickness_mm: t,
                    pressure_bar: p,
                    markers: std::array::from_fn(|k| {
                        s.markers.get(k).copied().unwrap_or([f64::NAN; 2])
                    }),
                });
            }
            _ => {
                let why = |r: Option<&super::baseline::SweepRamp>, what: &str| {
                    r.map_or(format!("{what}: not run"), |r| {
                        format!("{what}: {}", r.error)
                    })
                };
                missing.push(format!(
                    "N = {n}, T = {t} mm, P = {p} bar ({}; {})",
                    why(b, "bending"),
                    why(f, "force")
                ));
            }
        }
    }
    (truth, markers, missing)
}

/// `x` to `digits` decimals, without a negative zero.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn fixed(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

fn lines(header: &[&str], rows: impl Iterator<Item = Vec<String>>) -> String {
    let mut out = header.join(",");
    out.push('\n');
    for r in rows {
        out.push_str(&r.join(","));
        out.push('\n');
    }
    out
}

/// A bending file's text (the shipped file's columns and precision).
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn bending_csv(rows: &[BendingRecord]) -> String {
    lines(
        &schema::names(&schema::BENDING_COLUMNS),
        rows.iter().map(|r| {
            vec![
                r.n_bellows.to_string(),
                r.wall_thickness_mm.to_string(),
                r.pressure_bar.to_string(),
                fixed(r.tip_uz_mm, 2),
                fixed(r.tip_uy_mm, 2),
                fixed(r.angle_deg, 2),
                r.angle_std_deg.to_string(),
            ]
        }),
    )
}

/// A blocked-force file's text.
// public for the tests in tests/calibrate/
#[doc(hidden)]
pub fn force_csv(rows: &[ForceRecord]) -> String {
    lines(
        &schema::names(&schema::FORCE_COLUMNS),
        rows.iter().map(|r| {
            vec![
                r.n_bellows.to_string(),
                r.wall_thickness_mm.to_string(),
                r.pressure_bar.to_string(),
                fixed(r.force_n, 3),
                r.force_std_n.to_string(),
            ]
        }),
    )
}

/// A marker file's text (standard deviations to 0.001 mm, never rounded to 0).
fn markers_csv(rows: &[MarkerRecord]) -> String {
    lines(
        &schema::names(&schema::MARKER_RECORDING_COLUMNS),
        rows.iter().map(|r| {
            vec![
                r.n_bellows.to_string(),
                r.wall_thickness_mm.to_string(),
                r.pressure_bar.to_string(),
                r.marker.to_string(),
                fixed(r.uz_mm, 2),
                fixed(r.uy_mm, 2),
                fixed(r.std_mm.max(0.001), 3),
            ]
        }),
    )
}
