//! The FE settings shared by every case of a plan, and their checks.

use serde::{Deserialize, Serialize};

use crate::fe::effects::Effects;
use crate::fe::mesh::{MeshLevel, MeshOptions};
use crate::fe::preset::{Geometry, PresetError};
use crate::fe::simulate::ContactSettings;
use crate::fe::simulate::{validate_pressures, SimulateError};
use crate::fe::solver::SolverSettings;
use crate::snapshots::SnapshotError;

/// The FE settings shared by every case of a plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanSettings {
    /// The pressure ramp (bar), increasing, every level one snapshot.
    pub pressures_bar: Vec<f64>,
    /// Self-weight on/off.
    pub gravity: bool,
    /// Mesh level and optional element size.
    pub mesh: MeshOptions,
    /// Bulk modulus as a multiple of `μ0`.
    pub bulk_ratio: f64,
    /// Nonlinear solver settings.
    pub solver: SolverSettings,
    /// Contact settings (bellows, clamp, force plate).
    #[serde(default)]
    pub contact: ContactSettings,
    /// Effects fixed for every case (none: not written).
    #[serde(default, skip_serializing_if = "no_effects")]
    pub effects: Effects,
    /// The unstated dimensions every case is built with, a geometry preset (none: not
    /// written, [`Geometry::as_modelled`]; a plan written before the field reads as that).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<Geometry>,
}

/// Whether no effect is set (a plan without effects writes no `effects` field).
pub(super) fn no_effects(e: &Effects) -> bool {
    e.iter().next().is_none()
}

impl Default for PlanSettings {
    /// 0 → 3.5 bar in steps of 0.25 (15 levels), gravity, `standard` mesh, κ = 1000 μ0,
    /// default solver.
    fn default() -> Self {
        Self {
            pressures_bar: (0..=14).map(|i| f64::from(i) * 0.25).collect(),
            gravity: true,
            mesh: MeshOptions::level(MeshLevel::Standard),
            bulk_ratio: crate::fe::material::DEFAULT_BULK_RATIO,
            solver: SolverSettings::default(),
            contact: ContactSettings::default(),
            effects: Effects::default(),
            geometry: None,
        }
    }
}

impl PlanSettings {
    /// The geometry preset of every case ([`Geometry::as_modelled`] when none is set).
    pub fn geometry(&self) -> Geometry {
        self.geometry.clone().unwrap_or_default()
    }

    /// Checks the pressures, bulk ratio, mesh and solver settings.
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the field (`settings.<name>`).
    pub fn validate(&self) -> Result<(), SnapshotError> {
        if let Err(SimulateError::Pressure {
            index,
            value,
            expected,
        }) = validate_pressures(&self.pressures_bar)
        {
            return Err(SnapshotError::field(
                format!("settings.pressures_bar[{index}]"),
                value,
                &expected,
            ));
        }
        if !(self.bulk_ratio.is_finite() && self.bulk_ratio > 0.0) {
            return Err(SnapshotError::field(
                "settings.bulk_ratio",
                self.bulk_ratio,
                "a finite number > 0 (κ/μ0)",
            ));
        }
        let named = |e: crate::fe::InvalidSetting, prefix: &str| {
            SnapshotError::field(format!("{prefix}{}", e.field), e.value, &e.expected)
        };
        self.mesh
            .validate()
            .map_err(|e| named(e, "settings.mesh."))?;
        self.solver
            .validate()
            .map_err(|e| named(e, "settings.solver."))?;
        if let Err(crate::fe::contact::ContactError::OutOfRange {
            field,
            value,
            expected,
        }) = self.contact.validate()
        {
            let field = field.trim_start_matches("contact ");
            return Err(SnapshotError::field(
                format!("settings.contact.{field}"),
                value,
                &expected,
            ));
        }
        if let Some(g) = &self.geometry {
            match g.validate() {
                Ok(()) => {}
                Err(PresetError::OutOfRange {
                    field,
                    value,
                    lo,
                    hi,
                    unit,
                    ..
                }) => {
                    return Err(SnapshotError::field(
                        format!("settings.geometry.{field}"),
                        value,
                        &format!("{lo} … {hi}{unit} (its physical range)"),
                    ))
                }
                Err(e) => {
                    return Err(SnapshotError::field(
                        "settings.geometry",
                        &g.name,
                        &e.to_string(),
                    ))
                }
            }
        }
        Ok(())
    }
}
