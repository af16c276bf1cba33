//! Diagnosing one twin without its key, and the approximation error the null twins sample.

use std::path::Path;

use super::plan::{StudyPlan, TwinGroup};
use super::twins::StudyDirs;
use crate::calibrate::baseline::SweepSensitivities;
use crate::calibrate::Recordings;
use crate::case::OgdenSet;
use crate::diagnose::approx_error::{sample, ApproximationError, SampleSettings};
use crate::diagnose::refit::RefitSettings;
use crate::diagnose::report::{diagnose, DiagnoseSettings, Diagnosis};
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;
use crate::rom::Surrogate;

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
    diagnose_recordings(twin_recordings(dir, by)?, by)
}

/// A twin's recordings as [`diagnose_twin`] reads them: without its markers unless `by`
/// uses them.
///
/// # Errors
/// Unreadable recordings.
pub fn twin_recordings(dir: &Path, by: &Diagnoser<'_>) -> Result<Recordings, DiagnoseError> {
    let mut rec = Recordings::read_dir(dir)?;
    if !by.markers {
        rec.markers.clear();
        rec.markers_source.clear();
    }
    Ok(rec)
}

/// Diagnoses recordings as [`diagnose_twin`] diagnoses a twin's: corrected by the
/// approximation error's mean, calibrated through the model, located, the mesh error
/// measured, named with the sensitivities, the named effect refitted.
///
/// # Errors
/// As [`diagnose`] and the stages.
pub fn diagnose_recordings(
    mut rec: Recordings,
    by: &Diagnoser<'_>,
) -> Result<Diagnosis, DiagnoseError> {
    let (model, sens) = (by.model, by.sens);
    if let Some(a) = by.approximation {
        rec = a.correct(&rec);
    }
    let mut d = diagnose(model, &rec, &DiagnoseSettings::default(), &|_| {})?;
    if let Some((reference, name)) = by.mesh_reference {
        d.mesh_error_with(model, reference, name)?;
    }
    let settings = crate::diagnose::name::NameSettings {
        error_spread: by.approximation.map(|a| a.spread(&d.locate.cells)),
        ..Default::default()
    };
    d.name_with(sens, model, &settings)?;
    let named = d
        .naming()
        .and_then(crate::diagnose::name::Naming::named)
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
