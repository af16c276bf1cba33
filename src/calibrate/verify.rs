//! FE verification of a calibrated set: the full FE model (bending and blocked-force ramps,
//! contact, gravity) for every recorded design at the set, through the baseline sweep (cached
//! per ramp, so an interrupted verification resumes), compared with the experiments and with
//! the surrogate.
//!
//! Surrogate and FE **disagree** at a configuration when `|FE − surrogate|` exceeds twice the
//! surrogate's predictive standard deviation there (its stated 95 % band; the standard
//! deviations are calibrated on held-out cases, see [`crate::rom::surrogate`]) for tip Uz,
//! tip Uy or the force. The designs with a disagreement are the ones to add to the
//! high-fidelity training set before refitting.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::baseline::{
    cached_baseline, run_baseline, summarize, BaselineRow, BaselineSummary, SweepSettings,
};
use super::objective::{Config, Recordings};
use super::CalibrateError;
use crate::case::OgdenSet;
use crate::case::Query;
use crate::fe::material::{Material, MaterialLaw, Ogden2, DEFAULT_BULK_RATIO};
use crate::fe::mesh::MeshOptions;
use crate::rom::{Surrogate, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::schema;

/// One configuration: FE, surrogate, experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeCheckRow {
    /// The configuration.
    pub config: Config,
    /// The FE's baseline row (FE vs experiment).
    pub fe: BaselineRow,
    /// Surrogate tip Uz (mm).
    pub uz_sur_mm: f64,
    /// Surrogate tip Uy (mm).
    pub uy_sur_mm: f64,
    /// Surrogate angle (deg).
    pub angle_sur_deg: f64,
    /// Surrogate force (N).
    pub force_sur_n: f64,
    /// Surrogate predictive std of tip Uz, Uy and force.
    pub sur_std: [f64; 3],
    /// Outputs where surrogate and FE disagree (beyond 2 std).
    pub disagree: Vec<String>,
}

/// The FE verification of a set.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FeVerification {
    /// Mesh level (name).
    pub mesh: String,
    /// The set verified.
    pub params: OgdenSet,
    /// Per configuration.
    pub rows: Vec<FeCheckRow>,
    /// FE against the experiments.
    pub summary: BaselineSummary,
    /// Mean |FE − surrogate| of tip Uz, tip Uy, force.
    pub mean_abs_sur_fe: [f64; 3],
    /// Largest |FE − surrogate| of tip Uz, tip Uy, force.
    pub max_abs_sur_fe: [f64; 3],
    /// Configurations with a disagreement.
    pub disagreements: usize,
    /// Configurations without FE values (a ramp not run or not converged to them).
    pub incomplete: usize,
    /// Designs `(N, T)` to add as high-fidelity cases.
    pub designs_to_refine: Vec<(u32, f64)>,
}

/// The FE material of an Ogden set (κ = 1000 μ0, as in the training sets).
///
/// # Errors
/// An inadmissible set (cannot happen for a validated [`OgdenSet`]).
pub fn fe_material(p: &OgdenSet) -> Result<Material, CalibrateError> {
    let law = Ogden2::try_from(*p)
        .map_err(|e| CalibrateError::input("material", p.spec(), &e.expected()))?;
    Material::new(MaterialLaw::Ogden(law), DEFAULT_BULK_RATIO)
        .map_err(|e| CalibrateError::input("material", p.spec(), &e.expected()))
}

/// Runs (or reads from `cache`) the FE ramps of every recorded design at `params` on `mesh`,
/// with the geometry and fixed effects the model's training cases were built with
/// ([`SweepSettings::built_as`]), and compares them with the experiments and the surrogate;
/// `progress(done, total)` after each ramp.
///
/// # Errors
/// A design outside the FE model's range, an unwritable cache, or a surrogate error.
pub fn verify_fe(
    model: &Surrogate,
    rec: &Recordings,
    params: &OgdenSet,
    mesh: MeshOptions,
    cache: &Path,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<FeVerification, CalibrateError> {
    let settings =
        SweepSettings::new(fe_material(params)?, mesh).built_as(model.training.built_with.as_ref());
    let rows = run_baseline(&settings, &rec.bending, &rec.force, Some(cache), progress)?;
    compare_fe(model, params, mesh, rows)
}

/// [`verify_fe`] from the ramps already in `cache` only (no FE run): the configurations whose
/// ramps are missing count as [`FeVerification::incomplete`].
///
/// # Errors
/// A design outside the FE model's range, or a surrogate error.
pub fn cached_verification(
    model: &Surrogate,
    rec: &Recordings,
    params: &OgdenSet,
    mesh: MeshOptions,
    cache: &Path,
) -> Result<FeVerification, CalibrateError> {
    let settings =
        SweepSettings::new(fe_material(params)?, mesh).built_as(model.training.built_with.as_ref());
    let rows = cached_baseline(&settings, &rec.bending, &rec.force, cache)?;
    compare_fe(model, params, mesh, rows)
}

/// Compares finished baseline rows with the surrogate at `params`.
///
/// # Errors
/// A surrogate error.
pub fn compare_fe(
    model: &Surrogate,
    params: &OgdenSet,
    mesh: MeshOptions,
    rows: Vec<BaselineRow>,
) -> Result<FeVerification, CalibrateError> {
    let mut pred = model.new_prediction();
    let mut out = Vec::new();
    let mut designs = Vec::new();
    for r in &rows {
        let c = Config::of(r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
        let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, *params);
        model.predict_with_std_into(&q, &mut pred)?;
        let sur = [pred.tip_uz_mm(), pred.tip_uy_mm(), pred.force_n()];
        let std = [pred.std[Q_TIP_UZ], pred.std[Q_TIP_UY], pred.std[Q_FORCE]];
        let fe = [r.uz_sim_mm, r.uy_sim_mm, r.force_sim_n];
        let disagree: Vec<String> = [schema::TIP_UZ.name, schema::TIP_UY.name, schema::FORCE.name]
            .iter()
            .enumerate()
            .filter(|&(k, _)| fe[k].is_finite() && (fe[k] - sur[k]).abs() > 2.0 * std[k])
            .map(|(k, n)| {
                format!(
                    "{n}: FE {:.3}, surrogate {:.3} ± {:.3}",
                    fe[k], sur[k], std[k]
                )
            })
            .collect();
        if !disagree.is_empty() && !designs.contains(&(c.n_bellows, c.wall_thickness_mm)) {
            designs.push((c.n_bellows, c.wall_thickness_mm));
        }
        out.push(FeCheckRow {
            config: c,
            fe: r.clone(),
            uz_sur_mm: sur[0],
            uy_sur_mm: sur[1],
            angle_sur_deg: pred.angle_deg(),
            force_sur_n: sur[2],
            sur_std: std,
            disagree,
        });
    }
    let diff = |k: usize| -> Vec<f64> {
        out.iter()
            .map(|r| {
                let fe = [r.fe.uz_sim_mm, r.fe.uy_sim_mm, r.fe.force_sim_n][k];
                let s = [r.uz_sur_mm, r.uy_sur_mm, r.force_sur_n][k];
                (fe - s).abs()
            })
            .filter(|v| v.is_finite())
            .collect()
    };
    let mean_abs_sur_fe = [0, 1, 2].map(|k| {
        let d = diff(k);
        d.iter().sum::<f64>() / d.len().max(1) as f64
    });
    let max_abs_sur_fe = [0, 1, 2].map(|k| diff(k).into_iter().fold(0.0, f64::max));
    Ok(FeVerification {
        mesh: mesh.level.name().to_string(),
        params: *params,
        summary: summarize(&rows),
        disagreements: out.iter().filter(|r| !r.disagree.is_empty()).count(),
        incomplete: rows.iter().filter(|r| !r.error.is_empty()).count(),
        rows: out,
        mean_abs_sur_fe,
        max_abs_sur_fe,
        designs_to_refine: designs,
    })
}
