//! The FE sensitivities at the calibrated state: the sweep the Name and Model stages
//! linearise with, run for the recorded designs at the calibrated material (cached and
//! resumable), when no precomputed sweep fits; and which cells of the residual table a sweep
//! covers ([`SweepCoverage`]).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::cells::Cell;
use super::signature::{rig, sensitivity_step};
use super::wording::and_list;
use super::DiagnoseError;
use crate::calibrate::baseline::{
    cached_ramps, recorded_designs, run_ramps, SweepSensitivities, SweepSettings,
    SWEEP_MAX_PRESSURE_INCREMENT, SWEEP_RTOL,
};
use crate::calibrate::{CalibrateError, Recordings};
use crate::case::OgdenSet;
use crate::fe::effects::{Effect, Effects};
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::mesh::MeshOptions;
use crate::fe::preset::Geometry;
use crate::fe::sensitivity::Parameter;
use crate::fe::simulate::Mode;
use crate::rom::provenance::BuiltWith;

/// Cells with FE sensitivities the Name stage needs at least: the material's four directions
/// are projected out and each effect is tested against what is left, on one degree of freedom
/// beside the material and at least two for the residual.
pub const MIN_NAME_CELLS: usize = 7;

/// Runs (or reads from `cache`) the bending and blocked-force ramps of every recorded design
/// at `material` on `mesh`, built as the model's training cases were (`built`: the model's
/// [`BuiltWith`], none for the geometry as modelled without fixed effects), with the sensitivities of the four material parameters and every
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
    built: Option<&BuiltWith>,
    cache: &Path,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<SweepSensitivities, DiagnoseError> {
    let m = Material::from_spec(&material.spec(), DEFAULT_BULK_RATIO).map_err(|e| {
        DiagnoseError::input("calibrated material", material.spec(), &e.to_string())
    })?;
    let mut settings = SweepSettings {
        sensitivities: Parameter::all(),
        ..SweepSettings::new(m, mesh).built_as(built)
    };
    settings.solver.max_pressure_increment = SWEEP_MAX_PRESSURE_INCREMENT;
    settings.solver.rtol = SWEEP_RTOL;
    let designs = recorded_designs(&rec.bending);
    run_ramps(&settings, &designs, Some(cache), progress).map_err(CalibrateError::from)?;
    // read back from the cache the sweep just filled: no FE
    let ramps = cached_ramps(&settings, &designs, cache).map_err(CalibrateError::from)?;
    Ok(SweepSensitivities::of(&settings, &ramps))
}

/// Whether `sens` were computed on the model's actuator: the geometry and the fixed effects
/// of their sweep those the model's training cases were built with (`built`, the model's
/// [`BuiltWith`]; none: the geometry as modelled, no fixed effect). The effects' sizes of the
/// Name and Model stages are measured from the sweep's values and added to the model's
/// predictions, so a sweep of another actuator would count its differences twice or not at
/// all. A geometry is compared by its dimensions, not its name.
///
/// # Errors
/// [`DiagnoseError::SweepBuiltOtherwise`] naming the geometry or the fixed effects of both.
pub fn check_built_as(
    sens: &SweepSensitivities,
    built: Option<&BuiltWith>,
) -> Result<(), DiagnoseError> {
    let as_modelled = Geometry::as_modelled();
    let neutral = Effects::neutral();
    let (geometry, effects) = built.map_or((&as_modelled, &neutral), |b| (&b.geometry, &b.effects));
    let dimensions = |g: &Geometry| Geometry {
        name: String::new(),
        ..g.clone()
    };
    if dimensions(&sens.geometry) != dimensions(geometry) {
        return Err(DiagnoseError::SweepBuiltOtherwise {
            what: "geometry",
            sweep: geometry_text(&sens.geometry),
            model: geometry_text(geometry),
        });
    }
    if Effect::all().any(|e| sens.effects.get(e) != effects.get(e)) {
        return Err(DiagnoseError::SweepBuiltOtherwise {
            what: "fixed effects",
            sweep: effects_text(&sens.effects),
            model: effects_text(effects),
        });
    }
    Ok(())
}

/// A geometry in words: its name and dimensions.
fn geometry_text(g: &Geometry) -> String {
    format!(
        "'{}' ({})",
        g.name,
        serde_json::to_string(g).unwrap_or_default()
    )
}

/// Effects in words: `plate_offset = -4.5`, or `none`.
fn effects_text(e: &Effects) -> String {
    let set: Vec<String> = e
        .iter()
        .filter(|&(e, v)| v != e.info().neutral)
        .map(|(e, v)| format!("{} = {v}", e.name()))
        .collect();
    if set.is_empty() {
        "none".into()
    } else {
        set.join(", ")
    }
}

/// What computes the sensitivities a sweep lacks, in the command line's words.
pub const COMPUTE_MISSING: &str = "`--sensitivities calibrated` computes them by FE at the \
                                   calibrated material, for every recorded design and pressure";

/// A configuration of the residual table (design × pressure, in one rig) that a sweep has no
/// FE sensitivities for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Uncovered {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// The rig whose sensitivities are missing (bending outputs and markers: bending).
    pub rig: Mode,
    /// Cells (recorded outputs) of the configuration.
    pub cells: usize,
}

/// Which cells of a residual table a sweep of FE sensitivities covers: the Name and Model
/// stages linearise each cell with the sweep's derivatives at its design, rig and pressure,
/// and leave out the cells the sweep lacks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepCoverage {
    /// Cells of the residual table.
    pub cells: usize,
    /// Cells with sensitivities in the sweep.
    pub covered: usize,
    /// Cells with sensitivities the Name stage needs at least
    /// ([`MIN_NAME_CELLS`]).
    pub needed: usize,
    /// The configurations without sensitivities, by design, rig and pressure.
    pub uncovered: Vec<Uncovered>,
}

impl SweepCoverage {
    /// The coverage of `cells` by `sens`.
    pub fn of(cells: &[Cell], sens: &SweepSensitivities) -> Self {
        let mut uncovered: Vec<Uncovered> = Vec::new();
        let mut covered = 0;
        for c in cells {
            if sensitivity_step(sens, c).is_some() {
                covered += 1;
                continue;
            }
            let r = rig(c.output);
            match uncovered.iter_mut().find(|u| {
                u.n_bellows == c.n_bellows
                    && u.wall_thickness_mm == c.wall_thickness_mm
                    && u.pressure_bar == c.pressure_bar
                    && u.rig == r
            }) {
                Some(u) => u.cells += 1,
                None => uncovered.push(Uncovered {
                    n_bellows: c.n_bellows,
                    wall_thickness_mm: c.wall_thickness_mm,
                    pressure_bar: c.pressure_bar,
                    rig: r,
                    cells: 1,
                }),
            }
        }
        uncovered.sort_by(|a, b| {
            (a.rig as u8, a.n_bellows)
                .cmp(&(b.rig as u8, b.n_bellows))
                .then(a.wall_thickness_mm.total_cmp(&b.wall_thickness_mm))
                .then(a.pressure_bar.total_cmp(&b.pressure_bar))
        });
        SweepCoverage {
            cells: cells.len(),
            covered,
            needed: MIN_NAME_CELLS,
            uncovered,
        }
    }

    /// Every cell has sensitivities.
    pub fn complete(&self) -> bool {
        self.uncovered.is_empty()
    }

    /// Enough cells have sensitivities for the Name stage.
    pub fn enough(&self) -> bool {
        self.covered >= self.needed
    }

    /// The configurations without sensitivities in words, a design and rig at a time:
    /// `N = 11, T = 1.8 mm at 1, 2 and 3 bar (bending); N = 11, T = 2 mm at 0.5 bar (bending)`.
    pub fn uncovered_text(&self) -> String {
        let mut parts: Vec<String> = Vec::new();
        let mut i = 0;
        while i < self.uncovered.len() {
            let u = &self.uncovered[i];
            let same: Vec<&Uncovered> = self.uncovered[i..]
                .iter()
                .take_while(|v| {
                    v.rig == u.rig
                        && v.n_bellows == u.n_bellows
                        && v.wall_thickness_mm == u.wall_thickness_mm
                })
                .collect();
            let rig = match u.rig {
                Mode::Bending => "bending",
                Mode::Force => "blocked force",
            };
            parts.push(format!(
                "N = {}, T = {} mm at {} bar ({rig})",
                u.n_bellows,
                u.wall_thickness_mm,
                and_list(same.iter().map(|v| v.pressure_bar.to_string()).collect())
            ));
            i += same.len();
        }
        parts.join("; ")
    }

    /// The sentence of a report: how many cells the sweep covers, which configurations it
    /// lacks and what computes them (empty for a complete coverage).
    pub fn text(&self) -> String {
        if self.complete() {
            return String::new();
        }
        let verdict = if self.enough() {
            "the Name and Model stages leave the others out".to_string()
        } else {
            format!(
                "fewer than the {} the Name stage needs, so it does not run",
                self.needed
            )
        };
        format!(
            "the FE sensitivities cover {} of the {} cells of the residual table, {verdict}; \
             none at {}; {COMPUTE_MISSING}",
            self.covered,
            self.cells,
            self.uncovered_text()
        )
    }
}
