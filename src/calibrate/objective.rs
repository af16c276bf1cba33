//! What the fit compares: recordings → selected, standardised observations → residuals and
//! their Jacobian through the surrogate.
//!
//! ## The objective
//!
//! Every recorded number `yᵢ` (tip Uz, tip Uy, angle, blocked force, marker components) at its
//! configuration `(N, T, P)` gives one residual
//!
//! ```text
//!   rᵢ(θ) = √wᵢ · (ŷᵢ(θ) − yᵢ) / σᵢ,      σᵢ² = σ_meas,ᵢ² + σ_model,ᵢ²,      χ²(θ) = Σ rᵢ²
//! ```
//!
//! with `ŷ` the surrogate's prediction, `wᵢ` the weight of the output's term ([`Weights`]) and
//! `σᵢ` its standard deviation.
//!
//! ## Noise model
//!
//! - **angle**: the recorded standard deviation (`angle_std_deg`, the scatter of the 3
//!   specimens × 3 repetitions about their mean; a single test's scatter, not the standard
//!   error of the mean, because specimen-to-specimen differences do not average out over
//!   three specimens).
//! - **tip Uz, Uy**: the files give no standard deviation for the tip. The tip lies on the
//!   deformed chord from the support, of length `r = √((L_f − Uz)² + Uy²)` (L_f = 92 mm); a
//!   scatter `σ_α` of the angle moves it by `r·σ_α` (radians) across the chord. That value is
//!   taken for both components (isotropic: the scatter along the chord is not recorded, and
//!   this bound is the larger one).
//! - **force**: the recorded `force_std_n`.
//! - **markers**: the recorded `std_mm` of each component.
//! - **model**: the surrogate's own held-out RMSE of the output (stored in the model file) is
//!   added in quadrature, so that the fit does not chase the surrogate's error.
//!
//! Tip and angle carry largely the same information (the angle follows from the tip): `all`
//! counts it twice, which doubles its weight relative to the force; choose weights to suit.

use std::collections::BTreeSet;

use serde::{Deserialize, Serialize};

use super::experiments::{BendingRecord, ForceRecord, MarkerRecord};
use super::inputs::InputFile;
use super::params::ParamSpace;
use super::CalibrateError;
use crate::case::Query;
use crate::rom::{Jacobian, Prediction, Surrogate};
use crate::schema::{self, Quantity};

/// Free length used to derive the tip's standard deviation (mm).
pub use super::units::FREE_LENGTH_MM;

/// One recorded output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Output {
    /// Tip `Uz` (mm).
    TipUz,
    /// Tip `Uy` (mm).
    TipUy,
    /// Bending angle (deg).
    Angle,
    /// Blocked force (N).
    Force,
    /// Marker `k` (1..9) `Uz` (mm).
    MarkerUz(u8),
    /// Marker `k` (1..9) `Uy` (mm).
    MarkerUy(u8),
}

impl Output {
    /// Index of the output among the surrogate's 22 quantities.
    pub fn quantity(self) -> usize {
        match self {
            Output::TipUz => crate::rom::Q_TIP_UZ,
            Output::TipUy => crate::rom::Q_TIP_UY,
            Output::Angle => crate::rom::Q_ANGLE,
            Output::Force => crate::rom::Q_FORCE,
            Output::MarkerUz(k) => 2 * (k as usize - 1),
            Output::MarkerUy(k) => 2 * (k as usize - 1) + 1,
        }
    }

    /// The term of the objective the output belongs to.
    pub fn term(self) -> Term {
        match self {
            Output::TipUz | Output::TipUy => Term::Tip,
            Output::Angle => Term::Angle,
            Output::Force => Term::Force,
            Output::MarkerUz(_) | Output::MarkerUy(_) => Term::Markers,
        }
    }

    /// A readable name: the output's [`schema`] column (`tip_uz_mm`, `m3_uy_mm`, …).
    pub fn name(self) -> String {
        let marker = |list: &[Quantity; 9], k: u8, component: &str| match list
            .get(usize::from(k).wrapping_sub(1))
        {
            Some(q) => q.name.to_string(),
            None => format!("marker {k} {component} (not a marker 1..9)"),
        };
        match self {
            Output::TipUz => schema::TIP_UZ.name.into(),
            Output::TipUy => schema::TIP_UY.name.into(),
            Output::Angle => schema::ANGLE.name.into(),
            Output::Force => schema::FORCE.name.into(),
            Output::MarkerUz(k) => marker(&schema::MARKER_UZ, k, "Uz"),
            Output::MarkerUy(k) => marker(&schema::MARKER_UY, k, "Uy"),
        }
    }

    /// Name of the surrogate's validation entry holding this output's held-out error.
    fn validation_name(self) -> &'static str {
        match self {
            Output::TipUz => schema::TIP_UZ.name,
            Output::TipUy => schema::TIP_UY.name,
            Output::Angle => schema::ANGLE.name,
            Output::Force => schema::FORCE.name,
            Output::MarkerUz(_) | Output::MarkerUy(_) => schema::MARKERS.name,
        }
    }
}

/// A term of the objective.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// Tip Uz and Uy (the study's BE).
    Tip,
    /// Bending angle.
    Angle,
    /// Blocked force.
    Force,
    /// Markers along the actuator.
    Markers,
}

impl Term {
    /// All terms.
    pub const ALL: [Term; 4] = [Term::Tip, Term::Angle, Term::Force, Term::Markers];

    /// Name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Term::Tip => "tip",
            Term::Angle => "angle",
            Term::Force => "force",
            Term::Markers => "markers",
        }
    }
}

/// Weight of each term (0 = not fitted).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Weights {
    /// Tip Uz, Uy.
    pub tip: f64,
    /// Angle.
    pub angle: f64,
    /// Blocked force.
    pub force: f64,
    /// Markers.
    pub markers: f64,
}

impl Default for Weights {
    /// `tip` alone (the study's objective).
    fn default() -> Self {
        Weights {
            tip: 1.0,
            angle: 0.0,
            force: 0.0,
            markers: 0.0,
        }
    }
}

impl Weights {
    /// Weight of a term.
    pub fn of(&self, t: Term) -> f64 {
        match t {
            Term::Tip => self.tip,
            Term::Angle => self.angle,
            Term::Force => self.force,
            Term::Markers => self.markers,
        }
    }

    fn set(&mut self, t: Term, w: f64) {
        match t {
            Term::Tip => self.tip = w,
            Term::Angle => self.angle = w,
            Term::Force => self.force = w,
            Term::Markers => self.markers = w,
        }
    }

    /// Parses `tip`, `angle`, `force`, `markers`, `all`, or a weighted list such as
    /// `tip=1,force=0.5` (terms not named get 0).
    ///
    /// # Errors
    /// An unknown term, a weight that is not a finite number ≥ 0, a term named twice, or all
    /// weights zero.
    pub fn parse(text: &str) -> Result<Self, CalibrateError> {
        let expected = "tip, angle, force, markers, all, or term=weight,... (e.g. tip=1,force=2)";
        let mut w = Weights {
            tip: 0.0,
            angle: 0.0,
            force: 0.0,
            markers: 0.0,
        };
        let mut seen = BTreeSet::new();
        for item in text.split(',').map(str::trim) {
            let (name, weight) = match item.split_once('=') {
                Some((n, v)) => {
                    let x: f64 = v.trim().parse().map_err(|_| {
                        CalibrateError::input(
                            &format!("objective weight of {n}"),
                            v,
                            "a number ≥ 0",
                        )
                    })?;
                    (n.trim(), x)
                }
                None => (item, 1.0),
            };
            if !(weight.is_finite() && weight >= 0.0) {
                return Err(CalibrateError::input(
                    &format!("objective weight of {name}"),
                    weight,
                    "a finite number ≥ 0",
                ));
            }
            let terms: Vec<Term> = if name == "all" {
                Term::ALL.to_vec()
            } else {
                vec![Term::ALL
                    .into_iter()
                    .find(|t| t.name() == name)
                    .ok_or_else(|| CalibrateError::input("objective", name, expected))?]
            };
            for t in terms {
                if !seen.insert(t) {
                    return Err(CalibrateError::input(
                        "objective",
                        text,
                        "each term at most once",
                    ));
                }
                w.set(t, weight);
            }
        }
        if Term::ALL.iter().all(|&t| w.of(t) == 0.0) {
            return Err(CalibrateError::input(
                "objective",
                text,
                "at least one weight > 0",
            ));
        }
        Ok(w)
    }

    /// `tip=1,force=0.5` form of the non-zero weights.
    pub fn describe(&self) -> String {
        Term::ALL
            .iter()
            .filter(|&&t| self.of(t) > 0.0)
            .map(|&t| format!("{}={}", t.name(), self.of(t)))
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// A configuration `(N, T, P)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
}

impl Config {
    /// The configuration of a recorded row.
    pub fn of(n_bellows: usize, wall_thickness_mm: f64, pressure_bar: f64) -> Self {
        Config {
            n_bellows: n_bellows as u32,
            wall_thickness_mm,
            pressure_bar,
        }
    }

    /// Same configuration (to 1e-9).
    pub fn same(&self, o: &Config) -> bool {
        self.n_bellows == o.n_bellows
            && (self.wall_thickness_mm - o.wall_thickness_mm).abs() < 1e-9
            && (self.pressure_bar - o.pressure_bar).abs() < 1e-9
    }

    /// `N=11 T=1.6 P=1`.
    pub fn label(&self) -> String {
        format!(
            "N={} T={} P={}",
            self.n_bellows, self.wall_thickness_mm, self.pressure_bar
        )
    }
}

/// Which recording an exclusion applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Recording {
    /// Bending row (tip, angle, markers).
    Bending,
    /// Blocked-force row.
    Force,
    /// Both.
    Both,
}

/// An excluded configuration, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Exclusion {
    /// The configuration.
    pub config: Config,
    /// The recording(s) excluded.
    pub recording: Recording,
    /// Why (given by the user, or by a data check).
    pub reason: String,
}

impl Exclusion {
    /// Parses `N,T,P` (both recordings), `bending:N,T,P` or `force:N,T,P`.
    ///
    /// # Errors
    /// Malformed text, naming what was expected.
    pub fn parse(text: &str) -> Result<Self, CalibrateError> {
        let expected =
            "N,T,P (both recordings), bending:N,T,P or force:N,T,P, e.g. bending:11,1.6,1";
        let (recording, rest) = match text.split_once(':') {
            Some(("bending", r)) => (Recording::Bending, r),
            Some(("force", r)) => (Recording::Force, r),
            Some(_) => return Err(CalibrateError::input("--exclude", text, expected)),
            None => (Recording::Both, text),
        };
        let v: Vec<f64> = rest
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| CalibrateError::input("--exclude", text, expected))?;
        if v.len() != 3 || v.iter().any(|x| !x.is_finite()) || v[0].fract() != 0.0 || v[0] < 1.0 {
            return Err(CalibrateError::input("--exclude", text, expected));
        }
        Ok(Exclusion {
            config: Config {
                n_bellows: v[0] as u32,
                wall_thickness_mm: v[1],
                pressure_bar: v[2],
            },
            recording,
            reason: "excluded by the user".into(),
        })
    }

    /// Whether it leaves out the row of recording `r` at `c`.
    pub fn applies(&self, c: &Config, r: Recording) -> bool {
        self.config.same(c) && (self.recording == Recording::Both || self.recording == r)
    }
}

/// The recordings a calibration reads: bending (required), blocked force and markers
/// (optional), with the names of their sources for messages and the record of each file read.
#[derive(Clone, Debug, Default)]
pub struct Recordings {
    /// Bending rows.
    pub bending: Vec<BendingRecord>,
    /// Blocked-force rows.
    pub force: Vec<ForceRecord>,
    /// Marker rows.
    pub markers: Vec<MarkerRecord>,
    /// Source of the bending rows.
    pub bending_source: String,
    /// Source of the force rows.
    pub force_source: String,
    /// Source of the marker rows.
    pub markers_source: String,
    /// The files the rows were read from (path, checksum, rows, default or named); empty for
    /// recordings made in memory.
    pub files: Vec<InputFile>,
}

impl Recordings {
    /// The shipped experiments (bending and blocked force, 27 configurations each), as built
    /// into the program; both files are listed as defaults.
    ///
    /// # Errors
    /// Never for the shipped files (tested).
    pub fn shipped() -> Result<Self, CalibrateError> {
        let (b, f) = super::experiments::shipped_files()?;
        Ok(Recordings {
            bending_source: b.file.path.clone(),
            force_source: f.file.path.clone(),
            bending: b.rows,
            force: f.rows,
            markers: Vec::new(),
            markers_source: String::new(),
            files: vec![b.file, f.file],
        })
    }

    /// Exactly the files given: bending (required), blocked force and markers where given;
    /// nothing else is read.
    ///
    /// # Errors
    /// Any file that does not read ([`super::experiments`]).
    pub fn read_files(
        bending: &std::path::Path,
        force: Option<&std::path::Path>,
        markers: Option<&std::path::Path>,
    ) -> Result<Self, CalibrateError> {
        use super::experiments::{load_bending, load_force, load_markers};
        let b = load_bending(bending)?;
        let mut rec = Recordings {
            bending_source: b.file.path.clone(),
            bending: b.rows,
            files: vec![b.file],
            ..Recordings::default()
        };
        if let Some(p) = force {
            let f = load_force(p)?;
            rec.force_source = f.file.path.clone();
            rec.force = f.rows;
            rec.files.push(f.file);
        }
        if let Some(p) = markers {
            let m = load_markers(p)?;
            rec.markers_source = m.file.path.clone();
            rec.markers = m.rows;
            rec.files.push(m.file);
        }
        Ok(rec)
    }

    /// The recordings of a directory laid out like `training_data/` (a twin's output, say):
    /// [`super::experiments::BENDING_FILE`] (required), and
    /// [`super::experiments::FORCE_FILE`] and [`super::experiments::MARKERS_FILE`] where they
    /// exist.
    ///
    /// # Errors
    /// A missing bending file; any file that does not read ([`super::experiments`]).
    pub fn read_dir(dir: &std::path::Path) -> Result<Self, CalibrateError> {
        use super::experiments::{BENDING_FILE, FORCE_FILE, MARKERS_FILE};
        let (b, f, m) = (
            dir.join(BENDING_FILE),
            dir.join(FORCE_FILE),
            dir.join(MARKERS_FILE),
        );
        Self::read_files(
            &b,
            f.exists().then_some(f.as_path()),
            m.exists().then_some(m.as_path()),
        )
    }

    /// The same recordings with every file marked as a documented default (read without the
    /// user naming it).
    pub fn as_defaults(mut self) -> Self {
        for f in &mut self.files {
            f.default = true;
        }
        self
    }
}

/// One standardised observation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    /// Where it was recorded.
    pub config: Config,
    /// What was recorded.
    pub output: Output,
    /// The recorded value.
    pub value: f64,
    /// Measurement standard deviation.
    pub sigma_meas: f64,
    /// The surrogate's own error (held-out RMSE) for this output.
    pub sigma_model: f64,
    /// Weight of its term.
    pub weight: f64,
    /// `file, line N`.
    pub source: String,
}

impl Observation {
    /// `√(σ_meas² + σ_model²)`.
    pub fn sigma(&self) -> f64 {
        self.sigma_meas.hypot(self.sigma_model)
    }
}

/// The observations of a fit, grouped by configuration so that each surrogate query is made
/// once per evaluation.
#[derive(Clone, Debug)]
pub struct ObservationSet {
    /// The observations.
    pub obs: Vec<Observation>,
    /// The distinct configurations.
    pub configs: Vec<Config>,
    /// Configuration of each observation (index into `configs`).
    pub config_of: Vec<usize>,
    /// What was excluded, and why.
    pub excluded: Vec<Exclusion>,
}

/// Which configurations to use.
#[derive(Clone, Debug, Default)]
pub struct Selection {
    /// Only these `N` (empty: all).
    pub n_bellows: Vec<u32>,
    /// Only these `T` (empty: all).
    pub wall_thickness_mm: Vec<f64>,
    /// Only these `P` (empty: all).
    pub pressures_bar: Vec<f64>,
    /// Excluded rows.
    pub exclude: Vec<Exclusion>,
}

impl Selection {
    fn keeps(&self, c: &Config) -> bool {
        (self.n_bellows.is_empty() || self.n_bellows.contains(&c.n_bellows))
            && (self.wall_thickness_mm.is_empty()
                || self
                    .wall_thickness_mm
                    .iter()
                    .any(|t| (t - c.wall_thickness_mm).abs() < 1e-9))
            && (self.pressures_bar.is_empty()
                || self
                    .pressures_bar
                    .iter()
                    .any(|p| (p - c.pressure_bar).abs() < 1e-9))
    }
}

fn model_rmse(model: &Surrogate, o: Output) -> f64 {
    model
        .validation
        .outputs
        .iter()
        .find(|v| v.name == o.validation_name())
        .map_or(0.0, |v| v.total.rmse)
}

impl ObservationSet {
    /// Builds the observations of the terms with non-zero weight, for the selected and not
    /// excluded configurations.
    ///
    /// # Errors
    /// A selected configuration outside the model's domain (naming file, line and column; it
    /// must be excluded explicitly), a term with weight > 0 and no recordings, an exclusion
    /// that matches no row, or an empty selection.
    pub fn build(
        model: &Surrogate,
        rec: &Recordings,
        weights: &Weights,
        sel: &Selection,
    ) -> Result<Self, CalibrateError> {
        let mut b = ObservationBuilder::new(model, rec, weights, sel);
        if weights.tip > 0.0 || weights.angle > 0.0 {
            b.bending();
        }
        if weights.force > 0.0 {
            b.force()?;
        }
        if weights.markers > 0.0 {
            b.markers()?;
        }
        b.finish()
    }

    /// A set from given observations (grouped by configuration; nothing excluded).
    pub fn from_observations(obs: Vec<Observation>) -> Self {
        let mut configs: Vec<Config> = Vec::new();
        let mut config_of = Vec::with_capacity(obs.len());
        for o in &obs {
            let k = match configs.iter().position(|c| c.same(&o.config)) {
                Some(k) => k,
                None => {
                    configs.push(o.config);
                    configs.len() - 1
                }
            };
            config_of.push(k);
        }
        ObservationSet {
            obs,
            configs,
            config_of,
            excluded: Vec::new(),
        }
    }

    /// Number of observations.
    pub fn len(&self) -> usize {
        self.obs.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.obs.is_empty()
    }
}

/// The steps of [`ObservationSet::build`]: the observations of each recording in turn, the
/// exclusions that matched and the rows outside the model's domain noted as they go, then
/// the errors in order (outside the domain, an unused exclusion, nothing left).
struct ObservationBuilder<'a> {
    model: &'a Surrogate,
    rec: &'a Recordings,
    weights: &'a Weights,
    sel: &'a Selection,
    obs: Vec<Observation>,
    /// Whether each exclusion of `sel` matched a row.
    used: Vec<bool>,
    /// The kept rows outside the model's domain, each with its error.
    outside: Vec<(Config, CalibrateError)>,
}

impl<'a> ObservationBuilder<'a> {
    fn new(
        model: &'a Surrogate,
        rec: &'a Recordings,
        weights: &'a Weights,
        sel: &'a Selection,
    ) -> Self {
        ObservationBuilder {
            model,
            rec,
            weights,
            sel,
            obs: Vec::new(),
            used: vec![false; sel.exclude.len()],
            outside: Vec::new(),
        }
    }

    /// Whether the row of `r` at `c` is selected and not excluded (every exclusion that
    /// matches it is marked used); a kept row outside the model's domain is noted, naming
    /// `source`, line `line`.
    fn keeps(&mut self, c: &Config, r: Recording, source: &str, line: usize) -> bool {
        if !self.sel.keeps(c) || self.excluded(c, r) {
            return false;
        }
        if let Err(e) = check_domain(self.model, c, source, line) {
            self.outside.push((*c, e));
        }
        true
    }

    /// Whether an exclusion applies to the row of `r` at `c`, marking every one that does.
    fn excluded(&mut self, c: &Config, r: Recording) -> bool {
        let mut hit = false;
        for (i, e) in self.sel.exclude.iter().enumerate() {
            if e.applies(c, r) {
                self.used[i] = true;
                hit = true;
            }
        }
        hit
    }

    /// One observation of `output` at `config`, its weight its term's.
    fn push(
        &mut self,
        config: Config,
        output: Output,
        value: f64,
        sigma_meas: f64,
        source: String,
    ) {
        self.obs.push(Observation {
            config,
            output,
            value,
            sigma_meas,
            sigma_model: model_rmse(self.model, output),
            weight: self.weights.of(output.term()),
            source,
        });
    }

    /// Tip Uz and Uy (weight `tip`; σ from the angle's over the chord) and the angle (weight
    /// `angle`) of every bending row.
    fn bending(&mut self) {
        let rec = self.rec;
        for (i, r) in rec.bending.iter().enumerate() {
            let c = Config::of(r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            if !self.keeps(&c, Recording::Bending, &rec.bending_source, i + 2) {
                continue;
            }
            let source = format!("{}, line {}", rec.bending_source, i + 2);
            let sa = r.angle_std_deg;
            if self.weights.tip > 0.0 {
                let chord = (FREE_LENGTH_MM - r.tip_uz_mm).hypot(r.tip_uy_mm);
                let st = chord * sa.to_radians();
                self.push(c, Output::TipUz, r.tip_uz_mm, st, source.clone());
                self.push(c, Output::TipUy, r.tip_uy_mm, st, source.clone());
            }
            if self.weights.angle > 0.0 {
                self.push(c, Output::Angle, r.angle_deg, sa, source);
            }
        }
    }

    /// The blocked force of every force row.
    fn force(&mut self) -> Result<(), CalibrateError> {
        let rec = self.rec;
        if rec.force.is_empty() {
            return Err(CalibrateError::input(
                "objective",
                "force",
                "blocked-force recordings (none were given)",
            ));
        }
        for (i, r) in rec.force.iter().enumerate() {
            let c = Config::of(r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            if !self.keeps(&c, Recording::Force, &rec.force_source, i + 2) {
                continue;
            }
            let source = format!("{}, line {}", rec.force_source, i + 2);
            self.push(c, Output::Force, r.force_n, r.force_std_n, source);
        }
        Ok(())
    }

    /// Uz and Uy of every marker row.
    fn markers(&mut self) -> Result<(), CalibrateError> {
        let rec = self.rec;
        if rec.markers.is_empty() {
            return Err(CalibrateError::input(
                "objective",
                "markers",
                "marker recordings (none were given)",
            ));
        }
        for (i, r) in rec.markers.iter().enumerate() {
            let c = Config::of(r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            if !self.keeps(&c, Recording::Bending, &rec.markers_source, i + 2) {
                continue;
            }
            let k = r.marker as u8;
            for (o, v) in [
                (Output::MarkerUz(k), r.uz_mm),
                (Output::MarkerUy(k), r.uy_mm),
            ] {
                let source = format!("{}, line {}", rec.markers_source, i + 2);
                self.push(c, o, v, r.std_mm, source);
            }
        }
        Ok(())
    }

    /// The set, or the first error: rows outside the domain, an exclusion that matched no
    /// row, no observation left.
    fn finish(mut self) -> Result<ObservationSet, CalibrateError> {
        if self.outside.len() == 1 {
            return Err(self.outside.remove(0).1);
        }
        if !self.outside.is_empty() {
            return Err(outside_domain(self.outside));
        }
        if let Some(i) = self.used.iter().position(|u| !u) {
            let e = &self.sel.exclude[i];
            return Err(CalibrateError::input(
                "--exclude",
                e.config.label(),
                "a configuration present in the recordings of the fitted terms",
            ));
        }
        if self.obs.is_empty() {
            return Err(CalibrateError::input(
                "selection",
                "no observation left",
                "at least one recorded value after the selection and exclusions",
            ));
        }
        let mut set = ObservationSet::from_observations(self.obs);
        set.excluded = self.sel.exclude.clone();
        Ok(set)
    }
}

/// Several configurations outside the model's domain: one error naming every row and the
/// exclusions that would leave them out.
fn outside_domain(rows: Vec<(Config, CalibrateError)>) -> CalibrateError {
    let mut excludes: Vec<String> = Vec::new();
    for (c, _) in &rows {
        let e = format!(
            "--exclude {},{},{}",
            c.n_bellows, c.wall_thickness_mm, c.pressure_bar
        );
        if !excludes.contains(&e) {
            excludes.push(e);
        }
    }
    CalibrateError::OutsideDomain {
        rows: rows
            .into_iter()
            .map(|(_, e)| match e {
                CalibrateError::Record {
                    source_name,
                    line,
                    column,
                    reason,
                } => format!(
                    "{source_name}, line {line}, column {column}: {}",
                    reason.split("; exclude").next().unwrap_or(&reason)
                ),
                other => other.to_string(),
            })
            .collect(),
        excludes: excludes.join(" "),
    }
}

/// A configuration outside the model's domain is an error naming the file, line and column.
fn check_domain(
    model: &Surrogate,
    c: &Config,
    source: &str,
    line: usize,
) -> Result<(), CalibrateError> {
    let fail = |column: &str, value: String, expected: String| CalibrateError::Record {
        source_name: source.to_string(),
        line,
        column: column.to_string(),
        reason: format!(
            "{value} is outside the surrogate's domain ({expected}); exclude the row with \
             --exclude {},{},{} to go on without it",
            c.n_bellows, c.wall_thickness_mm, c.pressure_bar
        ),
    };
    if !model.n_allowed.contains(&c.n_bellows) {
        return Err(fail(
            schema::N_BELLOWS.name,
            c.n_bellows.to_string(),
            format!("trained N {:?}", model.n_allowed),
        ));
    }
    // the model's domain: the plan's range where its cases cover it (`crate::case::domain`)
    let [t_min, t_max] =
        model.domain().ranges[1].unwrap_or([model.inputs[1].min, model.inputs[1].max]);
    if c.wall_thickness_mm < t_min - 1e-9 || c.wall_thickness_mm > t_max + 1e-9 {
        return Err(fail(
            schema::WALL_THICKNESS.name,
            c.wall_thickness_mm.to_string(),
            format!("[{t_min:.3}, {t_max:.3}] mm"),
        ));
    }
    let (p0, p1) = (
        model.pressures[0],
        model.pressures[model.pressures.len() - 1],
    );
    if c.pressure_bar < p0 - 1e-9 || c.pressure_bar > p1 + 1e-9 {
        return Err(fail(
            schema::PRESSURE.name,
            c.pressure_bar.to_string(),
            format!("[{p0}, {p1}] bar"),
        ));
    }
    Ok(())
}

/// Buffers for evaluating residuals (reused across evaluations: no allocation per call).
#[derive(Clone, Debug)]
pub struct Evaluator<'a> {
    model: &'a Surrogate,
    set: &'a ObservationSet,
    space: ParamSpace,
    pred: Vec<Prediction>,
    jac: Vec<Jacobian>,
    /// `√wᵢ / σᵢ` per observation.
    scale: Vec<f64>,
    /// The surrogate quantities the observations read.
    quantities: std::ops::Range<usize>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator of `set` through `model`, with parameters in `space`.
    pub fn new(model: &'a Surrogate, set: &'a ObservationSet, space: ParamSpace) -> Self {
        let k = set.configs.len();
        Evaluator {
            model,
            set,
            space,
            pred: (0..k).map(|_| model.new_prediction()).collect(),
            jac: vec![Jacobian::default(); k],
            scale: set
                .obs
                .iter()
                .map(|o| o.weight.sqrt() / o.sigma())
                .collect(),
            quantities: {
                let q = set.obs.iter().map(|o| o.output.quantity());
                let lo = q.clone().min().unwrap_or(0);
                let hi = q.max().map_or(22, |v| v + 1);
                lo..hi
            },
        }
    }

    /// The surrogate.
    pub fn model(&self) -> &'a Surrogate {
        self.model
    }

    /// The parameter space.
    pub fn space(&self) -> &ParamSpace {
        &self.space
    }

    /// The observations.
    pub fn set(&self) -> &ObservationSet {
        self.set
    }

    /// Residuals `r` (and, if `jac` is given, `∂r/∂u` row by row) at unit-box point `u`.
    ///
    /// # Errors
    /// A query the surrogate rejects (cannot happen inside the space's box).
    pub fn residuals(
        &mut self,
        u: &[f64; 4],
        r: &mut [f64],
        jac: Option<&mut [[f64; 4]]>,
    ) -> Result<(), CalibrateError> {
        let p = self.space.ogden(u)?;
        let m = p.as_array();
        let with_jac = jac.is_some();
        for (k, c) in self.set.configs.iter().enumerate() {
            let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, m);
            if with_jac {
                self.model.gradient_range_into(
                    &q,
                    self.quantities.clone(),
                    &mut self.pred[k],
                    &mut self.jac[k],
                )?;
            } else {
                if self.quantities.start >= crate::rom::Q_TIP_UZ {
                    // tip, angle and force only: the folded scalar path
                    self.model.predict_scalars_into(&q, &mut self.pred[k])?;
                } else {
                    self.model.predict_into(&q, &mut self.pred[k])?;
                }
            }
        }
        for (i, o) in self.set.obs.iter().enumerate() {
            let qi = o.output.quantity();
            r[i] = self.scale[i] * (self.pred[self.set.config_of[i]].values[qi] - o.value);
        }
        if let Some(jac) = jac {
            let dm = self.space.ogden_jacobian(u);
            for (i, o) in self.set.obs.iter().enumerate() {
                let qi = o.output.quantity();
                let d = self.jac[self.set.config_of[i]].of(qi).material();
                for (j, out) in jac[i].iter_mut().enumerate() {
                    let mut v = 0.0;
                    for a in 0..4 {
                        v += d[a] * dm[a][j];
                    }
                    *out = self.scale[i] * v;
                }
            }
        }
        Ok(())
    }

    /// The predictions of every observation at `u` (unscaled), in observation order.
    ///
    /// # Errors
    /// As [`Self::residuals`].
    pub fn predictions(&mut self, u: &[f64; 4]) -> Result<Vec<f64>, CalibrateError> {
        let mut r = vec![0.0; self.set.len()];
        self.residuals(u, &mut r, None)?;
        Ok(self
            .set
            .obs
            .iter()
            .enumerate()
            .map(|(i, o)| r[i] / self.scale[i] + o.value)
            .collect())
    }

    /// `χ²(u) = Σ rᵢ²`.
    ///
    /// # Errors
    /// As [`Self::residuals`].
    pub fn chi2(&mut self, u: &[f64; 4]) -> Result<f64, CalibrateError> {
        let mut r = vec![0.0; self.set.len()];
        self.residuals(u, &mut r, None)?;
        Ok(r.iter().map(|v| v * v).sum())
    }
}
