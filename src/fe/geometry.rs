//! The actuator's design: the SPEC's dimensions live here and only here.
//!
//! Axes: `z` along the actuator from the support (z = 0) to the free tip (z = Lf), `y` vertical
//! with the strain-limiting base at the bottom (y ∈ [0, b]) and the bellows on top, `x` across the
//! width. Bellow `i` (0-based) is the box z ∈ [i·p + g/2, (i+1)·p − g/2], x ∈ [0, W], y ∈ [b, H]
//! with walls of thickness `T`; its cavity is z ∈ [i·p + g/2 + T, (i+1)·p − g/2 − T],
//! x ∈ [T, W − T], y ∈ [b, H − T]. The air duct in the base is
//! x ∈ [W/2 − d, W/2 + d], y ∈ [y₀, y₁], z ∈ [0, Lf − p/2].

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Errors of design parameters.
#[derive(Debug, Error, PartialEq)]
pub enum GeometryError {
    /// A parameter outside its allowed range.
    #[error("design parameter {field} = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// Parameter name.
        field: &'static str,
        /// Offending value.
        value: f64,
        /// The allowed range.
        expected: String,
    },
    /// The walls leave no cavity (or one too short to pressurise).
    #[error(
        "design N = {n}, T = {t} mm has no usable cavity: its cavity is {length:.3} mm long along z \
         (pitch {pitch:.3} − gap {gap} − 2·T), expected at least {min} mm"
    )]
    NoCavity {
        /// Number of bellows.
        n: usize,
        /// Wall thickness.
        t: f64,
        /// Cavity length along z.
        length: f64,
        /// Bellow pitch.
        pitch: f64,
        /// Gap between bellows.
        gap: f64,
        /// Minimum cavity length.
        min: f64,
    },
}

/// Smallest cavity length along z accepted by the SPEC (mm).
pub const MIN_CAVITY_LENGTH: f64 = 0.5;
/// Range of the number of bellows.
pub const N_RANGE: (usize, usize) = (7, 15);
/// Range of the wall thickness (mm).
pub const T_RANGE: (f64, f64) = (1.2, 2.8);
/// Range of a printed wall's actual thickness (mm) when it differs from the nominal `T`
/// ([`DesignParams::bellow_wall_thickness`], [`DesignParams::skin_thickness`]): the nominal
/// range widened by what a printer can miss.
pub const PRINTED_WALL_RANGE: (f64, f64) = (0.6, 3.4);

/// Raw design parameters (all lengths in mm). Defaults are the SPEC's pinned values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignParams {
    /// Number of bellows N.
    pub n_bellows: usize,
    /// Wall thickness T.
    pub wall_thickness: f64,
    /// Free length Lf (support face to tip).
    pub free_length: f64,
    /// Total height H.
    pub height: f64,
    /// Width W.
    pub width: f64,
    /// Base (strain-limiting layer) thickness b.
    pub base_thickness: f64,
    /// Gap g between neighbouring bellows.
    pub gap: f64,
    /// Half-width d of the air duct (duct spans W/2 ± d).
    pub duct_half_width: f64,
    /// Lower face y₀ of the air duct.
    pub duct_bottom: f64,
    /// Upper face y₁ of the air duct.
    pub duct_top: f64,
    /// Thickness of the bellow walls that face the gaps (normal ±z), when it differs from
    /// `wall_thickness` (a printed wall off nominal, [`crate::fe::effects`]). Not written when
    /// `None`, so designs written before it keep their hash.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bellow_wall_thickness: Option<f64>,
    /// Thickness of the outer skin of the bellows (the side wall, normal ±x, and the top,
    /// normal +y), when it differs from `wall_thickness`. Not written when `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skin_thickness: Option<f64>,
    /// Thickness of the side walls (normal ±x) alone, when it differs from the skin: the
    /// actuators are printed on their side, so these walls are solid layers whose thickness
    /// need not follow `T` ([`Geometry`]). Not written when `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side_wall_thickness: Option<f64>,
    /// Height above the base of the gaps' floor (mm): below it, the gap between two
    /// neighbouring bellows is solid, so their facing walls are one fused partition from the
    /// base up to this height; above it they stand apart. `None` (or 0): every gap reaches
    /// down to the base. Not written when `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_floor: Option<f64>,
    /// Size of the solid corner blocks at the cavities' floor (mm): each cavity's two bottom
    /// corners, where the walls facing the gaps meet the base, are solid over this height and
    /// this length along z (a fillet on the grid). A cavity shorter than twice the size has its
    /// whole floor raised by it. `None` (or 0): sharp corners. Not written when `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cavity_fillet: Option<f64>,
    /// Stiffness of each printed part relative to the material ([`PartStiffness`]): the walls
    /// facing the gaps and the top are shell layers (perimeters), the side walls solid layers
    /// and the base mostly infill, so their effective moduli need not agree. `None`: every
    /// part as the material. Not written when `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub part_stiffness: Option<PartStiffness>,
}

/// Range of a part's stiffness relative to the material ([`PartStiffness`]): from a quarter
/// (an under-extruded or poorly bonded part) to four times (a ceiling no print of one TPU
/// reaches, kept to bound what a mechanism can do).
pub const PART_STIFFNESS_RANGE: (f64, f64) = (0.25, 4.0);

/// Which printed part a point of the solid belongs to ([`Design::part`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The strain-limiting base (`y < b`), the duct's surroundings included.
    Base,
    /// The walls facing the gaps (normal ±z), with the fused gap roots and cavity corner
    /// blocks.
    GapWalls,
    /// The top of each bellow (normal +y).
    Top,
    /// The side walls (normal ±x).
    SideWalls,
}

/// The stiffness of each printed part relative to the material: every term of the strain
/// energy of an element in that part is multiplied by its factor (1: as the material).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartStiffness {
    /// The walls facing the gaps.
    pub gap_walls: f64,
    /// The tops of the bellows.
    pub top: f64,
    /// The side walls.
    pub side_walls: f64,
    /// The base.
    pub base: f64,
}

impl Default for PartStiffness {
    fn default() -> Self {
        Self {
            gap_walls: 1.0,
            top: 1.0,
            side_walls: 1.0,
            base: 1.0,
        }
    }
}

impl PartStiffness {
    /// The factor of `part`.
    pub fn of(&self, part: Part) -> f64 {
        match part {
            Part::Base => self.base,
            Part::GapWalls => self.gap_walls,
            Part::Top => self.top,
            Part::SideWalls => self.side_walls,
        }
    }

    /// The fields by their names in a design or preset (`part_stiffness.gap_walls`, …), in a
    /// fixed order.
    pub fn fields(&self) -> [(&'static str, f64); 4] {
        [
            ("part_stiffness.gap_walls", self.gap_walls),
            ("part_stiffness.top", self.top),
            ("part_stiffness.side_walls", self.side_walls),
            ("part_stiffness.base", self.base),
        ]
    }
}

impl Default for DesignParams {
    fn default() -> Self {
        Self {
            n_bellows: 11,
            wall_thickness: 2.0,
            free_length: 92.0,
            height: 22.0,
            width: 16.0,
            base_thickness: 4.0,
            gap: 1.0,
            duct_half_width: 2.0,
            duct_bottom: 1.0,
            duct_top: 3.0,
            bellow_wall_thickness: None,
            skin_thickness: None,
            side_wall_thickness: None,
            gap_floor: None,
            cavity_fillet: None,
            part_stiffness: None,
        }
    }
}

impl DesignParams {
    /// The SPEC's default design with the given N and T.
    pub fn new(n_bellows: usize, wall_thickness: f64) -> Self {
        Self {
            n_bellows,
            wall_thickness,
            ..Self::default()
        }
    }

    /// Validates the parameters.
    ///
    /// # Errors
    /// [`GeometryError::OutOfRange`] naming the first parameter outside its range, or
    /// [`GeometryError::NoCavity`] when the walls leave a cavity shorter than
    /// [`MIN_CAVITY_LENGTH`] along z (or none across x or y).
    pub fn validate(self) -> Result<Design, GeometryError> {
        let p = &self;
        let n = p.n_bellows;
        if n < N_RANGE.0 || n > N_RANGE.1 {
            return Err(GeometryError::OutOfRange {
                field: "n_bellows",
                value: n as f64,
                expected: format!("an integer in {}..={}", N_RANGE.0, N_RANGE.1),
            });
        }
        check_range("wall_thickness", p.wall_thickness, T_RANGE.0, T_RANGE.1)?;
        check_positive("free_length", p.free_length)?;
        check_positive("height", p.height)?;
        check_positive("width", p.width)?;
        check_range("base_thickness", p.base_thickness, 1e-3, p.height)?;
        check_range("gap", p.gap, 0.0, p.free_length / n as f64)?;
        check_range("duct_half_width", p.duct_half_width, 0.0, p.width / 2.0)?;
        check_range("duct_bottom", p.duct_bottom, 0.0, p.base_thickness)?;
        check_range("duct_top", p.duct_top, p.duct_bottom, p.base_thickness)?;
        if p.duct_half_width > 0.0 && !(p.duct_top > p.duct_bottom && p.duct_bottom > 0.0) {
            return Err(GeometryError::OutOfRange {
                field: "duct_top",
                value: p.duct_top,
                expected: format!(
                    "duct_bottom ({}) < duct_top < base_thickness ({}), duct_bottom > 0",
                    p.duct_bottom, p.base_thickness
                ),
            });
        }
        if let Some(tb) = p.bellow_wall_thickness {
            check_range(
                "bellow_wall_thickness",
                tb,
                PRINTED_WALL_RANGE.0,
                PRINTED_WALL_RANGE.1,
            )?;
        }
        if let Some(ts) = p.skin_thickness {
            check_range(
                "skin_thickness",
                ts,
                PRINTED_WALL_RANGE.0,
                PRINTED_WALL_RANGE.1,
            )?;
        }
        if let Some(tx) = p.side_wall_thickness {
            check_range(
                "side_wall_thickness",
                tx,
                PRINTED_WALL_RANGE.0,
                PRINTED_WALL_RANGE.1,
            )?;
        }
        let t = p.bellow_wall_thickness.unwrap_or(p.wall_thickness);
        let ts = p.skin_thickness.unwrap_or(p.wall_thickness);
        if let Some(f) = p.gap_floor {
            // the gaps stay open over at least the top skin's height
            check_range("gap_floor", f, 0.0, p.height - p.base_thickness - ts)?;
        }
        if let Some(r) = p.cavity_fillet {
            check_range(
                "cavity_fillet",
                r,
                0.0,
                (p.height - p.base_thickness - ts) / 2.0,
            )?;
        }
        if let Some(k) = &p.part_stiffness {
            for (name, v) in k.fields() {
                let (lo, hi) = PART_STIFFNESS_RANGE;
                if !(v.is_finite() && (lo..=hi).contains(&v)) {
                    return Err(GeometryError::OutOfRange {
                        field: name,
                        value: v,
                        expected: format!("a stiffness ratio in [{lo}, {hi}] (1: the material)"),
                    });
                }
            }
        }
        let tx = p.side_wall_thickness.unwrap_or(ts);
        let pitch = p.free_length / n as f64;
        let length = pitch - p.gap - 2.0 * t;
        if length < MIN_CAVITY_LENGTH
            || p.width - 2.0 * tx <= 0.0
            || p.height - ts <= p.base_thickness
        {
            return Err(GeometryError::NoCavity {
                n,
                t,
                length,
                pitch,
                gap: p.gap,
                min: MIN_CAVITY_LENGTH,
            });
        }
        Ok(Design { params: self })
    }
}

fn check_positive(field: &'static str, value: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeometryError::OutOfRange {
            field,
            value,
            expected: "a finite positive length in mm".into(),
        })
    }
}

fn check_range(field: &'static str, value: f64, lo: f64, hi: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(GeometryError::OutOfRange {
            field,
            value,
            expected: format!("a value in [{lo}, {hi}] mm"),
        })
    }
}

/// A validated design. Construct with [`DesignParams::validate`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Design {
    params: DesignParams,
}

/// An axis-aligned box `[lo, hi]` in (x, y, z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub lo: [f64; 3],
    /// Upper corner.
    pub hi: [f64; 3],
}

impl Aabb {
    /// Whether the point lies strictly inside the box.
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|i| p[i] > self.lo[i] && p[i] < self.hi[i])
    }
}

impl Design {
    /// The validated parameters.
    pub fn params(&self) -> &DesignParams {
        &self.params
    }
    /// Number of bellows N.
    pub fn n_bellows(&self) -> usize {
        self.params.n_bellows
    }
    /// Nominal wall thickness T (mm).
    pub fn wall_thickness(&self) -> f64 {
        self.params.wall_thickness
    }
    /// Thickness of the bellow walls facing the gaps (mm): T unless overridden.
    pub fn bellow_wall(&self) -> f64 {
        self.params
            .bellow_wall_thickness
            .unwrap_or(self.params.wall_thickness)
    }
    /// Thickness of the outer skin, side wall and top (mm): T unless overridden.
    pub fn skin(&self) -> f64 {
        self.params
            .skin_thickness
            .unwrap_or(self.params.wall_thickness)
    }
    /// Thickness of the side walls, normal ±x (mm): the skin's unless overridden.
    pub fn side_wall(&self) -> f64 {
        self.params
            .side_wall_thickness
            .unwrap_or_else(|| self.skin())
    }
    /// Free length Lf (mm).
    pub fn free_length(&self) -> f64 {
        self.params.free_length
    }
    /// Width W (mm).
    pub fn width(&self) -> f64 {
        self.params.width
    }
    /// Base thickness b (mm).
    pub fn base_thickness(&self) -> f64 {
        self.params.base_thickness
    }
    /// Height of the gaps' floor above the base (mm): 0 unless the gaps are fused at their
    /// root ([`DesignParams::gap_floor`]).
    pub fn gap_floor(&self) -> f64 {
        self.params.gap_floor.unwrap_or(0.0)
    }
    /// Size of the solid blocks in the cavities' bottom corners (mm): 0 unless set
    /// ([`DesignParams::cavity_fillet`]).
    pub fn cavity_fillet(&self) -> f64 {
        self.params.cavity_fillet.unwrap_or(0.0)
    }
    /// Bellow pitch p = Lf / N (mm).
    pub fn pitch(&self) -> f64 {
        self.params.free_length / self.params.n_bellows as f64
    }

    /// The box of bellow `i` (outer faces).
    pub fn bellow(&self, i: usize) -> Aabb {
        let p = &self.params;
        let pitch = self.pitch();
        Aabb {
            lo: [0.0, p.base_thickness, i as f64 * pitch + p.gap / 2.0],
            hi: [p.width, p.height, (i + 1) as f64 * pitch - p.gap / 2.0],
        }
    }

    /// The cavity of bellow `i`.
    pub fn cavity(&self, i: usize) -> Aabb {
        let p = &self.params;
        let b = self.bellow(i);
        let (t, ts, tx) = (self.bellow_wall(), self.skin(), self.side_wall());
        Aabb {
            lo: [tx, p.base_thickness, b.lo[2] + t],
            hi: [p.width - tx, p.height - ts, b.hi[2] - t],
        }
    }

    /// The air duct in the base, if any.
    pub fn duct(&self) -> Option<Aabb> {
        let p = &self.params;
        (p.duct_half_width > 0.0).then(|| Aabb {
            lo: [p.width / 2.0 - p.duct_half_width, p.duct_bottom, 0.0],
            hi: [
                p.width / 2.0 + p.duct_half_width,
                p.duct_top,
                p.free_length - self.pitch() / 2.0,
            ],
        })
    }

    /// The base (strain-limiting layer) box.
    pub fn base(&self) -> Aabb {
        let p = &self.params;
        Aabb {
            lo: [0.0, 0.0, 0.0],
            hi: [p.width, p.base_thickness, p.free_length],
        }
    }

    /// Reference positions of the 9 markers (x = W/2, y = 0, z = k·Lf/9, k = 1..9).
    pub fn markers(&self) -> [[f64; 3]; 9] {
        let p = &self.params;
        std::array::from_fn(|k| [p.width / 2.0, 0.0, (k + 1) as f64 * p.free_length / 9.0])
    }

    /// The support point (W/2, 0, 0).
    pub fn support_point(&self) -> [f64; 3] {
        [self.params.width / 2.0, 0.0, 0.0]
    }

    /// Classifies a point (away from interfaces) of the full design.
    pub fn region(&self, x: [f64; 3]) -> Region {
        let p = &self.params;
        let base = self.base();
        if base.contains(x) {
            return match self.duct() {
                Some(d) if d.contains(x) => Region::Duct,
                _ => Region::Solid,
            };
        }
        if x[1] <= p.base_thickness || x[1] >= p.height || x[0] <= 0.0 || x[0] >= p.width {
            return Region::Exterior;
        }
        let pitch = self.pitch();
        let i = ((x[2] / pitch).floor().max(0.0) as usize).min(p.n_bellows - 1);
        let bellow = self.bellow(i);
        let fused = x[1] < p.base_thickness + self.gap_floor();
        if x[2] < bellow.lo[2] {
            return match i {
                0 => Region::ClampGap,
                _ if fused => Region::Solid,
                _ => Region::Gap(i - 1),
            };
        }
        if x[2] > bellow.hi[2] {
            return match i + 1 < p.n_bellows {
                true if fused => Region::Solid,
                true => Region::Gap(i),
                false => Region::Exterior,
            };
        }
        let cavity = self.cavity(i);
        let r = self.cavity_fillet();
        let in_corner =
            x[1] < cavity.lo[1] + r && (x[2] < cavity.lo[2] + r || x[2] > cavity.hi[2] - r);
        if cavity.contains(x) && !in_corner {
            Region::Cavity(i)
        } else {
            Region::Solid
        }
    }
}

impl Design {
    /// The printed part a point of the solid belongs to: the base below `y = b`, then the
    /// side walls (`x` within the side-wall thickness of either face), then the top (within
    /// the skin of `y = H`), and every other solid point (the walls facing the gaps, fused gap
    /// roots, cavity corner blocks) to the walls facing the gaps.
    pub fn part(&self, x: [f64; 3]) -> Part {
        let p = &self.params;
        let tx = self.side_wall();
        if x[1] < p.base_thickness {
            Part::Base
        } else if x[0] < tx || x[0] > p.width - tx {
            Part::SideWalls
        } else if x[1] > p.height - self.skin() {
            Part::Top
        } else {
            Part::GapWalls
        }
    }

    /// The stiffness factor of the solid at `x` ([`DesignParams::part_stiffness`]); 1 when
    /// the parts are not set.
    pub fn stiffness_at(&self, x: [f64; 3]) -> f64 {
        self.params
            .part_stiffness
            .map_or(1.0, |k| k.of(self.part(x)))
    }
}

/// What occupies a point of the design's bounding box.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// TPU.
    Solid,
    /// The pressurised cavity of bellow `i`.
    Cavity(usize),
    /// The pressurised air duct in the base.
    Duct,
    /// The gap between bellow `i` and bellow `i + 1`.
    Gap(usize),
    /// The gap between the first bellow and the clamp block (z ∈ [0, g/2], y > b).
    ClampGap,
    /// Outside the actuator.
    Exterior,
}
