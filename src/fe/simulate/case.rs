//! The case: what one simulation is asked (design, material, pressures, rig, discretisation,
//! effects), its checks, and the pressure list's command-line syntax.
//!
//! A case is validated at the door ([`Case::validate`]) before any FE work; the design and the
//! material validate themselves when they are built. Pressures are gauge pressures in bar,
//! strictly increasing in `[0, MAX_PRESSURE_BAR]`; the model works in MPa (`p · BAR`).

use serde::{Deserialize, Serialize};

use super::SimulateError;
use crate::fe::contact::ContactError;
use crate::fe::effects::Effects;
use crate::fe::geometry::Design;
use crate::fe::material::Material;
use crate::fe::mesh::MeshOptions;
use crate::fe::solver::SolverSettings;

/// 1 bar in MPa.
pub const BAR: f64 = 0.1;
/// Largest pressure accepted (bar).
pub const MAX_PRESSURE_BAR: f64 = 10.0;

/// What the rig measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Free bending: markers, tip, angle.
    #[default]
    Bending,
    /// Blocked force: a rigid plate 5 mm below the tip of the actuator hanging unpressurised
    /// under its own weight; the plate's reaction per pressure step. The plate is an infinite
    /// frictionless plane; every outer face of the tip region (reference z ≥ Lf − 25: bottom
    /// layer, end cap, bellow flanks and tops, side wall) is searched against it, so a tip
    /// that turns past vertical rests on its end cap instead of passing through the plate.
    Force,
}

/// Contact settings of a case: bellow-to-bellow, first bellow against the clamp block, and
/// the tip against the force plate (penalty barrier, see [`crate::fe::contact`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactSettings {
    /// Contact on/off (bellow-to-bellow and clamp; the plate of [`Mode::Force`] is always on).
    pub enabled: bool,
    /// Penalty stiffness ε (MPa/mm).
    pub stiffness: f64,
    /// Smoothing width δ (mm).
    pub smoothing: f64,
    /// Bellow walls: gap to the closest point of the facing wall (frictionless under any
    /// sliding) instead of between points of equal reference position. Off by default: on the
    /// actuator the two agree to 0.01 % (`fe_reference/contact/README.md`), and the projection
    /// stays on the paired face (its polynomial extended), which suits small sliding only.
    /// Not written when off, so plans written before it keep their hash.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub closest_point: bool,
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            stiffness: 20.0,
            smoothing: 0.05,
            closest_point: false,
        }
    }
}

impl ContactSettings {
    /// Checks the ranges: ε ∈ [1, 1e5] MPa/mm, δ ∈ [0, 0.5] mm.
    ///
    /// # Errors
    /// [`ContactError::OutOfRange`] naming the setting.
    pub fn validate(&self) -> Result<(), ContactError> {
        if !(self.stiffness.is_finite() && (1.0..=1e5).contains(&self.stiffness)) {
            return Err(ContactError::OutOfRange {
                field: "contact stiffness",
                value: self.stiffness,
                expected: "a penalty stiffness in [1, 1e5] MPa/mm".into(),
            });
        }
        if !(self.smoothing.is_finite() && (0.0..=0.5).contains(&self.smoothing)) {
            return Err(ContactError::OutOfRange {
                field: "contact smoothing",
                value: self.smoothing,
                expected: "a smoothing width in [0, 0.5] mm".into(),
            });
        }
        Ok(())
    }
}

/// One simulation: design, material, pressures and discretisation.
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// The design.
    pub design: Design,
    /// The material.
    pub material: Material,
    /// Pressures (bar) at which results are reported, increasing, ≥ 0.
    pub pressures_bar: Vec<f64>,
    /// Self-weight on/off.
    pub gravity: bool,
    /// Mesh options.
    pub mesh: MeshOptions,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Bending or blocked force.
    pub mode: Mode,
    /// Contact settings.
    pub contact: ContactSettings,
    /// Physics beyond the nominal model ([`crate::fe::effects`]); neutral by default, and
    /// then not written.
    #[serde(skip_serializing_if = "Effects::is_neutral")]
    pub effects: Effects,
}

impl Case {
    /// Checks the case before any FE work: pressures ([`validate_pressures`]), mesh options,
    /// solver settings and contact settings. The design and the material validate themselves
    /// when they are built
    /// ([`DesignParams::validate`](crate::fe::geometry::DesignParams::validate),
    /// [`Material::new`]).
    ///
    /// # Errors
    /// [`SimulateError::Pressure`], [`SimulateError::Setting`] (field `mesh.…` or
    /// `solver.…`) or [`SimulateError::Contact`] for the first invalid entry.
    pub fn validate(&self) -> Result<(), SimulateError> {
        validate_pressures(&self.pressures_bar)?;
        self.mesh.validate().map_err(|e| e.within("mesh."))?;
        self.solver.validate().map_err(|e| e.within("solver."))?;
        self.contact.validate()?;
        self.printed_design()?;
        Ok(())
    }

    /// The design as printed: the nominal design with the effects' biases
    /// ([`Effects::printed_design`]); the nominal design itself when they are neutral.
    ///
    /// # Errors
    /// [`SimulateError::Geometry`] when a bias leaves an invalid design (e.g. no cavity).
    pub fn printed_design(&self) -> Result<Design, SimulateError> {
        if self.effects.is_neutral() {
            return Ok(self.design.clone());
        }
        Ok(self
            .effects
            .printed_design(self.design.params())
            .validate()?)
    }
}

/// Validates a pressure list (bar): finite, ≥ 0, strictly increasing, ≤ [`MAX_PRESSURE_BAR`].
///
/// # Errors
/// [`SimulateError::Pressure`] naming the first bad entry.
pub fn validate_pressures(p: &[f64]) -> Result<(), SimulateError> {
    if p.is_empty() {
        return Err(SimulateError::Pressure {
            index: 0,
            value: f64::NAN,
            expected: "at least one pressure".into(),
        });
    }
    for (i, &v) in p.iter().enumerate() {
        if v < 0.0 {
            return Err(SimulateError::Pressure {
                index: i,
                value: v,
                expected: format!(
                    "a gauge pressure ≥ 0 bar (a negative pressure, below atmospheric, is not \
                     modelled; the range is [0, {MAX_PRESSURE_BAR}] bar)"
                ),
            });
        }
        if !v.is_finite() || !(0.0..=MAX_PRESSURE_BAR).contains(&v) {
            return Err(SimulateError::Pressure {
                index: i,
                value: v,
                expected: format!("a gauge pressure in [0, {MAX_PRESSURE_BAR}] bar"),
            });
        }
        if i > 0 && v <= p[i - 1] {
            return Err(SimulateError::Pressure {
                index: i,
                value: v,
                expected: format!("pressures in increasing order (previous {})", p[i - 1]),
            });
        }
    }
    Ok(())
}

/// Parses a pressure list in bar: comma-separated values (`0,1,2,3`) or `max:step` (`3.5:0.25`:
/// 0, 0.25, …, 3.5; each level rounded to 1e-9 bar so that `3:0.1` gives `0.3`, not
/// `0.30000000000000004`). Positions in messages count from 1. The values are not range
/// checked here ([`validate_pressures`] does).
///
/// # Errors
/// [`SimulateError::PressureText`] naming the entry that is not a number or the malformed
/// `max:step`.
pub fn parse_pressures(s: &str) -> Result<Vec<f64>, SimulateError> {
    let text = |what: String| SimulateError::PressureText {
        list: s.to_string(),
        what,
    };
    if let Some((max, step)) = s.split_once(':') {
        let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let (Some(max), Some(step)) = (num(max), num(step)) else {
            return Err(text(
                "expected max:step, two numbers (e.g. 3.5:0.25)".into(),
            ));
        };
        if !(step > 0.0 && max >= 0.0 && max / step < 1e4) {
            return Err(text(format!(
                "max:step = {max}:{step}: expected max ≥ 0 and step > 0 (at most 10000 levels)"
            )));
        }
        let n = (max / step + 1e-9).floor() as usize;
        return Ok((0..=n)
            .map(|i| (i as f64 * step * 1e9).round() / 1e9)
            .collect());
    }
    s.split(',')
        .enumerate()
        .map(|(i, v)| {
            v.trim().parse::<f64>().map_err(|_| {
                text(format!(
                    "entry {} '{}' is not a number (expected bar values such as 0,1,2,3 or max:step such as 3.5:0.25)",
                    i + 1,
                    v.trim()
                ))
            })
        })
        .collect()
}
