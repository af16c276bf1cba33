//! The standardised observations of a fit: the selected rows of the recordings, each with its
//! noise and weight, checked against the model's domain.

use serde::{Deserialize, Serialize};

use super::recordings::Recordings;
use super::selection::{Config, Exclusion, Recording, Selection};
use super::terms::{Output, Weights};
use crate::calibrate::units::FREE_LENGTH_MM;
use crate::calibrate::CalibrateError;
use crate::rom::Surrogate;
use crate::schema;

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
