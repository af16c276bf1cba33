//! The Name and Model-and-show stages of a [`Diagnosis`] as one step each, the way
//! `surrogate diagnose` runs them after Locate: Name weighed by the model's approximation
//! error and followed by the measurement plan, and a refit confirmed by the FE model.
use super::approx_error::ApproximationError;
use super::measure_design::PlanSettings;
use super::name::{NameSettings, Naming};
use super::refit::{
    confirm_with_fe, rank_with_fe, FeConfirmSettings, FeRankSettings, FeRanking, Refit,
    RefitSettings,
};
use super::report::Diagnosis;
use super::sweep::check_built_as;
use super::DiagnoseError;
use crate::calibrate::baseline::SweepSensitivities;
use crate::rom::Surrogate;

impl Diagnosis {
    /// The Name stage ([`Self::name_with`]) with the FE sensitivities `sens`, through `model`,
    /// its residual weighed by the covariance of `approximation` over this report's cells (the
    /// model's approximation error, if known); then, with `plan`, the measurements that would
    /// best separate the tied candidates ([`Self::plan_with`], weighed the same). `progress`
    /// gets a line per stage.
    ///
    /// # Errors
    /// An `approximation` sampled from another model than `model`
    /// ([`ApproximationError::check_model`]); as [`Self::name_with`] and [`Self::plan_with`].
    pub fn name_and_plan(
        &mut self,
        sens: &SweepSensitivities,
        model: &Surrogate,
        approximation: Option<&ApproximationError>,
        plan: Option<&PlanSettings>,
        progress: &dyn Fn(&str),
    ) -> Result<&Naming, DiagnoseError> {
        if let Some(e) = approximation {
            e.check_model(model)?;
        }
        progress(&format!(
            "name: {} effects against the FE sensitivities of {} ramps ({} mesh)",
            sens.designs
                .first()
                .map_or(0, |d| d.sensitivities.parameters.len().saturating_sub(4)),
            sens.designs.len(),
            sens.mesh.level.name()
        ));
        let ns = NameSettings {
            error_spread: approximation.map(|e| e.spread(&self.locate.cells)),
            ..NameSettings::default()
        };
        self.name_with(sens, model, &ns)?;
        if let Some(plan) = plan {
            let ps = PlanSettings {
                error_spread: ns.error_spread,
                ..plan.clone()
            };
            progress(&format!(
                "plan: up to {} measurements to separate the tied candidates",
                ps.k
            ));
            self.plan_with(sens, &ps)?;
        }
        Ok(self.naming().expect("just named"))
    }

    /// Ranks the Name stage's top candidates by FE-confirmed nonlinear fits
    /// ([`rank_with_fe`]: each refitted with the material from the calibrated set, run on the
    /// FE model with `fe` and refitted around it) and records the ranking; Model and show's
    /// `auto` choice ([`Self::chosen`]) is then the FE's first. `progress` gets a line per
    /// candidate, `ramp_progress(done, total)` one per FE ramp.
    ///
    /// # Errors
    /// Sensitivities of another actuator than `model`'s ([`check_built_as`]); no Name stage;
    /// as [`rank_with_fe`].
    pub fn rank_with_fe(
        &mut self,
        sens: &SweepSensitivities,
        model: &Surrogate,
        s: &FeRankSettings,
        fe: &FeConfirmSettings,
        progress: &dyn Fn(&str),
        ramp_progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<&FeRanking, DiagnoseError> {
        check_built_as(sens, model.training.built_with.as_ref())?;
        let naming = self.naming().ok_or_else(|| {
            DiagnoseError::input("FE ranking", "no Name stage", "a diagnosis named first")
        })?;
        let r = rank_with_fe(
            &self.locate.cells,
            sens,
            model,
            &self.calibration.best,
            naming,
            s,
            fe,
            progress,
            ramp_progress,
        )?;
        Ok(self.fe_ranking.insert(r))
    }

    /// The effect Model and show refits by default: the FE ranking's first when it ran, else
    /// the Name stage's named effect (none: nothing named).
    pub fn chosen(&self) -> Option<&str> {
        match &self.fe_ranking {
            Some(r) => r.first().map(|c| c.effect.as_str()),
            None => self
                .naming()
                .and_then(|n| n.named())
                .map(|c| c.effect.as_str()),
        }
    }

    /// Confirms the refit of the Model-and-show stage with the FE model
    /// ([`confirm_with_fe`]: the recorded designs run with the effects of `s` on at their
    /// refitted values, the refit redone around the FE where the two differ) and records the
    /// confirmed refit. `progress(done, total)` after every FE ramp.
    ///
    /// # Errors
    /// Sensitivities of another actuator than `model`'s ([`check_built_as`]); no refit yet
    /// ([`Self::refit_with`] first); as [`confirm_with_fe`].
    pub fn confirm_refit_with_fe(
        &mut self,
        sens: &SweepSensitivities,
        model: &Surrogate,
        s: &RefitSettings,
        fe: &FeConfirmSettings,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<&Refit, DiagnoseError> {
        check_built_as(sens, model.training.built_with.as_ref())?;
        let first = self.refitted().cloned().ok_or_else(|| {
            DiagnoseError::input(
                "FE confirmation",
                "no Model-and-show stage",
                "a diagnosis refitted first",
            )
        })?;
        let confirmed = confirm_with_fe(&self.locate.cells, sens, model, first, s, fe, progress)?;
        self.set_refit(confirmed);
        Ok(self.refitted().expect("just set"))
    }
}
