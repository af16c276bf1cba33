//! The diagnosis report: calibrate → locate, and the stages not run yet, in one versioned
//! JSON document.

use serde::{Deserialize, Serialize};

use super::locate::{locate, Localisation, LocateSettings};
use super::measure_design::{plan, MeasurementPlan, PlanSettings};
use super::mesh_error::{mesh_error, MeshError};
use super::name::{name_refitted, NameSettings, Naming};
use super::refit::{refit, FeRanking, Refit, RefitSettings};
use super::sweep::{check_built_as, SweepCoverage};
use super::DiagnoseError;
use crate::calibrate::fit::describe_exclusions;
use crate::calibrate::inputs::InputFile;
use crate::calibrate::{calibrate, Calibration, CalibrationSettings, Recordings};
use crate::case::OgdenSet;
use crate::rom::Surrogate;

/// The `format` field of a diagnosis report.
pub const FORMAT: &str = "surrogate.diagnosis";
/// The `version` field this code writes and reads.
pub const VERSION: u32 = 1;

/// Where the recordings came from (empty: none of that kind).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sources {
    /// Bending rows.
    pub bending: String,
    /// Blocked-force rows.
    pub force: String,
    /// Marker rows.
    pub markers: String,
}

/// The calibration the diagnosis starts from, in brief.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CalibrationSummary {
    /// Model file checksum and provenance.
    pub model: String,
    /// The objective (`tip=1`).
    pub objective: String,
    /// The calibrated set.
    pub best: OgdenSet,
    /// The calibration's `χ²` (its objective, weights included).
    pub chi2: f64,
    /// Its `χ²` per degree of freedom.
    pub chi2_per_dof: f64,
    /// Observations fitted.
    pub n_observations: usize,
    /// Configurations fitted.
    pub n_configurations: usize,
    /// Mean tip bending error at the calibrated set (mm, surrogate).
    pub mean_be_mm: f64,
    /// Mean force error (predicted − measured, N; none without force recordings).
    pub mean_force_error_n: Option<f64>,
    /// Bounds of the training domain active at the optimum.
    pub active_bounds: Vec<String>,
    /// Data-check flags, in words.
    pub flags: Vec<String>,
    /// Rows excluded from the fit, and why.
    pub excluded: Vec<String>,
}

impl CalibrationSummary {
    /// The summary of a calibration.
    pub fn of(cal: &Calibration) -> Self {
        CalibrationSummary {
            model: cal.model.clone(),
            objective: cal.objective.clone(),
            best: cal.best,
            chi2: cal.chi2,
            chi2_per_dof: cal.chi2 / cal.identifiability.dof.max(1) as f64,
            n_observations: cal.n_observations,
            n_configurations: cal.n_configurations,
            mean_be_mm: cal.calibrated.mean_be_mm,
            mean_force_error_n: Some(cal.calibrated.mean_force_error_n).filter(|v| v.is_finite()),
            active_bounds: cal.active_bounds.clone(),
            flags: cal
                .flags
                .iter()
                .map(|f| format!("{} ({}): {}", f.config.label(), f.source, f.message))
                .collect(),
            excluded: describe_exclusions(&cal.excluded),
        }
    }
}

/// A stage of the diagnoser: not run (and why), or its result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "status")]
pub enum Stage {
    /// Not run.
    NotRun {
        /// Why.
        reason: String,
    },
    /// The Name stage's result ([`super::name`]).
    Named(Box<Naming>),
    /// The Model-and-show stage's result ([`super::refit`]).
    Modelled(Box<Refit>),
}

fn naming_of(s: &Stage) -> Option<&Naming> {
    match s {
        Stage::Named(n) => Some(n),
        _ => None,
    }
}

/// The diagnosis report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The recordings.
    pub recordings: Sources,
    /// Every file read: the recordings and, added by the caller that read them, the model,
    /// the FE sensitivities and the other references; each with its checksum and whether it
    /// was a documented default.
    #[serde(default)]
    pub inputs: Vec<InputFile>,
    /// The calibration diagnosed.
    pub calibration: CalibrationSummary,
    /// Where the residual is.
    pub locate: Localisation,
    /// The diagnosing model's mesh error, tested by the Name stage beside the effects
    /// (none: not measured, [`Self::mesh_error_with`]).
    #[serde(default)]
    pub mesh_error: Option<MeshError>,
    /// Which cells of the residual table the FE sensitivities of the Name and Model stages
    /// cover (none: no sweep was given, [`Self::cover`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensitivity_coverage: Option<SweepCoverage>,
    /// Candidate effects ranked by their signatures.
    pub name: Stage,
    /// Refit with the chosen effect(s), held-out gain, FE confirmation.
    pub model_and_show: Stage,
    /// What to measure next to separate the candidates the Name stage found tied (none: not
    /// planned, [`Self::plan_with`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measurement_plan: Option<MeasurementPlan>,
    /// The Name stage's top candidates ranked by FE-confirmed nonlinear fits (none: not run,
    /// [`Self::rank_with_fe`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fe_ranking: Option<FeRanking>,
}

impl Diagnosis {
    /// The report of a calibration and its localisation.
    pub fn new(cal: &Calibration, rec: &Recordings, locate: Localisation) -> Self {
        Diagnosis {
            format: FORMAT.into(),
            version: VERSION,
            recordings: Sources {
                bending: rec.bending_source.clone(),
                force: rec.force_source.clone(),
                markers: rec.markers_source.clone(),
            },
            inputs: rec.files.clone(),
            calibration: CalibrationSummary::of(cal),
            locate,
            mesh_error: None,
            sensitivity_coverage: None,
            name: Stage::NotRun {
                reason: "needs the FE sensitivities of the effect library at the calibrated \
                         state, which do not exist yet: no candidate is named or ranked"
                    .into(),
            },
            model_and_show: Stage::NotRun {
                reason: "needs a named effect".into(),
            },
            measurement_plan: None,
            fe_ranking: None,
        }
    }

    /// Records which cells of the residual table the FE sensitivities `sens` cover
    /// ([`SweepCoverage`]). When they cover fewer than the Name stage needs, the Name and
    /// Model-and-show stages are recorded as not run, with the configurations that have no
    /// sensitivities and what computes them; the report is complete without them.
    pub fn cover(
        &mut self,
        sens: &crate::calibrate::baseline::SweepSensitivities,
    ) -> &SweepCoverage {
        let c = SweepCoverage::of(&self.locate.cells, sens);
        if !c.enough() {
            self.name = Stage::NotRun { reason: c.text() };
            self.model_and_show = Stage::NotRun {
                reason: "needs the Name stage's FE sensitivities at the recorded designs and \
                         pressures"
                    .into(),
            };
        }
        self.sensitivity_coverage.insert(c)
    }

    /// Runs the Name stage on this report's residual table with the FE sensitivities
    /// `sens`, after the material's nonlinear re-fit through `model` (the surrogate the
    /// calibration used; see [`super::name::name_refitted`]), and records it with the
    /// coverage of the table by `sens` ([`Self::cover`]).
    ///
    /// # Errors
    /// Sensitivities of another actuator than `model`'s ([`check_built_as`]); see
    /// [`name_refitted`]; too few cells with sensitivities (the stage is then recorded as not
    /// run, [`Self::cover`]).
    pub fn name_with(
        &mut self,
        sens: &crate::calibrate::baseline::SweepSensitivities,
        model: &Surrogate,
        settings: &NameSettings,
    ) -> Result<&Naming, DiagnoseError> {
        check_built_as(sens, model.training.built_with.as_ref())?;
        let coverage = self.cover(sens);
        if !coverage.enough() {
            return Err(DiagnoseError::input(
                "cells with sensitivities",
                coverage.covered,
                &format!("at least {}: {}", coverage.needed, coverage.text()),
            ));
        }
        let mut settings = settings.clone();
        if let Some(me) = &self.mesh_error {
            if !settings
                .model_errors
                .iter()
                .any(|n| n.name == me.direction.name)
            {
                settings.model_errors.push(me.direction.clone());
            }
        }
        let naming = name_refitted(
            &self.locate.cells,
            sens,
            model,
            &self.calibration.best,
            &settings,
        )?;
        self.name = Stage::Named(Box::new(naming));
        self.model_and_show = Stage::NotRun {
            reason: match naming_of(&self.name).and_then(Naming::named) {
                Some(c) => format!("{} was named; the refit was not asked for", c.effect),
                None => "no effect was named (a refit can still be asked for by name)".into(),
            },
        };
        Ok(naming_of(&self.name).expect("just set"))
    }

    /// Measures the diagnosing `model`'s mesh error against `reference` (a surrogate of the
    /// same plan on a finer mesh, named `reference_name` in the report) at the calibrated
    /// material ([`super::mesh_error`]); the Name stage run after it tests it beside the
    /// effects.
    ///
    /// # Errors
    /// As [`super::mesh_error::mesh_error`].
    pub fn mesh_error_with(
        &mut self,
        model: &Surrogate,
        reference: &Surrogate,
        reference_name: &str,
    ) -> Result<&MeshError, DiagnoseError> {
        let me = mesh_error(
            &self.locate.cells,
            model,
            reference,
            reference_name,
            &self.calibration.best,
        )?;
        Ok(self.mesh_error.insert(me))
    }

    /// Plans the measurements that would best separate the candidates the Name stage found
    /// tied ([`super::measure_design::plan`]), with the FE sensitivities `sens` the stage ran
    /// with, and records the plan.
    ///
    /// # Errors
    /// The Name stage has not run; see [`plan`].
    pub fn plan_with(
        &mut self,
        sens: &crate::calibrate::baseline::SweepSensitivities,
        settings: &PlanSettings,
    ) -> Result<&MeasurementPlan, DiagnoseError> {
        let naming = self.naming().ok_or_else(|| {
            DiagnoseError::input(
                "measurement plan",
                "no Name stage",
                "a diagnosis named first",
            )
        })?;
        let p = plan(&self.locate.cells, sens, naming, settings)?;
        Ok(self.measurement_plan.insert(p))
    }

    /// The Name stage's result, if it ran.
    pub fn naming(&self) -> Option<&Naming> {
        naming_of(&self.name)
    }

    /// The Model-and-show stage's result, if it ran.
    pub fn refitted(&self) -> Option<&Refit> {
        match &self.model_and_show {
            Stage::Modelled(r) => Some(r),
            _ => None,
        }
    }

    /// Runs the Model-and-show stage ([`super::refit`]): the material refitted from the
    /// calibrated set together with `settings.effects`, linearised with `sens`, through
    /// `model` (the surrogate the calibration used), and records it.
    ///
    /// # Errors
    /// Sensitivities of another actuator than `model`'s ([`check_built_as`]); see [`refit`].
    pub fn refit_with(
        &mut self,
        sens: &crate::calibrate::baseline::SweepSensitivities,
        model: &Surrogate,
        settings: &RefitSettings,
    ) -> Result<&Refit, DiagnoseError> {
        check_built_as(sens, model.training.built_with.as_ref())?;
        let r = refit(
            &self.locate.cells,
            sens,
            model,
            &self.calibration.best,
            settings,
        )?;
        self.set_refit(r);
        Ok(self.refitted().expect("just set"))
    }

    /// Records a refit made elsewhere (for example confirmed by the FE model,
    /// [`super::refit::confirm_with_fe`]).
    pub fn set_refit(&mut self, r: Refit) {
        self.model_and_show = Stage::Modelled(Box::new(r));
    }

    /// The report as pretty JSON.
    ///
    /// # Errors
    /// A serialisation error.
    pub fn to_json(&self) -> Result<String, DiagnoseError> {
        Ok(serde_json::to_string_pretty(self)?)
    }

    /// Reads a report written by [`Self::to_json`].
    ///
    /// # Errors
    /// Text that is not a report, or a report of another format or version.
    pub fn from_json(text: &str) -> Result<Self, DiagnoseError> {
        let v: serde_json::Value = serde_json::from_str(text)?;
        let format = v.get("format").and_then(|f| f.as_str()).unwrap_or("");
        if format != FORMAT {
            return Err(DiagnoseError::input("format", format, FORMAT));
        }
        let version = v.get("version").and_then(|f| f.as_u64()).unwrap_or(0);
        if version != u64::from(VERSION) {
            return Err(DiagnoseError::input(
                "version",
                version,
                &format!("{VERSION} (the version this program reads)"),
            ));
        }
        Ok(serde_json::from_value(v)?)
    }
}

/// Settings of [`diagnose`].
#[derive(Clone, Debug, Default)]
pub struct DiagnoseSettings {
    /// The calibration the diagnosis starts from.
    pub calibration: CalibrationSettings,
    /// Locate.
    pub locate: LocateSettings,
}

/// Calibrates the material to `rec` through `model`, then locates the residual; `progress`
/// gets a line per stage.
///
/// # Errors
/// A calibration error ([`calibrate`]) or a locate error ([`locate`]).
pub fn diagnose(
    model: &Surrogate,
    rec: &Recordings,
    s: &DiagnoseSettings,
    progress: &dyn Fn(&str),
) -> Result<Diagnosis, DiagnoseError> {
    s.locate.validate()?;
    let cal = calibrate(model, rec, &s.calibration, progress)?;
    progress("locate: residual table, shares, structure over N, T, P, sign patterns");
    let loc = locate(&cal, model, rec, &s.locate)?;
    Ok(Diagnosis::new(&cal, rec, loc))
}
