//! The diagnosing model's approximation error as a random quantity, estimated from a finer
//! reference model at sample materials (the Bayesian approximation error approach of Kaipio
//! and Somersalo, *J. Comput. Appl. Math.* 198, 2007).
//!
//! A surrogate trained on one mesh differs from any other discretisation (and from a real
//! actuator) by its own error `ε(θ) = ŷ_model(θ) − y_reference(θ)`, which depends on the
//! material `θ` and on the design. A single direction of that error
//! ([`super::mesh_error`]) leaves most of it in the residual, where effects whose signatures
//! resemble it compete for it. Here `ε` is sampled: at `K` materials `θ_k` the reference
//! model's exact outputs are compared with the surrogate's, per recorded number, and
//!
//! ```text
//!   ε̄ᵢ = (1/K) Σ_k εᵢ(θ_k)                     (mean error, unit of the output)
//!   Γ_ε = (1/(K−1)) Σ_k (ε(θ_k) − ε̄)(ε(θ_k) − ε̄)ᵀ    (its covariance, rank ≤ K − 1)
//! ```
//!
//! Recordings `y` are corrected by the mean, `y + ε̄` (what the surrogate would predict for
//! the reference's actuator: [`ApproximationError::correct`]), and the Name stage weighs
//! the residual by `(I + Γ̃)⁻¹`, `Γ̃` the covariance in the recordings' σ
//! ([`ApproximationError::spread`]): the directions along which the model's own error
//! varies between materials count for less than noise alone would. A number the samples
//! do not cover (a pressure or marker the reference lacks) gets no correction.
//!
//! The samples are the user's to choose: reference FE runs of the recorded designs at
//! materials spread over the surrogate's domain, without any effect (the blind study uses
//! its null twins, leaving each scored twin's own material out).

use std::path::{Path, PathBuf};

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use super::cells::Cell;
use super::DiagnoseError;
use crate::calibrate::baseline::{cached_ramps, recorded_designs, run_ramps, RampSource};
use crate::calibrate::objective::{Evaluator, ObservationSet, Output, Selection, Weights};
use crate::calibrate::twin::{exact_twin_recordings, TwinSettings};
use crate::calibrate::{ParamSpace, Recordings};
use crate::case::OgdenSet;
use crate::fe::effects::Effects;
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::mesh::MeshOptions;
use crate::rom::Surrogate;

/// `model`'s checksum, as its file carries it.
fn model_checksum(model: &Surrogate) -> Result<String, DiagnoseError> {
    model
        .checksum()
        .map_err(|e| DiagnoseError::Calibrate(e.into()))
}

/// The `format` field of an approximation-error file.
pub const FORMAT: &str = "surrogate.approximation-error";
/// The version this code writes and reads.
pub const VERSION: u32 = 1;

/// The model's error at one recorded number of one sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorValue {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// The output.
    pub output: Output,
    /// `ŷ_model − y_reference` (unit of the output).
    pub error: f64,
}

/// One sample of the model's error: the reference at one material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorSample {
    /// What the reference is (a twin group, a file).
    pub source: String,
    /// The material of both.
    pub material: OgdenSet,
    /// Per recorded number.
    pub values: Vec<ErrorValue>,
}

/// Samples of the model's approximation error (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ApproximationError {
    /// [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The diagnosing model's provenance, as its file states it.
    pub model: String,
    /// What the reference model is.
    pub reference: String,
    /// The samples.
    pub samples: Vec<ErrorSample>,
    /// The checksum of the model the samples were taken with ([`Surrogate::checksum`]),
    /// checked against the diagnosing model by [`ApproximationError::check_model`] (absent
    /// in files written before 2026-12-06: not checked).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_checksum: Option<String>,
}

/// The covariance of the model's error over the cells of a residual table, as deviations
/// (`Γ = D Dᵀ`, each column one sample's deviation from the mean over `√(K − 1)`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorSpread {
    /// The samples' sources, in column order.
    pub sources: Vec<String>,
    /// Per sample, per cell of the table: the deviation in the unit of the cell's output
    /// (0 where the sample lacks the cell).
    pub deviations: Vec<Vec<f64>>,
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

impl ErrorSample {
    /// The error of `model` against `reference` (exact recordings of a reference model at
    /// `material`, as [`crate::calibrate::twin::exact_twin_recordings`] writes them), named
    /// `source`.
    ///
    /// # Errors
    /// A material outside the model's training domain, recordings outside its designs.
    pub fn measure(
        model: &Surrogate,
        source: &str,
        material: &OgdenSet,
        reference: &Recordings,
    ) -> Result<Self, DiagnoseError> {
        let space = ParamSpace::training_domain(model)?;
        let u = space.unit(material);
        if u.iter().any(|v| !(-1e-9..=1.0 + 1e-9).contains(v)) {
            return Err(DiagnoseError::input(
                "approximation-error sample",
                format!("{source} at {}", material.spec()),
                "a material inside the surrogate's training domain",
            ));
        }
        let u = u.map(|v| v.clamp(0.0, 1.0));
        let weights = Weights {
            tip: 1.0,
            angle: 1.0,
            force: if reference.force.is_empty() { 0.0 } else { 1.0 },
            markers: if reference.markers.is_empty() {
                0.0
            } else {
                1.0
            },
        };
        let set = ObservationSet::build(model, reference, &weights, &Selection::default())?;
        let pred = Evaluator::new(model, &set, space).predictions(&u)?;
        let values = set
            .obs
            .iter()
            .zip(&pred)
            .filter(|(o, p)| o.value.is_finite() && p.is_finite())
            .map(|(o, p)| ErrorValue {
                n_bellows: o.config.n_bellows,
                wall_thickness_mm: o.config.wall_thickness_mm,
                pressure_bar: o.config.pressure_bar,
                output: o.output,
                error: p - o.value,
            })
            .collect();
        Ok(ErrorSample {
            source: source.to_string(),
            material: *material,
            values,
        })
    }

    /// Its error at one recorded number, if it has it.
    pub fn at(&self, n: u32, t: f64, p: f64, o: Output) -> Option<f64> {
        self.values
            .iter()
            .find(|v| {
                v.n_bellows == n
                    && same(v.wall_thickness_mm, t)
                    && same(v.pressure_bar, p)
                    && v.output == o
            })
            .map(|v| v.error)
    }
}

/// `n` points of a Latin hypercube in `[0, 1)^dims`.
pub(crate) fn lhs(rng: &mut Xoshiro256PlusPlus, n: usize, dims: usize) -> Vec<Vec<f64>> {
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(dims);
    for _ in 0..dims {
        let mut c: Vec<f64> = (0..n)
            .map(|i| (i as f64 + rng.gen::<f64>()) / n as f64)
            .collect();
        for i in (1..n).rev() {
            let j = rng.gen_range(0..=i);
            c.swap(i, j);
        }
        cols.push(c);
    }
    (0..n)
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect()
}

/// How [`sample`] runs its reference: the reference FE's mesh, the materials, the cache.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleSettings {
    /// The reference's discretisation (finer than the model's, or another one).
    pub mesh: MeshOptions,
    /// The materials of the samples.
    pub materials: Vec<OgdenSet>,
    /// Root of the FE cache (`twin_<hash>` per material, shared with `surrogate twin`).
    pub cache: PathBuf,
    /// Whether ramps missing from the cache are run (otherwise they are an error).
    pub run_fe: bool,
}

/// `k` materials by a Latin hypercube over the central 80 % of `domain` (in its sampling
/// coordinates), drawn with `seed`, rounded to 4 significant digits.
///
/// # Errors
/// `k < 2`; a draw outside the admissible sets (not for a training domain).
pub fn spread_materials(
    domain: &ParamSpace,
    k: usize,
    seed: u64,
) -> Result<Vec<OgdenSet>, DiagnoseError> {
    if k < 2 {
        return Err(DiagnoseError::input(
            "materials",
            k,
            "at least 2 (the covariance needs two)",
        ));
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    lhs(&mut rng, k, 4)
        .into_iter()
        .map(|u| {
            let u: [f64; 4] = std::array::from_fn(|i| 0.1 + 0.8 * u[i]);
            Ok(domain.ogden(&u)?.rounded(4))
        })
        .collect()
}

/// Samples the approximation error of `model` (named `model_name`): the reference FE of
/// every design of `noise_from` on `s.mesh` at each of `s.materials`, built as the model was
/// (its geometry and fixed effects, [`crate::rom::provenance::TrainingInfo::built_with`];
/// as modelled when it states none) and without any other effect
/// (cached and resumable, 2 ramps per design and material), its exact outputs against the
/// model's. `progress(material, ramps done, ramps)` after every ramp.
///
/// # Errors
/// A ramp missing from the cache when `s.run_fe` is off, an FE or cache error, a material
/// outside the model's domain, fewer than two materials.
pub fn sample(
    model: &Surrogate,
    model_name: &str,
    s: &SampleSettings,
    noise_from: &Recordings,
    progress: &(dyn Fn(usize, usize, usize) + Sync),
) -> Result<ApproximationError, DiagnoseError> {
    let designs = recorded_designs(&noise_from.bending);
    let mut samples = Vec::new();
    for (k, m) in s.materials.iter().enumerate() {
        let spec = m.spec();
        let material = Material::from_spec(&spec, DEFAULT_BULK_RATIO)
            .map_err(|e| DiagnoseError::input("material", &spec, &e.expected()))?;
        let mut t = TwinSettings::new(material, &spec, s.mesh, Effects::neutral(), 0, &s.cache);
        // the reference is built as the model was (its geometry and fixed effects)
        t.sweep = t.sweep.built_as(model.training.built_with.as_ref());
        let dir = t.ramp_dir();
        let ramps = if s.run_fe {
            run_ramps(&t.sweep, &designs, Some(&dir), |d, n| progress(k, d, n))
        } else {
            cached_ramps(&t.sweep, &designs, &dir)
        }
        .map_err(crate::calibrate::CalibrateError::from)?;
        let missing = ramps
            .iter()
            .filter(|r| r.source == RampSource::Missing)
            .count();
        if missing > 0 {
            return Err(DiagnoseError::input(
                &format!("reference FE at {spec}"),
                format!(
                    "{missing} of {} ramps not in {}",
                    ramps.len(),
                    dir.display()
                ),
                "every ramp (run the FE)",
            ));
        }
        let rec = exact_twin_recordings(&ramps, noise_from, &spec)?;
        samples.push(ErrorSample::measure(model, &spec, m, &rec)?);
    }
    let mesh = match s.mesh.element_size {
        Some(h) => format!("{h} mm elements"),
        None => format!("the {} mesh", s.mesh.level.name()),
    };
    let mut e =
        ApproximationError::new(model_name, &format!("FE on {mesh} without effect"), samples)?;
    e.model_checksum = Some(model_checksum(model)?);
    Ok(e)
}

impl ApproximationError {
    /// The samples of `model` (its provenance `model_name`) against `reference`.
    ///
    /// # Errors
    /// Fewer than two samples (no covariance), two samples of one source.
    pub fn new(
        model_name: &str,
        reference: &str,
        samples: Vec<ErrorSample>,
    ) -> Result<Self, DiagnoseError> {
        if samples.len() < 2 {
            return Err(DiagnoseError::input(
                "approximation-error samples",
                samples.len(),
                "at least 2 (the covariance needs two)",
            ));
        }
        for (i, s) in samples.iter().enumerate() {
            if samples[..i].iter().any(|o| o.source == s.source) {
                return Err(DiagnoseError::input(
                    "approximation-error sample",
                    &s.source,
                    "one sample per source",
                ));
            }
        }
        Ok(Self {
            format: FORMAT.into(),
            version: VERSION,
            model: model_name.to_string(),
            reference: reference.to_string(),
            samples,
            model_checksum: None,
        })
    }

    /// Whether these samples are the error of `model`: the error of another model would
    /// shift the recordings by the wrong amount, silently.
    ///
    /// # Errors
    /// [`DiagnoseError::Input`] naming both models when the file records another
    /// model's checksum than `model`'s.
    pub fn check_model(&self, model: &Surrogate) -> Result<(), DiagnoseError> {
        let Some(sampled) = &self.model_checksum else {
            return Ok(());
        };
        let diagnosing = model_checksum(model)?;
        if *sampled == diagnosing {
            return Ok(());
        }
        Err(DiagnoseError::input(
            "approximation error's model",
            format!("{} ({sampled})", self.model),
            &format!(
                "the diagnosing model ({diagnosing}): an approximation error holds for the \
                 model it was sampled from (`surrogate approximation-error --model` with the \
                 diagnosing model)"
            ),
        ))
    }

    /// The same without the samples whose source is in `sources` (to diagnose a
    /// reference's own recordings without its own sample).
    ///
    /// # Errors
    /// Fewer than two samples left.
    pub fn without(&self, sources: &[&str]) -> Result<Self, DiagnoseError> {
        let mut e = Self::new(
            &self.model,
            &self.reference,
            self.samples
                .iter()
                .filter(|s| !sources.contains(&s.source.as_str()))
                .cloned()
                .collect(),
        )?;
        e.model_checksum.clone_from(&self.model_checksum);
        Ok(e)
    }

    /// The samples' errors at one recorded number.
    fn values_at(&self, n: u32, t: f64, p: f64, o: Output) -> Vec<Option<f64>> {
        self.samples.iter().map(|s| s.at(n, t, p, o)).collect()
    }

    /// The mean error `ε̄` at one recorded number (none: no sample has it).
    pub fn mean_at(&self, n: u32, t: f64, p: f64, o: Output) -> Option<f64> {
        let v: Vec<f64> = self.values_at(n, t, p, o).into_iter().flatten().collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    }

    /// `rec` corrected by the mean error: every recorded number the samples cover plus
    /// `ε̄` (what the model would predict for the reference's actuator); the standard
    /// deviations unchanged.
    pub fn correct(&self, rec: &Recordings) -> Recordings {
        let mut out = rec.clone();
        let shift = |v: &mut f64, n: usize, t: f64, p: f64, o: Output| {
            if let Some(m) = self.mean_at(n as u32, t, p, o) {
                *v += m;
            }
        };
        for r in &mut out.bending {
            let (n, t, p) = (r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            shift(&mut r.tip_uz_mm, n, t, p, Output::TipUz);
            shift(&mut r.tip_uy_mm, n, t, p, Output::TipUy);
            shift(&mut r.angle_deg, n, t, p, Output::Angle);
        }
        for r in &mut out.force {
            let (n, t, p) = (r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            shift(&mut r.force_n, n, t, p, Output::Force);
        }
        for r in &mut out.markers {
            let (n, t, p) = (r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            let k = r.marker as u8;
            shift(&mut r.uz_mm, n, t, p, Output::MarkerUz(k));
            shift(&mut r.uy_mm, n, t, p, Output::MarkerUy(k));
        }
        let note = |s: &str| format!("{s}, corrected by the mean error of {}", self.reference);
        out.bending_source = note(&out.bending_source);
        out.force_source = note(&out.force_source);
        if !out.markers_source.is_empty() {
            out.markers_source = note(&out.markers_source);
        }
        out
    }

    /// The covariance of the error over `cells` (see [`ErrorSpread`]); a cell only some
    /// samples cover uses those.
    pub fn spread(&self, cells: &[Cell]) -> ErrorSpread {
        let k = self.samples.len();
        let mut deviations = vec![vec![0.0; cells.len()]; k];
        for (i, c) in cells.iter().enumerate() {
            let v = self.values_at(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, c.output);
            let have: Vec<f64> = v.iter().flatten().copied().collect();
            if have.len() < 2 {
                continue;
            }
            let mean = have.iter().sum::<f64>() / have.len() as f64;
            let scale = 1.0 / ((have.len() - 1) as f64).sqrt();
            for (s, x) in v.iter().enumerate() {
                if let Some(x) = x {
                    deviations[s][i] = (x - mean) * scale;
                }
            }
        }
        ErrorSpread {
            sources: self.samples.iter().map(|s| s.source.clone()).collect(),
            deviations,
        }
    }

    /// `rms(ε̄ᵢ/σᵢ)` and the rms of the spread's diagonal `√Γ̃ᵢᵢ` over `cells`: how large
    /// the model's mean error and its variation are against the recordings' σ.
    pub fn size_over(&self, cells: &[Cell]) -> (f64, f64) {
        let spread = self.spread(cells);
        let n = cells.len().max(1) as f64;
        let mut mean2 = 0.0;
        let mut var = 0.0;
        for (i, c) in cells.iter().enumerate() {
            let m = self
                .mean_at(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, c.output)
                .unwrap_or(0.0);
            mean2 += (m / c.sigma).powi(2);
            var += spread
                .deviations
                .iter()
                .map(|d| (d[i] / c.sigma).powi(2))
                .sum::<f64>();
        }
        ((mean2 / n).sqrt(), (var / n).sqrt())
    }

    /// Reads a file written by [`Self::write`], checking its format and version.
    ///
    /// # Errors
    /// An unreadable file, another format or version.
    pub fn read(path: &Path) -> Result<Self, DiagnoseError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            DiagnoseError::input("approximation error", path.display(), &e.to_string())
        })?;
        let a: Self = serde_json::from_str(&text).map_err(|e| {
            DiagnoseError::input(
                "approximation error",
                path.display(),
                &format!("a {FORMAT} file ({e})"),
            )
        })?;
        if a.format != FORMAT || a.version != VERSION {
            return Err(DiagnoseError::input(
                "approximation error",
                format!(
                    "{} (format {}, version {})",
                    path.display(),
                    a.format,
                    a.version
                ),
                &format!("format {FORMAT}, version {VERSION}"),
            ));
        }
        let mut e = Self::new(&a.model, &a.reference, a.samples)?;
        e.model_checksum = a.model_checksum;
        Ok(e)
    }

    /// Writes it (atomically).
    ///
    /// # Errors
    /// A file that cannot be written.
    pub fn write(&self, path: &Path) -> Result<(), DiagnoseError> {
        let text = serde_json::to_string_pretty(self)?;
        crate::io::write_atomic(path, text.as_bytes()).map_err(|e| {
            DiagnoseError::input("approximation error", path.display(), &e.to_string())
        })
    }
}
