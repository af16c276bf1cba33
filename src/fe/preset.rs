//! The dimensions the reference study leaves unstated, as one named set: a geometry preset.
//!
//! The study states N, T (4, 5 or 6 perimeters of a 0.4 mm nozzle), the height 22 mm and the
//! width 16 mm. It does not state the gap between the bellows, the base (strain-limiting
//! layer), the duct, the thickness of the side walls (the actuators were printed on their
//! side, so the walls normal to x are solid layers, not perimeters) or the clamped length.
//! A [`Geometry`] holds one value for each, shared by every design: `Geometry::design(N, T)`
//! is the actuator of that design built with them.
//!
//! [`Geometry::as_modelled`] is the model's historical choice (gap 1 mm, base 4 mm, duct
//! half-width 2 mm, free length 92 mm, side walls `T` thick); its designs are bit for bit
//! those of [`DesignParams::new`], so every cache keyed by a design stays valid. The
//! identification ([`crate::calibrate::joint`]) writes the values it finds as a preset of
//! its own.
//!
//! Two more are optional (absent in every preset written before them): the depth of the gaps
//! between the bellows, as the height of their floor above the base (the facing walls fused
//! below it), and solid blocks in the cavities' floor corners (a fillet on the grid).
//!
//! Physical ranges (mm), refused outside with a named error: gap 0.2 … 2, base 3.2 … 7, duct
//! half-width 0.5 … 4, side wall 0.6 … 3.4, free length 86 … 98, gap floor 0 … 9, cavity
//! fillet 0 … 3. A preset that leaves some
//! design without a valid actuator (a closed cavity) is refused by [`Geometry::design`].

use std::path::Path;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::geometry::{
    Design, DesignParams, GeometryError, PartStiffness, MIN_CAVITY_LENGTH, PART_STIFFNESS_RANGE,
    PRINTED_WALL_RANGE, T_RANGE,
};

/// Physical range of the gap between neighbouring bellows (mm).
pub const GAP_RANGE: (f64, f64) = (0.2, 2.0);
/// Physical range of the base thickness (mm): above the duct, below the bellows' cavities.
pub const BASE_RANGE: (f64, f64) = (3.2, 7.0);
/// Physical range of the duct's half-width (mm).
pub const DUCT_HALF_WIDTH_RANGE: (f64, f64) = (0.5, 4.0);
/// Physical range of the free length (mm).
pub const FREE_LENGTH_RANGE: (f64, f64) = (86.0, 98.0);
/// Physical range of the gaps' floor above the base (mm): from gaps open down to the base to
/// gaps fused over half the bellows' height.
pub const GAP_FLOOR_RANGE: (f64, f64) = (0.0, 9.0);
/// Physical range of the cavities' corner blocks (mm).
pub const CAVITY_FILLET_RANGE: (f64, f64) = (0.0, 3.0);
/// Range of [`WallLaw::offset_mm`] (mm): about a perimeter's width either way.
pub const WALL_LAW_OFFSET_RANGE: (f64, f64) = (-0.6, 0.6);
/// Range of [`WallLaw::inverse_cavity_mm2`] (mm²): up to ±1.5 mm at the shortest cavity of
/// the recorded designs (2 mm).
pub const WALL_LAW_INVERSE_CAVITY_RANGE: (f64, f64) = (-3.0, 3.0);

/// Walls printed off nominal by an amount that depends on the design: every wall of design
/// `(N, T)` (the walls facing the gaps, the tops and the side walls) is thicker than drawn by
/// `offset_mm + inverse_cavity_mm2 / c`, with `c = Lf / N − g − 2T` the drawn cavity's length
/// along the actuator. A print whose perimeters crowd a short cavity has `inverse_cavity_mm2 >
/// 0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallLaw {
    /// The offset of every design (mm).
    pub offset_mm: f64,
    /// The part that grows as the cavity gets shorter (mm²).
    pub inverse_cavity_mm2: f64,
}

impl WallLaw {
    /// The offset of the walls of a design with this drawn cavity length (mm).
    pub fn offset(&self, cavity_mm: f64) -> f64 {
        self.offset_mm + self.inverse_cavity_mm2 / cavity_mm
    }
}

/// Errors of a geometry preset.
#[derive(Debug, Error)]
pub enum PresetError {
    /// A dimension outside its physical range.
    #[error("geometry preset '{preset}': {field} = {value}{unit} is outside its physical range: expected {lo} … {hi}{unit}")]
    OutOfRange {
        /// The preset's name.
        preset: String,
        /// The dimension.
        field: &'static str,
        /// Its value (mm).
        value: f64,
        /// Lower end (mm).
        lo: f64,
        /// Upper end (mm).
        hi: f64,
        /// The unit as printed after a value (" mm", or "" for a ratio).
        unit: &'static str,
    },
    /// A name that is no preset.
    #[error(
        "unknown geometry preset '{0}': expected as_modelled, identified or a preset file (.json)"
    )]
    Unknown(String),
    /// A design this preset cannot build.
    #[error("geometry preset '{preset}' at N = {n}, T = {t} mm: {source}")]
    Design {
        /// The preset's name.
        preset: String,
        /// Number of bellows.
        n: usize,
        /// Wall thickness (mm).
        t: f64,
        /// Why.
        source: GeometryError,
    },
    /// A preset file that cannot be read.
    #[error("geometry preset file {path}: {why}")]
    File {
        /// The file.
        path: String,
        /// Why.
        why: String,
    },
}

/// The unstated dimensions, one value each for every design (mm).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Its name (`as_modelled`, or what the identification calls it).
    pub name: String,
    /// Gap between neighbouring bellows.
    pub gap_mm: f64,
    /// Base (strain-limiting layer) thickness.
    pub base_thickness_mm: f64,
    /// Half-width of the air duct in the base.
    pub duct_half_width_mm: f64,
    /// Free length, support face to tip.
    pub free_length_mm: f64,
    /// Side walls (normal ±x, solid layers of the print), the same for every `T`; `None`:
    /// `T` thick like the other walls.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side_wall_mm: Option<f64>,
    /// Height above the base of the gaps' floor: neighbouring bellows fused below it
    /// ([`DesignParams::gap_floor`]); `None`: the gaps reach down to the base.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_floor_mm: Option<f64>,
    /// Solid blocks in the cavities' bottom corners ([`DesignParams::cavity_fillet`]);
    /// `None`: sharp corners.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cavity_fillet_mm: Option<f64>,
    /// The stiffness of each printed part relative to the material
    /// ([`DesignParams::part_stiffness`]); `None`: every part as the material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub part_stiffness: Option<PartStiffness>,
    /// Walls off nominal by a law of the cavity length ([`WallLaw`]); `None`: as drawn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_law: Option<WallLaw>,
}

impl Default for Geometry {
    fn default() -> Self {
        Self::as_modelled()
    }
}

impl Geometry {
    /// The model's historical values ([`DesignParams::default`]).
    pub fn as_modelled() -> Self {
        let d = DesignParams::default();
        Self {
            name: "as_modelled".into(),
            gap_mm: d.gap,
            base_thickness_mm: d.base_thickness,
            duct_half_width_mm: d.duct_half_width,
            free_length_mm: d.free_length,
            side_wall_mm: None,
            gap_floor_mm: None,
            cavity_fillet_mm: None,
            part_stiffness: None,
            wall_law: None,
        }
    }

    /// Whether this is the historical geometry (its designs are [`DesignParams::new`]'s).
    pub fn is_as_modelled(&self) -> bool {
        let m = Self::as_modelled();
        self.gap_mm == m.gap_mm
            && self.base_thickness_mm == m.base_thickness_mm
            && self.duct_half_width_mm == m.duct_half_width_mm
            && self.free_length_mm == m.free_length_mm
            && self.side_wall_mm.is_none()
            && self.gap_floor_mm.is_none()
            && self.cavity_fillet_mm.is_none()
            && self.part_stiffness.is_none()
            && self.wall_law.is_none()
    }

    /// The geometry the joint identification found for the actuators that were built
    /// (`data/geometry/identified.json`, built into the library): gap 0.2 mm, side walls
    /// 2.92 mm, base 5.16 mm, walls off nominal by `−0.278 + 1.325 / c` mm
    /// (`fe_reference/identification/README.md`).
    /// The values are those of the file, to the last digit (tested).
    pub fn identified() -> Self {
        Self {
            name: "identified".into(),
            gap_mm: 0.2,
            base_thickness_mm: 5.158487780919267,
            duct_half_width_mm: 2.0,
            free_length_mm: 92.0,
            side_wall_mm: Some(2.9182015460280297),
            gap_floor_mm: None,
            cavity_fillet_mm: None,
            part_stiffness: None,
            wall_law: Some(WallLaw {
                offset_mm: -0.27769828608339125,
                inverse_cavity_mm2: 1.3251425094449878,
            }),
        }
    }

    /// A named preset (`as_modelled`, `identified`) or a preset file (a path ending in
    /// `.json`).
    ///
    /// # Errors
    /// [`PresetError::Unknown`], [`PresetError::File`], or the file's first dimension outside
    /// its physical range.
    pub fn from_name(name: &str) -> Result<Self, PresetError> {
        match name {
            "as_modelled" => Ok(Self::as_modelled()),
            "identified" => Ok(Self::identified()),
            n if n.ends_with(".json") => Self::load(Path::new(n)),
            n => Err(PresetError::Unknown(n.to_string())),
        }
    }

    /// Reads a preset file (JSON, the fields of [`Geometry`]) and checks it.
    ///
    /// # Errors
    /// [`PresetError::File`] for a missing or malformed file, [`PresetError::OutOfRange`].
    pub fn load(path: &Path) -> Result<Self, PresetError> {
        let file = |why: String| PresetError::File {
            path: path.display().to_string(),
            why,
        };
        let text = std::fs::read_to_string(path).map_err(|e| file(e.to_string()))?;
        let g: Geometry = serde_json::from_str(&text).map_err(|e| file(e.to_string()))?;
        g.validate()?;
        Ok(g)
    }

    /// Checks every dimension against its physical range.
    ///
    /// # Errors
    /// [`PresetError::OutOfRange`] naming the first dimension outside.
    pub fn validate(&self) -> Result<(), PresetError> {
        let check = |field: &'static str, value: f64, (lo, hi): (f64, f64)| {
            if value.is_finite() && value >= lo && value <= hi {
                Ok(())
            } else {
                Err(PresetError::OutOfRange {
                    preset: self.name.clone(),
                    field,
                    value,
                    lo,
                    hi,
                    unit: match field {
                        f if f.starts_with("part_stiffness") => "",
                        "wall_law.inverse_cavity_mm2" => " mm²",
                        _ => " mm",
                    },
                })
            }
        };
        check("gap_mm", self.gap_mm, GAP_RANGE)?;
        check("base_thickness_mm", self.base_thickness_mm, BASE_RANGE)?;
        check(
            "duct_half_width_mm",
            self.duct_half_width_mm,
            DUCT_HALF_WIDTH_RANGE,
        )?;
        check("free_length_mm", self.free_length_mm, FREE_LENGTH_RANGE)?;
        if let Some(s) = self.side_wall_mm {
            check("side_wall_mm", s, PRINTED_WALL_RANGE)?;
        }
        if let Some(f) = self.gap_floor_mm {
            check("gap_floor_mm", f, GAP_FLOOR_RANGE)?;
        }
        if let Some(r) = self.cavity_fillet_mm {
            check("cavity_fillet_mm", r, CAVITY_FILLET_RANGE)?;
        }
        if let Some(w) = &self.wall_law {
            check("wall_law.offset_mm", w.offset_mm, WALL_LAW_OFFSET_RANGE)?;
            check(
                "wall_law.inverse_cavity_mm2",
                w.inverse_cavity_mm2,
                WALL_LAW_INVERSE_CAVITY_RANGE,
            )?;
        }
        if let Some(k) = &self.part_stiffness {
            for (field, v) in k.fields() {
                check(field, v, PART_STIFFNESS_RANGE)?;
            }
        }
        Ok(())
    }

    /// The raw parameters of design `(n, t)` with these dimensions; exactly
    /// [`DesignParams::new`]`(n, t)` for [`Geometry::as_modelled`].
    pub fn params(&self, n: usize, t: f64) -> DesignParams {
        let mut p = DesignParams::new(n, t);
        if self.is_as_modelled() {
            return p;
        }
        p.gap = self.gap_mm;
        p.base_thickness = self.base_thickness_mm;
        p.duct_half_width = self.duct_half_width_mm;
        p.free_length = self.free_length_mm;
        p.side_wall_thickness = self.side_wall_mm;
        p.gap_floor = self.gap_floor_mm;
        p.cavity_fillet = self.cavity_fillet_mm;
        p.part_stiffness = self.part_stiffness;
        if let Some(w) = &self.wall_law {
            let d = w.offset(self.cavity_length(n, t));
            p.bellow_wall_thickness = Some(t + d);
            p.skin_thickness = Some(t + d);
            p.side_wall_thickness = p.side_wall_thickness.map(|s| s + d);
        }
        p
    }

    /// The drawn cavity length along the actuator of design `(n, t)`, `Lf / N − g − 2T` (mm):
    /// what [`WallLaw`] reads.
    pub fn cavity_length(&self, n: usize, t: f64) -> f64 {
        self.free_length_mm / n as f64 - self.gap_mm - 2.0 * t
    }

    /// The largest wall thickness `T` (mm) inside [`T_RANGE`] at which design `(n, T)` is a
    /// valid actuator with these dimensions (the buildability limit of `N`), or `None` when
    /// even the thinnest `T` is not.
    ///
    /// For [`Geometry::as_modelled`] this is the drawn rule `(Lf/N − g − 0.5)/2` less
    /// 10⁻⁹ mm, capped at the range's top. Otherwise it is found by bisection to 10⁻⁹ mm on
    /// [`Geometry::params`]'s validity, which a wall law makes nonlinear in `T` (a printed
    /// cavity `c − 2(a + b/c)` shrinks with `T` for `b ≥ 0`); the value returned is itself
    /// checked valid.
    pub fn max_wall_thickness(&self, n: usize) -> Option<f64> {
        let (t_lo, t_hi) = T_RANGE;
        let valid = |t: f64| self.params(n, t).validate().is_ok();
        if self.is_as_modelled() {
            let drawn = (self.free_length_mm / n as f64 - self.gap_mm - MIN_CAVITY_LENGTH) / 2.0;
            let t = (drawn - 1e-9).min(t_hi);
            return (t >= t_lo).then_some(t);
        }
        if !valid(t_lo) {
            return None;
        }
        if valid(t_hi) {
            return Some(t_hi);
        }
        let (mut lo, mut hi) = (t_lo, t_hi);
        while hi - lo > 1e-9 {
            let mid = 0.5 * (lo + hi);
            if valid(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(lo)
    }

    /// The validated design `(n, t)` with these dimensions.
    ///
    /// # Errors
    /// [`PresetError::OutOfRange`] for a dimension outside its physical range,
    /// [`PresetError::Design`] when the design is invalid with them (a closed cavity).
    pub fn design(&self, n: usize, t: f64) -> Result<Design, PresetError> {
        self.validate()?;
        self.params(n, t)
            .validate()
            .map_err(|source| PresetError::Design {
                preset: self.name.clone(),
                n,
                t,
                source,
            })
    }
}
