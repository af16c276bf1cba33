//! The unknowns of the identification, a point of it (material, geometry, effects) and each
//! unknown's bounds.

use serde::{Deserialize, Serialize};

use crate::calibrate::CalibrateError;
use crate::case::OgdenSet;
use crate::fe::effects::{Effect, Effects};
use crate::fe::geometry::PRINTED_WALL_RANGE;
use crate::fe::preset::{
    Geometry, WallLaw, BASE_RANGE, DUCT_HALF_WIDTH_RANGE, FREE_LENGTH_RANGE, GAP_RANGE,
    WALL_LAW_INVERSE_CAVITY_RANGE, WALL_LAW_OFFSET_RANGE,
};
use crate::fe::sensitivity::{OgdenParameter, Parameter};

/// One unknown of the identification.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unknown {
    /// An Ogden parameter.
    Material(OgdenParameter),
    /// Gap between the bellows (mm).
    Gap,
    /// Base thickness (mm).
    Base,
    /// Duct half-width (mm).
    Duct,
    /// Side-wall thickness, the same for every T (mm).
    SideWall,
    /// Free length (mm).
    FreeLength,
    /// The walls' offset shared by every design, [`WallLaw::offset_mm`] (mm).
    WallLawOffset,
    /// The walls' offset growing as the cavity gets shorter, [`WallLaw::inverse_cavity_mm2`]
    /// (mm²).
    WallLawInverseCavity,
    /// An effect of the library at one value for every ramp.
    Effect(Effect),
}

impl Unknown {
    /// Its name on the command line and in reports.
    pub fn name(self) -> String {
        match self {
            Unknown::Material(m) => Parameter::Material(m).name().to_string(),
            Unknown::Gap => "gap".into(),
            Unknown::Base => "base".into(),
            Unknown::Duct => "duct".into(),
            Unknown::SideWall => "side_wall".into(),
            Unknown::FreeLength => "free_length".into(),
            Unknown::WallLawOffset => "wall_law_offset".into(),
            Unknown::WallLawInverseCavity => "wall_law_inverse_cavity".into(),
            Unknown::Effect(e) => e.name().to_string(),
        }
    }

    /// The unknown called `name`.
    ///
    /// # Errors
    /// [`CalibrateError::Input`] listing the names.
    pub fn from_name(name: &str) -> Result<Self, CalibrateError> {
        Ok(match name {
            "gap" => Unknown::Gap,
            "base" => Unknown::Base,
            "duct" => Unknown::Duct,
            "side_wall" => Unknown::SideWall,
            "free_length" => Unknown::FreeLength,
            "wall_law_offset" => Unknown::WallLawOffset,
            "wall_law_inverse_cavity" => Unknown::WallLawInverseCavity,
            n => match Parameter::from_name(n) {
                Ok(Parameter::Material(m)) => Unknown::Material(m),
                Ok(Parameter::Effect(e))
                    if [
                        Effect::GapBias,
                        Effect::BaseBias,
                        Effect::DuctBias,
                        Effect::WallBiasSide,
                        Effect::FreeLengthBias,
                    ]
                    .contains(&e) =>
                {
                    return Err(CalibrateError::input(
                        "unknown",
                        n,
                        "the dimension itself (gap, base, duct, side_wall, free_length), \
                         not its bias",
                    ))
                }
                Ok(Parameter::Effect(e)) => Unknown::Effect(e),
                Err(_) => {
                    return Err(CalibrateError::input(
                        "unknown",
                        n,
                        "mu1, alpha1, mu2, alpha2, gap, base, duct, side_wall, free_length, \
                         wall_law_offset, wall_law_inverse_cavity or an effect name (surrogate \
                         effects)",
                    ))
                }
            },
        })
    }

    /// The parameter whose sensitivities are this unknown's derivatives.
    pub fn parameter(self) -> Parameter {
        match self {
            Unknown::Material(m) => Parameter::Material(m),
            Unknown::Gap => Parameter::Effect(Effect::GapBias),
            Unknown::Base => Parameter::Effect(Effect::BaseBias),
            Unknown::Duct => Parameter::Effect(Effect::DuctBias),
            Unknown::SideWall => Parameter::Effect(Effect::WallBiasSide),
            Unknown::FreeLength => Parameter::Effect(Effect::FreeLengthBias),
            Unknown::WallLawOffset | Unknown::WallLawInverseCavity => {
                Parameter::Effect(Effect::WallBias)
            }
            Unknown::Effect(e) => Parameter::Effect(e),
        }
    }

    /// The factor from [`Self::parameter`]'s derivative to this unknown's at design `(n, t)`
    /// of `geometry`: 1, except `1 / c` for [`Unknown::WallLawInverseCavity`] (the walls of
    /// that design move by `δb / c`).
    pub fn design_factor(self, geometry: &Geometry, n: usize, t: f64) -> f64 {
        match self {
            Unknown::WallLawInverseCavity => 1.0 / geometry.cavity_length(n, t),
            _ => 1.0,
        }
    }
}

/// A point of the identification: material, geometry, effects.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointPoint {
    /// The Ogden set (in the file: `[μ1, α1, μ2, α2]`).
    #[serde(with = "crate::case::material::array")]
    pub ogden: OgdenSet,
    /// The geometry.
    pub geometry: Geometry,
    /// The effects (rig, tolerances).
    pub effects: Effects,
}

impl JointPoint {
    /// The value of `u` here.
    pub fn get(&self, u: Unknown) -> f64 {
        let g = &self.geometry;
        match u {
            Unknown::Material(m) => self.ogden.as_array()[m as usize],
            Unknown::Gap => g.gap_mm,
            Unknown::Base => g.base_thickness_mm,
            Unknown::Duct => g.duct_half_width_mm,
            Unknown::SideWall => g.side_wall_mm.unwrap_or(f64::NAN),
            Unknown::FreeLength => g.free_length_mm,
            Unknown::WallLawOffset => g.wall_law.map_or(0.0, |w| w.offset_mm),
            Unknown::WallLawInverseCavity => g.wall_law.map_or(0.0, |w| w.inverse_cavity_mm2),
            Unknown::Effect(e) => self.effects.get(e),
        }
    }

    /// This point with `u` set to `v`.
    ///
    /// # Errors
    /// An effect value outside its range.
    pub fn set(&mut self, u: Unknown, v: f64) -> Result<(), CalibrateError> {
        let g = &mut self.geometry;
        match u {
            Unknown::Material(m) => {
                let mut p = self.ogden.as_array();
                p[m as usize] = v;
                self.ogden = OgdenSet::from_array(p);
            }
            Unknown::Gap => g.gap_mm = v,
            Unknown::Base => g.base_thickness_mm = v,
            Unknown::Duct => g.duct_half_width_mm = v,
            Unknown::SideWall => g.side_wall_mm = Some(v),
            Unknown::FreeLength => g.free_length_mm = v,
            Unknown::WallLawOffset | Unknown::WallLawInverseCavity => {
                let w = g.wall_law.get_or_insert(WallLaw {
                    offset_mm: 0.0,
                    inverse_cavity_mm2: 0.0,
                });
                match u {
                    Unknown::WallLawOffset => w.offset_mm = v,
                    _ => w.inverse_cavity_mm2 = v,
                }
            }
            Unknown::Effect(e) => self
                .effects
                .set(e, v)
                .map_err(|err| CalibrateError::input(e.name(), v, &err.to_string()))?,
        }
        Ok(())
    }
}

/// Bounds of `u` for a start at `x0`.
pub fn bounds(u: Unknown, x0: f64) -> (f64, f64) {
    match u {
        Unknown::Material(OgdenParameter::Mu1 | OgdenParameter::Mu2) => {
            let (a, b) = (x0 / 5.0, x0 * 5.0);
            (a.min(b), a.max(b))
        }
        Unknown::Material(_) if x0 >= 0.0 => (0.5, 12.0),
        Unknown::Material(_) => (-12.0, -0.5),
        Unknown::Gap => GAP_RANGE,
        Unknown::Base => BASE_RANGE,
        Unknown::Duct => DUCT_HALF_WIDTH_RANGE,
        Unknown::SideWall => PRINTED_WALL_RANGE,
        Unknown::FreeLength => FREE_LENGTH_RANGE,
        Unknown::WallLawOffset => WALL_LAW_OFFSET_RANGE,
        Unknown::WallLawInverseCavity => WALL_LAW_INVERSE_CAVITY_RANGE,
        Unknown::Effect(e) => e.info().range,
    }
}
