//! The sensitivities of a sweep's ramps as one versioned file, as the discrepancy diagnoser
//! reads them.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::cache::BaselineError;
use super::ramps::SweepRamp;
use super::settings::SweepSettings;
use crate::fe::effects::{Effect, Effects};
use crate::fe::material::Material;
use crate::fe::mesh::MeshOptions;
use crate::fe::preset::Geometry;
use crate::fe::sensitivity::Sensitivities;
use crate::fe::simulate::Mode;

/// Format name of a sweep's sensitivities file ([`SweepSensitivities`]).
pub const SWEEP_SENSITIVITY_FORMAT: &str = "surrogate-sweep-sensitivities";

/// Version of that file.
pub const SWEEP_SENSITIVITY_VERSION: u32 = 1;

/// The sensitivities of one ramp of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignSensitivities {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Bending or blocked force.
    pub mode: Mode,
    /// Every reported step's outputs and their derivatives.
    pub sensitivities: Sensitivities,
}

/// The sensitivities of a sweep's ramps: what the discrepancy diagnoser reads (its
/// signatures of the effects, at the material of the sweep). Written by
/// `surrogate validate --sensitivities`, versioned and checked on load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepSensitivities {
    /// [`SWEEP_SENSITIVITY_FORMAT`].
    pub format: String,
    /// [`SWEEP_SENSITIVITY_VERSION`].
    pub version: u32,
    /// The material of every ramp.
    pub material: Material,
    /// The mesh.
    pub mesh: MeshOptions,
    /// The geometry of every ramp's design; written only when it is not
    /// [`Geometry::as_modelled`], so a file of the historical geometry is what it was before
    /// the field existed, and such a file reads back as modelled.
    #[serde(default, skip_serializing_if = "Geometry::is_as_modelled")]
    pub geometry: Geometry,
    /// The effects of every ramp (neutral: none).
    pub effects: Effects,
    /// One per ramp that finished.
    pub designs: Vec<DesignSensitivities>,
    /// Ramps without sensitivities, and why (not in the cache, stopped early).
    pub missing: Vec<String>,
}

impl SweepSensitivities {
    /// The sensitivities of `ramps`, run with `settings`.
    pub fn of(settings: &SweepSettings, ramps: &[SweepRamp]) -> Self {
        let mut designs = Vec::new();
        let mut missing = Vec::new();
        for r in ramps {
            match &r.sensitivities {
                Some(s) => designs.push(DesignSensitivities {
                    n_bellows: r.n_bellows,
                    wall_thickness_mm: r.wall_thickness_mm,
                    mode: r.mode,
                    sensitivities: s.clone(),
                }),
                None => missing.push(format!(
                    "N = {}, T = {} mm, {:?}: {}",
                    r.n_bellows,
                    r.wall_thickness_mm,
                    r.mode,
                    if r.error.is_empty() {
                        "no sensitivities"
                    } else {
                        &r.error
                    }
                )),
            }
        }
        Self {
            format: SWEEP_SENSITIVITY_FORMAT.into(),
            version: SWEEP_SENSITIVITY_VERSION,
            material: settings.material.clone(),
            mesh: settings.mesh,
            geometry: settings.geometry.clone(),
            effects: settings.effects.clone(),
            designs,
            missing,
        }
    }

    /// Reads a file written from [`Self::of`].
    ///
    /// # Errors
    /// [`BaselineError::Cache`] naming the file if it cannot be read or parsed, or is not
    /// this format and version.
    pub fn read(path: &Path) -> Result<Self, BaselineError> {
        let text = std::fs::read_to_string(path).map_err(|e| BaselineError::cache(path, e))?;
        let s: Self = serde_json::from_str(&text).map_err(|e| BaselineError::cache(path, e))?;
        if s.format != SWEEP_SENSITIVITY_FORMAT || s.version != SWEEP_SENSITIVITY_VERSION {
            return Err(BaselineError::cache(
                path,
                format!(
                    "format {} version {}: expected {SWEEP_SENSITIVITY_FORMAT} version                      {SWEEP_SENSITIVITY_VERSION}",
                    s.format, s.version
                ),
            ));
        }
        Ok(s)
    }

    /// The value of effect `e` in every ramp of the sweep: the point its sensitivities are
    /// taken at, from which an effect's estimated size is measured (its neutral value unless
    /// the sweep fixed it, as for a model trained with the force rig's plate).
    pub fn base(&self, e: Effect) -> f64 {
        self.effects.get(e)
    }

    /// The sensitivities of design `(n, t)` in `mode`, if there.
    pub fn design(&self, n: usize, t: f64, mode: Mode) -> Option<&Sensitivities> {
        self.designs
            .iter()
            .find(|d| d.n_bellows == n && d.wall_thickness_mm == t && d.mode == mode)
            .map(|d| &d.sensitivities)
    }
}
