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

/// Largest pressure increment of the sweep's load steps (bar), four times the solver's
/// default: only the states at the recorded pressures are used, and a converged state does
/// not depend on the path to it. Measured on the coarse N = 11, T = 2.0 actuator, 0 → 3 bar
/// with all 20 sensitivities, one core each: bending 96.6 → 60.5 s, blocked force 102.6 →
/// 65.7 s; tip, force and every derivative the same to 10⁻⁸ relative. Over the whole sweep
/// at the calibrated state every derivative of tip, angle and force is within 2.8 % of the
/// committed sweep in steps of 0.05 bar (`fe_reference/sensitivities/calibrated_coarse/`)
/// and the verdict is the same: `fe_reference/diagnosis/bench.md`.
pub const SWEEP_MAX_PRESSURE_INCREMENT: f64 = 0.2;

/// Newton tolerance of the sweep's ramps (normalised residual), ten times the solver's default:
/// the last Newton iteration of a load step takes the residual from about 10⁻⁶ to 10⁻¹⁰, and
/// the sensitivities do not need it. Measured on the coarse N = 13, T = 1.6 mm actuator at the
/// shipped experiments' calibrated set, 0 → 3 bar with all 20 sensitivities: bending 210 → 206
/// Newton iterations, blocked force 218 → 201; tip and force the same to 10⁻⁵, every
/// derivative of tip, angle and markers within 6·10⁻⁶ relative, of the force within 0.05 %
/// (one derivative of −1.5·10⁻⁴ N per unit within 0.5 %).
pub const SWEEP_RTOL: f64 = 1e-6;

/// Runs (or reads from `cache`) the bending and blocked-force ramps of every recorded design
/// at `material` on `mesh`, with the sensitivities of the four material parameters and every
/// effect of the library, in load steps of at most [`SWEEP_MAX_PRESSURE_INCREMENT`] to the
/// tolerance [`SWEEP_RTOL`];
/// `progress(done, total)` after every ramp.
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
    let mut settings = SweepSettings {
        sensitivities: Parameter::all(),
        ..SweepSettings::new(m, mesh)
    };
    settings.solver.max_pressure_increment = SWEEP_MAX_PRESSURE_INCREMENT;
    settings.solver.rtol = SWEEP_RTOL;
    let designs = recorded_designs(&rec.bending);
    run_ramps(&settings, &designs, Some(cache), progress).map_err(CalibrateError::from)?;
    // read back from the cache the sweep just filled: no FE
    let ramps = cached_ramps(&settings, &designs, cache).map_err(CalibrateError::from)?;
    Ok(SweepSensitivities::of(&settings, &ramps))
}
