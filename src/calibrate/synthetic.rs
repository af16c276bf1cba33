//! Synthetic recordings: model outputs at known parameters plus noise at the experiments'
//! standard deviations, in the experiments' own format. They test the calibrator (does it
//! recover what it was given, within the intervals it reports?).
//!
//! The noise of each configuration is the recorded scatter of the matching experimental row
//! (same `N, T, P`): the angle gets `N(0, σ_α)`, tip Uz and Uy each `N(0, r σ_α)` (the tip
//! noise model of [`super::objective`]), the force `N(0, σ_F)`; the standard-deviation columns
//! of the written records are the experiments' ones. Normal deviates come from a seeded
//! xoshiro256+ stream (Box–Muller), in record order: the same seed gives the same recordings.
//!
//! Marker recordings ([`noisy_markers`]) have no recorded scatter to copy: marker `k` gets the
//! tip's rule along its own chord, `σ_k = r_k σ_α` with `r_k = √((k·L_f/9 − Uz_k)² + Uy_k²)`
//! (σ_α in radians) for each component, from an independent stream of the same seed (the
//! generator's long jump), so adding markers changes no bending or force value.

use std::path::{Path, PathBuf};

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;
use serde::{Deserialize, Serialize};

use super::experiments::{BendingRecord, ForceRecord, MarkerRecord};
use super::objective::{Recordings, FREE_LENGTH_MM};
use super::CalibrateError;
use crate::random::standard_normal;

/// Noise-free outputs of one configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrueOutputs {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Tip Uz (mm).
    pub tip_uz_mm: f64,
    /// Tip Uy (mm).
    pub tip_uy_mm: f64,
    /// Angle (deg).
    pub angle_deg: f64,
    /// Blocked force (N); NaN when not simulated.
    pub force_n: f64,
}

impl TrueOutputs {
    /// The rows at `pressures` (bar) of every snapshot case file (`*.csv`, the columns of
    /// `surrogate snapshots run`) in `dir`, in file-name order: FE outputs at a known material,
    /// such as `fe_reference/calibration/synthetic_coarse/cases/cases/`.
    ///
    /// # Errors
    /// [`CalibrateError::Record`] for an unreadable file, a missing column or a bad number,
    /// naming the file, line and column.
    pub fn read_cases(dir: &Path, pressures: &[f64]) -> Result<Vec<Self>, CalibrateError> {
        let bad = |file: &Path, line: usize, column: &str, reason: String| CalibrateError::Record {
            source_name: file.display().to_string(),
            line,
            column: column.to_string(),
            reason,
        };
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| bad(dir, 0, "", e.to_string()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "csv"))
            .collect();
        files.sort();
        let mut out = Vec::new();
        for f in &files {
            let mut r = csv::Reader::from_path(f).map_err(|e| bad(f, 0, "", e.to_string()))?;
            let header = r
                .headers()
                .map_err(|e| bad(f, 1, "", e.to_string()))?
                .clone();
            let cols = CASE_COLUMNS.map(|name| header.iter().position(|c| c == name));
            for (i, rec) in r.records().enumerate() {
                let rec = rec.map_err(|e| bad(f, i + 2, "", e.to_string()))?;
                let mut v = [0.0; 7];
                for (k, name) in CASE_COLUMNS.iter().enumerate() {
                    let text = cols[k].and_then(|c| rec.get(c));
                    v[k] = text.and_then(|t| t.parse().ok()).ok_or_else(|| {
                        bad(f, i + 2, name, format!("expected a number, got {text:?}"))
                    })?;
                }
                if pressures.contains(&v[2]) {
                    out.push(TrueOutputs {
                        n_bellows: v[0] as usize,
                        wall_thickness_mm: v[1],
                        pressure_bar: v[2],
                        tip_uz_mm: v[3],
                        tip_uy_mm: v[4],
                        angle_deg: v[5],
                        force_n: v[6],
                    });
                }
            }
        }
        Ok(out)
    }
}

/// The columns of a snapshot case file that [`TrueOutputs::read_cases`] reads, in the order of
/// the fields of [`TrueOutputs`].
const CASE_COLUMNS: [&str; 7] = [
    "n_bellows",
    "wall_thickness_mm",
    "pressure_bar",
    "tip_uz_mm",
    "tip_uy_mm",
    "angle_deg",
    "force_n",
];

/// Recordings of `truth` with noise at the scatter of the matching rows of `noise_from`.
///
/// # Errors
/// A configuration of `truth` without a matching row in `noise_from` (naming it).
pub fn noisy_recordings(
    truth: &[TrueOutputs],
    noise_from: &Recordings,
    seed: u64,
    source: &str,
) -> Result<Recordings, CalibrateError> {
    recordings_with_noise(truth, noise_from, seed, source, 1.0)
}

/// Recordings of `truth` without noise, with the standard deviations of the matching rows of
/// `noise_from` (what a reference model says exactly, in the recordings' format).
///
/// # Errors
/// As [`noisy_recordings`].
pub fn exact_recordings(
    truth: &[TrueOutputs],
    noise_from: &Recordings,
    source: &str,
) -> Result<Recordings, CalibrateError> {
    recordings_with_noise(truth, noise_from, 0, source, 0.0)
}

fn recordings_with_noise(
    truth: &[TrueOutputs],
    noise_from: &Recordings,
    seed: u64,
    source: &str,
    scale: f64,
) -> Result<Recordings, CalibrateError> {
    let mut rng = Xoshiro256Plus::seed_from_u64(seed);
    let mut bending = Vec::new();
    let mut force = Vec::new();
    let same = |n: usize, t: f64, p: f64, t0: &TrueOutputs| {
        n == t0.n_bellows
            && (t - t0.wall_thickness_mm).abs() < 1e-9
            && (p - t0.pressure_bar).abs() < 1e-9
    };
    for t in truth {
        let b = noise_from
            .bending
            .iter()
            .find(|r| same(r.n_bellows, r.wall_thickness_mm, r.pressure_bar, t))
            .ok_or_else(|| {
                CalibrateError::input(
                    "synthetic configuration",
                    format!(
                        "N={} T={} P={}",
                        t.n_bellows, t.wall_thickness_mm, t.pressure_bar
                    ),
                    "a configuration of the noise source's bending recordings",
                )
            })?;
        let sa = b.angle_std_deg;
        let st = (FREE_LENGTH_MM - t.tip_uz_mm).hypot(t.tip_uy_mm) * sa.to_radians();
        let (nt, na) = (scale * st, scale * sa);
        bending.push(BendingRecord {
            n_bellows: t.n_bellows,
            wall_thickness_mm: t.wall_thickness_mm,
            pressure_bar: t.pressure_bar,
            tip_uz_mm: t.tip_uz_mm + nt * standard_normal(&mut rng),
            tip_uy_mm: t.tip_uy_mm + nt * standard_normal(&mut rng),
            angle_deg: t.angle_deg + na * standard_normal(&mut rng),
            angle_std_deg: sa,
        });
        if t.force_n.is_finite() {
            if let Some(f) = noise_from
                .force
                .iter()
                .find(|r| same(r.n_bellows, r.wall_thickness_mm, r.pressure_bar, t))
            {
                force.push(ForceRecord {
                    n_bellows: t.n_bellows,
                    wall_thickness_mm: t.wall_thickness_mm,
                    pressure_bar: t.pressure_bar,
                    force_n: t.force_n + scale * f.force_std_n * standard_normal(&mut rng),
                    force_std_n: f.force_std_n,
                });
            }
        }
    }
    Ok(Recordings {
        bending,
        force,
        markers: Vec::new(),
        bending_source: format!("{source} (bending)"),
        force_source: format!("{source} (force)"),
        markers_source: String::new(),
        files: Vec::new(),
    })
}

/// Noise-free markers of one configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrueMarkers {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Markers 1..9: `[Uz, Uy]` (mm).
    pub markers: [[f64; 2]; 9],
}

/// Marker recordings of `truth`, each component with noise `N(0, r_k σ_α)` (see the
/// [module docs](self)), `σ_α` from the matching bending row of `noise_from`; the standard
/// deviation column holds `r_k σ_α`.
///
/// # Errors
/// A configuration of `truth` without a matching bending row in `noise_from` (naming it).
pub fn noisy_markers(
    truth: &[TrueMarkers],
    noise_from: &Recordings,
    seed: u64,
) -> Result<Vec<MarkerRecord>, CalibrateError> {
    markers_with_noise(truth, noise_from, seed, 1.0)
}

/// Marker recordings of `truth` without noise, the standard deviation column as
/// [`noisy_markers`] writes it.
///
/// # Errors
/// As [`noisy_markers`].
pub fn exact_markers(
    truth: &[TrueMarkers],
    noise_from: &Recordings,
) -> Result<Vec<MarkerRecord>, CalibrateError> {
    markers_with_noise(truth, noise_from, 0, 0.0)
}

fn markers_with_noise(
    truth: &[TrueMarkers],
    noise_from: &Recordings,
    seed: u64,
    scale: f64,
) -> Result<Vec<MarkerRecord>, CalibrateError> {
    let mut rng = Xoshiro256Plus::seed_from_u64(seed);
    rng.long_jump();
    let mut out = Vec::with_capacity(9 * truth.len());
    for t in truth {
        let b = noise_from
            .bending
            .iter()
            .find(|r| {
                r.n_bellows == t.n_bellows
                    && (r.wall_thickness_mm - t.wall_thickness_mm).abs() < 1e-9
                    && (r.pressure_bar - t.pressure_bar).abs() < 1e-9
            })
            .ok_or_else(|| {
                CalibrateError::input(
                    "synthetic configuration",
                    format!(
                        "N={} T={} P={}",
                        t.n_bellows, t.wall_thickness_mm, t.pressure_bar
                    ),
                    "a configuration of the noise source's bending recordings",
                )
            })?;
        for (k, m) in t.markers.iter().enumerate() {
            let z = FREE_LENGTH_MM * (k + 1) as f64 / 9.0;
            let std = (z - m[0]).hypot(m[1]) * b.angle_std_deg.to_radians();
            out.push(MarkerRecord {
                n_bellows: t.n_bellows,
                wall_thickness_mm: t.wall_thickness_mm,
                pressure_bar: t.pressure_bar,
                marker: k + 1,
                uz_mm: m[0] + scale * std * standard_normal(&mut rng),
                uy_mm: m[1] + scale * std * standard_normal(&mut rng),
                std_mm: std,
            });
        }
    }
    Ok(out)
}
