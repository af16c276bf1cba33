//! The FE sensitivities at the calibrated state: the sweep the Name and Model stages
//! linearise with, run for the recorded designs at the calibrated material (cached and
//! resumable), when no precomputed sweep fits.

use std::path::Path;

use super::DiagnoseError;
use crate::calibrate::baseline::{
    cached_ramps, recorded_designs, run_ramps, SweepSensitivities, SweepSettings,
};
use crate::calibrate::{CalibrateError, OgdenSet, Recordings};
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::mesh::MeshOptions;
use crate::fe::sensitivity::Parameter;

/// Runs (or reads from `cache`) the bending and blocked-force ramps of every recorded design
/// at `material` on `mesh`, with the sensitivities of the four material parameters and every
/// effect of the library; `progress(done, total)` after every ramp.
///
/// # Errors
/// A material the FE model refuses, an invalid design, an unwritable cache.
pub fn sweep_at(
    material: &OgdenSet,
    rec: &Recordings,
    mesh: MeshOptions,
    cache: &Path,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<SweepSensitivities, DiagnoseError> {
    let m = Material::from_spec(&material.spec(), DEFAULT_BULK_RATIO).map_err(|e| {
        DiagnoseError::input("calibrated material", material.spec(), &e.to_string())
    })?;
    let settings = SweepSettings {
        sensitivities: Parameter::all(),
        ..SweepSettings::new(m, mesh)
    };
    let designs = recorded_designs(&rec.bending);
    run_ramps(&settings, &designs, Some(cache), progress).map_err(CalibrateError::from)?;
    // read back from the cache the sweep just filled: no FE
    let ramps = cached_ramps(&settings, &designs, cache).map_err(CalibrateError::from)?;
    Ok(SweepSensitivities::of(&settings, &ramps))
}
