//! Physics the nominal model leaves out, as switchable effects of a case.
//!
//! Each effect is a named parameter with a unit, a neutral value and a plausible range. At its
//! neutral value an effect changes nothing: the case runs exactly the floating-point operations
//! of a case without it (tested bit for bit). The diagnoser ranks these effects as candidate
//! explanations of a mismatch between the model and the recordings.
//!
//! | effect | unit | neutral | range | kind | what it changes |
//! |---|---|---|---|---|---|
//! | `wall_bias` | mm | 0 | −0.4 … 0.4 | tolerance | every bellow wall printed `T + bias` thick |
//! | `wall_bias_bellows` | mm | 0 | −0.4 … 0.4 | tolerance | only the walls facing the gaps (normal ±z) |
//! | `wall_bias_skin` | mm | 0 | −0.4 … 0.4 | tolerance | only the outer skin (side wall and top) |
//! | `wall_bias_side` | mm | 0 | −1.8 … 1.8 | unstated | only the side walls (normal ±x), within 0.6 … 3.4 mm |
//! | `gap_bias` | mm | 0 | −0.8 … 1.0 | unstated | gap between bellows `g + bias` (modelled 1 mm): 0.2 … 2 mm |
//! | `base_bias` | mm | 0 | −0.8 … 3.0 | unstated | base thickness `b + bias` (modelled 4 mm): 3.2 … 7 mm |
//! | `duct_bias` | mm | 0 | −1.5 … 2.0 | unstated | duct half-width `d + bias` (modelled 2 mm): 0.5 … 4 mm |
//! | `free_length_bias` | mm | 0 | −6 … 6 | unstated | free length `Lf + bias` (modelled 92 mm) |
//! | `clamp_compliance` | mm/MPa | 0 | 0 … 0.5 | tolerance | clamped face on normal springs `k = 1/c` |
//! | `clamp_shear_compliance` | mm/MPa | 0 | 0 … 0.5 | tolerance | clamped face on tangential springs |
//! | `pressure_loss` | 1 | 0 | 0 … 0.3 | tolerance | effective pressure `(1 − f)·P − p₀` |
//! | `pressure_offset` | bar | 0 | 0 … 0.3 | tolerance | the `p₀` above |
//! | `density` | 1 | 1 | 0.5 … 1.5 | tolerance | self-weight scaled |
//! | `anisotropy` | 1 | 0 | −0.25 … 1 | tolerance | fibre term along the length, `k = a·μ0` |
//! | `plate_offset` | mm | 0 | −4.5 … 2 | unstated | plate `5 + offset` mm below the sagged tip (a printed square of unstated height on the scale) |
//! | `plate_compliance` | mm/N | 0 | 0 … 1 | tolerance | plate yields `c·F` under the blocked force |
//! | `force_scale` | 1 | 1 | 0.7 … 1.3 | tolerance | reported blocked force scaled (load-cell calibration) |
//!
//! **Tolerances and unstated dimensions** ([`Kind`]). A tolerance is a print or rig error around
//! a value the reference study states (the wall thickness `T` is 4, 5 or 6 perimeters of a
//! 0.4 mm nozzle); its range is what a printer or a rig can miss. An unstated dimension is one
//! the study does not give (the gap, the base, the duct, the side walls' solid layers, the
//! clamped length, the height of the printed square under the tip in the force rig): the
//! model's value is an assumption, and the range is what is physically possible for this
//! actuator. Each entry's [`EffectInfo::source`] quotes the study's sentence or states its
//! silence. A combination that leaves no valid actuator (gap ≤ 0, walls meeting, a closed
//! cavity, a duct above the base) is refused by [`DesignParams::validate`] before any FE.
//!
//! Why each is plausible, from the printing process and the rigs:
//!
//! * **Walls** — FDM prints a wall as whole extrusion lines: a 1.6 mm wall with a 0.4 mm nozzle
//!   is four lines, and over- or under-extrusion, line overlap and the slicer's rounding move
//!   the printed thickness by a tenth of a millimetre or more. The walls facing the gaps and
//!   the outer skin are sliced differently (perimeters vs. the top surface), so they can err
//!   differently. The bending stiffness goes with `T³`: the thin walls are hit hardest, which is
//!   a pattern over `T`.
//! * **Dimensions** — the gap, base and duct are small features printed near the nozzle's
//!   resolution; the free length depends on where the clamp grips.
//! * **Clamp** — the actuator's base is held between printed or metal jaws; the TPU under the
//!   jaws and the jaws themselves yield. A compliance `c` (displacement per traction) of
//!   `ℓ/E` for a held length `ℓ` of material of modulus `E` gives ≈ 0.3 mm/MPa for 5 mm of TPU.
//!   It adds sag at P = 0 and rotation under pressure.
//! * **Pressure** — the gauge reads at the regulator; tubing, fittings and the inlet duct lose
//!   some pressure when flowing and a small offset to leaks or a zero error.
//! * **Density** — the print is not fully dense (infill, voids between lines), and the
//!   recorded mass of TPU varies by grade.
//! * **Print anisotropy** — the actuators are printed lying on their side, the bending plane
//!   parallel to the build plate, so the perimeter lines of the skin and the base run along
//!   the length `z`; lines bond to each other less well than a line holds together, which
//!   makes the print stiffer (`a > 0`) or, with poor fusion of the lines' ends, softer
//!   (`a < 0`) along `z` than across. Modelled as a transversely isotropic fibre term
//!   `W_f = k/2 (Ī₄ − 1)²` along `z` ([`Fibre`]) with `k = a·μ0`:
//!   the small-strain modulus along `z` becomes `3μ0 + 4k`, the shear moduli stay `μ0`.
//! * **Force rig** — the plate is set 5 mm below the hanging tip by eye; the load cell's
//!   calibration is a scale factor; the load cell and the plate's mount deflect under the
//!   force (a beam load cell with a cantilevered plate yields tenths of a millimetre per
//!   newton), which lowers the force the tip builds up against it.

use std::collections::BTreeMap;
use std::fmt;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::geometry::DesignParams;
use super::material::{Fibre, Material, MaterialError};

/// One effect of the library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    /// Every bellow wall off nominal (mm).
    WallBias,
    /// The walls facing the gaps off nominal (mm).
    WallBiasBellows,
    /// The outer skin (side wall, top) off nominal (mm).
    WallBiasSkin,
    /// The side walls (normal ±x, printed as solid layers) off their modelled thickness (mm).
    WallBiasSide,
    /// Gap between bellows off nominal (mm).
    GapBias,
    /// Base thickness off nominal (mm).
    BaseBias,
    /// Duct half-width off nominal (mm).
    DuctBias,
    /// Free length off nominal (mm).
    FreeLengthBias,
    /// Normal compliance of the clamp (mm/MPa).
    ClampCompliance,
    /// Tangential compliance of the clamp (mm/MPa).
    ClampShearCompliance,
    /// Fraction of the gauge pressure lost (1).
    PressureLoss,
    /// Pressure lost as an offset (bar).
    PressureOffset,
    /// Self-weight scale (1).
    Density,
    /// Print anisotropy: fibre modulus along the length over μ0 (1).
    Anisotropy,
    /// Plate further below the sagged tip than 5 mm (mm).
    PlateOffset,
    /// Compliance of the plate and load cell (mm/N).
    PlateCompliance,
    /// Load-cell scale (1).
    ForceScale,
}

/// Which rig an effect acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Acts {
    /// Both bending and blocked force.
    Both,
    /// The blocked-force rig only.
    Force,
}

/// What an effect's value stands for: a tolerance around a value the reference study states,
/// or a dimension (of the actuator or a rig) that it does not state, whose range is then what
/// is physically possible for this actuator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A print or rig tolerance around a stated value.
    Tolerance,
    /// A dimension the source does not state: the model's value is an assumption.
    Unstated,
}

/// What the library says about an effect.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct EffectInfo {
    /// The effect.
    pub effect: Effect,
    /// Its name on the command line and in files.
    pub name: &'static str,
    /// Physical meaning, one line.
    pub meaning: &'static str,
    /// Unit of its value.
    pub unit: &'static str,
    /// The value that changes nothing.
    pub neutral: f64,
    /// Plausible range `[lo, hi]` (values outside are refused).
    pub range: (f64, f64),
    /// A tolerance or an unstated dimension.
    pub kind: Kind,
    /// What the reference study says of it: its sentence, or its silence.
    pub source: &'static str,
    /// Which rig it acts on.
    pub acts_on: Acts,
}

/// The library, in the order listed by `surrogate effects`.
pub const EFFECTS: [EffectInfo; 17] = [
    EffectInfo {
        effect: Effect::WallBias,
        name: "wall_bias",
        meaning: "every bellow wall printed T + bias thick (over/under-extrusion)",
        unit: "mm",
        neutral: 0.0,
        range: (-0.4, 0.4),
        kind: Kind::Tolerance,
        source: "T = 1.6, 2.0, 2.4 mm: \"the deposition of 4, 5 and 6 shell layers\" of a 0.4 mm nozzle",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::WallBiasBellows,
        name: "wall_bias_bellows",
        meaning: "only the walls facing the gaps (normal ±z) off nominal",
        unit: "mm",
        neutral: 0.0,
        range: (-0.4, 0.4),
        kind: Kind::Tolerance,
        source: "the walls facing the gaps are shell layers (perimeters): T is stated",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::WallBiasSkin,
        name: "wall_bias_skin",
        meaning: "only the outer skin (side wall and top) off nominal",
        unit: "mm",
        neutral: 0.0,
        range: (-0.4, 0.4),
        kind: Kind::Tolerance,
        source: "side wall and top drawn T thick in the model; the drawing labels only \"wall thickness\"",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::WallBiasSide,
        name: "wall_bias_side",
        meaning: "only the side walls (normal ±x, solid layers of the print) off their modelled thickness",
        unit: "mm",
        neutral: 0.0,
        range: (-1.8, 1.8),
        kind: Kind::Unstated,
        source: "not stated: printed \"sideways, with the bending plane parallel to the building platform\", the side walls (normal x) are solid layers of 0.15 mm whose count is not given",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::GapBias,
        name: "gap_bias",
        meaning: "gap between neighbouring bellows off its nominal 1 mm",
        unit: "mm",
        neutral: 0.0,
        range: (-0.8, 1.0),
        kind: Kind::Unstated,
        source: "not stated: the drawing shows \"repeated slots\", the text \"narrow gaps\"; 1 mm is assumed",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::BaseBias,
        name: "base_bias",
        meaning: "strain-limiting base off its nominal 4 mm",
        unit: "mm",
        neutral: 0.0,
        range: (-0.8, 3.0),
        kind: Kind::Unstated,
        source: "not stated: the drawing gives only the height 22 and width 16; 4 mm is assumed",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::DuctBias,
        name: "duct_bias",
        meaning: "air duct half-width off its nominal 2 mm",
        unit: "mm",
        neutral: 0.0,
        range: (-1.5, 2.0),
        kind: Kind::Unstated,
        source: "not stated: \"chambers connected by a central duct\"; 2 mm half-width is assumed",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::FreeLengthBias,
        name: "free_length_bias",
        meaning: "free length off its nominal 92 mm (where the clamp grips)",
        unit: "mm",
        neutral: 0.0,
        range: (-6.0, 6.0),
        kind: Kind::Unstated,
        source: "not stated: \"the overall length of the actuator is set at 115 mm\" includes the clamped inlet; 92 mm free is assumed",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::ClampCompliance,
        name: "clamp_compliance",
        meaning: "clamped face on normal springs of stiffness 1/c per unit area (yielding jaws)",
        unit: "mm/MPa",
        neutral: 0.0,
        range: (0.0, 0.5),
        kind: Kind::Tolerance,
        source: "\"mounted horizontally on a 3D-printed custom support\": a rigid clamp is assumed",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::ClampShearCompliance,
        name: "clamp_shear_compliance",
        meaning: "clamped face on tangential springs of stiffness 1/c per unit area",
        unit: "mm/MPa",
        neutral: 0.0,
        range: (0.0, 0.5),
        kind: Kind::Tolerance,
        source: "as clamp_compliance",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::PressureLoss,
        name: "pressure_loss",
        meaning: "fraction f of the gauge pressure lost: effective (1 − f)·P − p0",
        unit: "1",
        neutral: 0.0,
        range: (0.0, 0.3),
        kind: Kind::Tolerance,
        source: "\"regulated by a pressure gauge at the compressor's outlet\" and an electro-pneumatic transducer",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::PressureOffset,
        name: "pressure_offset",
        meaning: "pressure p0 lost as an offset (leak, gauge zero): effective (1 − f)·P − p0",
        unit: "bar",
        neutral: 0.0,
        range: (0.0, 0.3),
        kind: Kind::Tolerance,
        source: "as pressure_loss",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::Density,
        name: "density",
        meaning: "self-weight scaled (print not fully dense, grade)",
        unit: "1",
        neutral: 1.0,
        range: (0.5, 1.5),
        kind: Kind::Tolerance,
        source: "NinjaFlex TPU; the print's density is not stated",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::Anisotropy,
        name: "anisotropy",
        meaning: "print anisotropy: fibre term along the length (deposition), k = a·μ0",
        unit: "1",
        neutral: 0.0,
        range: (-0.25, 1.0),
        kind: Kind::Tolerance,
        source: "printed sideways with PrusaSlicer, 0.4 mm nozzle, 0.15 mm layers; no anisotropy is reported",
        acts_on: Acts::Both,
    },
    EffectInfo {
        effect: Effect::PlateOffset,
        name: "plate_offset",
        meaning: "force plate this much further than 5 mm below the sagged tip (negative: closer)",
        unit: "mm",
        neutral: 0.0,
        range: (-4.5, 2.0),
        kind: Kind::Unstated,
        source: "not stated: the actuator \"was positioned 5 mm above the scale's plate to allow it to bend and apply force to a 3D-printed square\" of unstated height",
        acts_on: Acts::Force,
    },
    EffectInfo {
        effect: Effect::PlateCompliance,
        name: "plate_compliance",
        meaning: "plate and load cell on a spring: the plate yields c·F under the force F",
        unit: "mm/N",
        neutral: 0.0,
        range: (0.0, 1.0),
        kind: Kind::Tolerance,
        source: "\"a digital scale with a 0.1 g sensitivity\"",
        acts_on: Acts::Force,
    },
    EffectInfo {
        effect: Effect::ForceScale,
        name: "force_scale",
        meaning: "load cell's calibration: recorded force = scale × plate reaction",
        unit: "1",
        neutral: 1.0,
        range: (0.7, 1.3),
        kind: Kind::Tolerance,
        source: "as plate_compliance",
        acts_on: Acts::Force,
    },
];

impl Effect {
    /// The library entry of this effect.
    pub fn info(self) -> &'static EffectInfo {
        // EFFECTS lists the variants in declaration order (tested)
        &EFFECTS[self as usize]
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The effect called `name`.
    ///
    /// # Errors
    /// [`EffectError::Unknown`] listing the known names.
    pub fn from_name(name: &str) -> Result<Self, EffectError> {
        EFFECTS
            .iter()
            .find(|i| i.name == name)
            .map(|i| i.effect)
            .ok_or_else(|| EffectError::Unknown {
                name: name.to_string(),
                known: EFFECTS
                    .iter()
                    .map(|i| i.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// Every effect.
    pub fn all() -> impl Iterator<Item = Effect> {
        EFFECTS.iter().map(|i| i.effect)
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Errors of effect settings.
#[derive(Debug, Error, PartialEq)]
pub enum EffectError {
    /// A name that is not in the library.
    #[error("unknown effect {name:?}: expected one of {known}")]
    Unknown {
        /// The name as given.
        name: String,
        /// The library's names.
        known: String,
    },
    /// A value outside the effect's range (or not finite).
    #[error("effect {name} = {value} {unit}: expected a value in [{lo}, {hi}] {unit}")]
    OutOfRange {
        /// The effect.
        name: &'static str,
        /// The value.
        value: f64,
        /// Its unit.
        unit: &'static str,
        /// Lower end of the range.
        lo: f64,
        /// Upper end of the range.
        hi: f64,
    },
    /// The same effect given twice.
    #[error("effect {name} given twice ({first} and {second}): expected each effect at most once")]
    Duplicate {
        /// The effect.
        name: &'static str,
        /// The first value.
        first: f64,
        /// The second value.
        second: f64,
    },
    /// Not `NAME=VALUE`.
    #[error("effect {text:?}: expected NAME=VALUE, e.g. wall_bias=-0.1 (see `surrogate effects`)")]
    Syntax {
        /// The text as given.
        text: String,
    },
}

/// The effects of a case: each effect's value, neutral where not set.
///
/// Serialised as a map `{name: value}` of the effects that are set; a case without effects
/// writes none (`#[serde(skip_serializing_if = "Effects::is_neutral")]`), so its files and
/// hashes are those of a case written before effects existed.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "BTreeMap<String, f64>", into = "BTreeMap<String, f64>")]
pub struct Effects {
    values: BTreeMap<Effect, f64>,
}

impl TryFrom<BTreeMap<String, f64>> for Effects {
    type Error = EffectError;
    fn try_from(m: BTreeMap<String, f64>) -> Result<Self, EffectError> {
        let mut e = Effects::default();
        for (name, v) in m {
            e.set(Effect::from_name(&name)?, v)?;
        }
        Ok(e)
    }
}

impl From<Effects> for BTreeMap<String, f64> {
    fn from(e: Effects) -> Self {
        e.values
            .into_iter()
            .map(|(k, v)| (k.name().to_string(), v))
            .collect()
    }
}

impl Effects {
    /// No effect.
    pub fn neutral() -> Self {
        Self::default()
    }

    /// Whether every effect is at its neutral value.
    pub fn is_neutral(&self) -> bool {
        self.values.iter().all(|(e, &v)| v == e.info().neutral)
    }

    /// The value of `e` (its neutral value when not set).
    pub fn get(&self, e: Effect) -> f64 {
        self.values.get(&e).copied().unwrap_or(e.info().neutral)
    }

    /// The effects that are set, with their values.
    pub fn iter(&self) -> impl Iterator<Item = (Effect, f64)> + '_ {
        self.values.iter().map(|(&e, &v)| (e, v))
    }

    /// Sets `e` to `value` after checking its range.
    ///
    /// # Errors
    /// [`EffectError::OutOfRange`] for a value outside the range or not finite.
    pub fn set(&mut self, e: Effect, value: f64) -> Result<(), EffectError> {
        let info = e.info();
        if !(value.is_finite() && value >= info.range.0 && value <= info.range.1) {
            return Err(EffectError::OutOfRange {
                name: info.name,
                value,
                unit: info.unit,
                lo: info.range.0,
                hi: info.range.1,
            });
        }
        self.values.insert(e, value);
        Ok(())
    }

    /// These effects with `e` set to `value`.
    ///
    /// # Errors
    /// See [`Effects::set`].
    pub fn with(mut self, e: Effect, value: f64) -> Result<Self, EffectError> {
        self.set(e, value)?;
        Ok(self)
    }

    /// Parses `NAME=VALUE` assignments (the command line's repeated `--effect`).
    ///
    /// # Errors
    /// [`EffectError::Syntax`], [`EffectError::Unknown`], [`EffectError::OutOfRange`] or
    /// [`EffectError::Duplicate`] for the first bad assignment.
    pub fn parse<'a>(items: impl IntoIterator<Item = &'a str>) -> Result<Self, EffectError> {
        let mut out = Effects::default();
        for text in items {
            let (name, value) = text.split_once('=').ok_or_else(|| EffectError::Syntax {
                text: text.to_string(),
            })?;
            let e = Effect::from_name(name.trim())?;
            let v: f64 = value.trim().parse().map_err(|_| EffectError::Syntax {
                text: text.to_string(),
            })?;
            if let Some(&first) = out.values.get(&e) {
                return Err(EffectError::Duplicate {
                    name: e.name(),
                    first,
                    second: v,
                });
            }
            out.set(e, v)?;
        }
        Ok(out)
    }

    /// The design as printed: the nominal design with the wall and dimension biases applied.
    /// Neutral biases leave it unchanged (the same value, not a recomputed one).
    pub fn printed_design(&self, nominal: &DesignParams) -> DesignParams {
        let mut p = nominal.clone();
        let add = |x: f64, e: Effect| -> f64 {
            match self.values.get(&e) {
                Some(&b) if b != 0.0 => x + b,
                _ => x,
            }
        };
        let all = self.get(Effect::WallBias);
        let (bellows, skin) = (
            self.get(Effect::WallBiasBellows),
            self.get(Effect::WallBiasSkin),
        );
        let t = nominal.wall_thickness;
        if all != 0.0 || bellows != 0.0 {
            p.bellow_wall_thickness =
                Some(nominal.bellow_wall_thickness.unwrap_or(t) + all + bellows);
        }
        if all != 0.0 || skin != 0.0 {
            p.skin_thickness = Some(nominal.skin_thickness.unwrap_or(t) + all + skin);
        }
        let side = self.get(Effect::WallBiasSide);
        if all != 0.0 || skin != 0.0 || side != 0.0 {
            if let Some(s) = nominal.side_wall_thickness {
                p.side_wall_thickness = Some(s + all + skin + side);
            } else if side != 0.0 {
                p.side_wall_thickness =
                    Some(nominal.skin_thickness.unwrap_or(t) + all + skin + side);
            }
        }
        p.gap = add(p.gap, Effect::GapBias);
        p.base_thickness = add(p.base_thickness, Effect::BaseBias);
        p.duct_half_width = add(p.duct_half_width, Effect::DuctBias);
        p.free_length = add(p.free_length, Effect::FreeLengthBias);
        p
    }

    /// The pressure that acts in the cavities (bar) for a gauge pressure `gauge` (bar):
    /// `max(0, (1 − f)·P − p₀)`; the gauge pressure itself when both are neutral.
    pub fn effective_pressure_bar(&self, gauge: f64) -> f64 {
        let f = self.get(Effect::PressureLoss);
        let p0 = self.get(Effect::PressureOffset);
        if f == 0.0 && p0 == 0.0 {
            return gauge;
        }
        ((1.0 - f) * gauge - p0).max(0.0)
    }

    /// The self-weight's scale.
    pub fn gravity_scale(&self) -> f64 {
        self.get(Effect::Density)
    }

    /// Extra distance of the plate below the nominal 5 mm (mm).
    pub fn plate_offset_mm(&self) -> f64 {
        self.get(Effect::PlateOffset)
    }

    /// Compliance of the plate's support (mm/N): the plate moves `c·F` away from the tip
    /// under the blocked force `F` (the whole actuator's, N).
    pub fn plate_compliance_mm_per_n(&self) -> f64 {
        self.get(Effect::PlateCompliance)
    }

    /// The material as printed: `material` with the anisotropy's fibre term along the length
    /// (`k = a·μ0`); `material` itself (cloned) when the anisotropy is neutral.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `fibre` when `material` already has a fibre term
    /// (the effect would replace it silently), or when `k` is outside the fibre's admissible
    /// range for this law.
    pub fn printed_material(&self, material: &Material) -> Result<Material, MaterialError> {
        let a = self.get(Effect::Anisotropy);
        if a == 0.0 {
            return Ok(material.clone());
        }
        if let Some(f) = &material.fibre {
            return Err(MaterialError::Inadmissible {
                field: "fibre".into(),
                value: f.modulus(),
                expected: "no fibre term in a material the anisotropy effect applies to \
                           (the effect adds its own along the length)"
                    .into(),
            });
        }
        let fibre = Fibre::new(Fibre::ALONG_LENGTH, a * material.mu0())?;
        material.clone().with_fibre(fibre)
    }

    /// The load cell's scale.
    pub fn force_scale(&self) -> f64 {
        self.get(Effect::ForceScale)
    }

    /// Spring stiffness per unit area of the clamped face in x, y, z (MPa/mm), `None` where the
    /// face stays rigidly held: tangential (x, y) from `clamp_shear_compliance`, normal (z)
    /// from `clamp_compliance`, each `1/c`.
    pub fn clamp_springs(&self) -> [Option<f64>; 3] {
        let k = |c: f64| (c > 0.0).then(|| 1.0 / c);
        let (n, t) = (
            self.get(Effect::ClampCompliance),
            self.get(Effect::ClampShearCompliance),
        );
        [k(t), k(t), k(n)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_library_lists_every_effect_once_with_its_neutral_value_inside_the_range() {
        let mut names: Vec<_> = EFFECTS.iter().map(|i| i.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), EFFECTS.len());
        for (k, i) in EFFECTS.iter().enumerate() {
            assert_eq!(i.effect as usize, k, "{} out of order", i.name);
            assert_eq!(i.effect.info().name, i.name);
            assert_eq!(Effect::from_name(i.name), Ok(i.effect));
            assert!(
                i.range.0 <= i.neutral && i.neutral <= i.range.1,
                "{}",
                i.name
            );
            assert!(i.range.0 < i.range.1);
            // the enum's order is the table's
            assert_eq!(Effect::all().nth(k), Some(i.effect));
        }
    }

    #[test]
    fn neutral_effects_leave_the_design_and_the_pressure_unchanged() {
        let nominal = DesignParams::new(9, 1.6);
        let e = Effects::neutral()
            .with(Effect::WallBias, 0.0)
            .unwrap()
            .with(Effect::Density, 1.0)
            .unwrap();
        assert!(e.is_neutral());
        assert_eq!(e.printed_design(&nominal), nominal);
        for p in [0.0, 0.1, 1.7, 3.5] {
            assert_eq!(e.effective_pressure_bar(p).to_bits(), p.to_bits());
        }
        assert_eq!(e.clamp_springs(), [None, None, None]);
        // a neutral set writes nothing
        assert_eq!(serde_json::to_string(&Effects::neutral()).unwrap(), "{}");
    }

    #[test]
    fn biases_reach_the_printed_design() {
        let nominal = DesignParams::new(11, 2.0);
        let e = Effects::parse(["wall_bias=0.1", "wall_bias_skin=-0.3", "gap_bias=0.2"]).unwrap();
        let p = e.printed_design(&nominal);
        assert_eq!(p.wall_thickness, 2.0);
        assert!((p.bellow_wall_thickness.unwrap() - 2.1).abs() < 1e-12);
        assert!((p.skin_thickness.unwrap() - 1.8).abs() < 1e-12);
        assert!((p.gap - 1.2).abs() < 1e-12);
        assert!(p.validate().is_ok());
        let e = Effects::parse(["pressure_loss=0.1", "pressure_offset=0.05"]).unwrap();
        assert!((e.effective_pressure_bar(2.0) - 1.75).abs() < 1e-12);
        assert_eq!(e.effective_pressure_bar(0.0), 0.0);
        let e = Effects::parse(["clamp_compliance=0.2"]).unwrap();
        assert_eq!(e.clamp_springs(), [None, None, Some(5.0)]);
    }

    #[test]
    fn anisotropy_adds_a_fibre_along_the_length_and_refuses_to_replace_one() {
        let m = Material::from_spec("ogden_002", crate::fe::material::DEFAULT_BULK_RATIO).unwrap();
        assert_eq!(Effects::neutral().printed_material(&m).unwrap(), m);
        let e = Effects::parse(["anisotropy=0.5"]).unwrap();
        let printed = e.printed_material(&m).unwrap();
        let fibre = printed.fibre.as_ref().unwrap();
        assert!((fibre.modulus() - 0.5 * m.mu0()).abs() < 1e-12);
        assert_eq!(fibre.params().direction, Fibre::ALONG_LENGTH);
        let err = e.printed_material(&printed).unwrap_err().to_string();
        assert!(err.contains("fibre") && err.contains("anisotropy"), "{err}");
    }

    /// Fuzz-style: every malformed assignment is an error naming the effect and its range.
    #[test]
    fn bad_assignments_are_errors_naming_the_effect_and_its_range() {
        let cases: &[(&[&str], &str)] = &[
            (
                &["wal_bias=0.1"],
                "unknown effect \"wal_bias\": expected one of wall_bias",
            ),
            (&["wall_bias"], "expected NAME=VALUE"),
            (&["wall_bias=abc"], "expected NAME=VALUE"),
            (&["=0.1"], "unknown effect \"\""),
            (
                &["wall_bias=NaN"],
                "effect wall_bias = NaN mm: expected a value in [-0.4, 0.4] mm",
            ),
            (&["wall_bias=inf"], "effect wall_bias = inf mm"),
            (&["wall_bias=0.5"], "expected a value in [-0.4, 0.4] mm"),
            (
                &["density=0"],
                "effect density = 0 1: expected a value in [0.5, 1.5]",
            ),
            (&["clamp_compliance=-0.1"], "clamp_compliance = -0.1 mm/MPa"),
            (
                &["pressure_loss=0.1", "pressure_loss=0.2"],
                "given twice (0.1 and 0.2)",
            ),
        ];
        for (items, want) in cases {
            let e = Effects::parse(items.iter().copied())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{items:?}: {e}");
        }
        // random strings never panic
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let alphabet: Vec<char> = "wall_bias=0.1-e+NaN,;= xyz".chars().collect();
        for _ in 0..2000 {
            let len = (state % 24) as usize;
            let s: String = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    alphabet[(state % alphabet.len() as u64) as usize]
                })
                .collect();
            let _ = Effects::parse([s.as_str()]);
        }
    }

    #[test]
    fn effects_round_trip_through_json_and_refuse_bad_files() {
        let e = Effects::parse(["wall_bias=-0.1", "plate_offset=1"]).unwrap();
        let s = serde_json::to_string(&e).unwrap();
        assert_eq!(s, r#"{"plate_offset":1.0,"wall_bias":-0.1}"#);
        assert_eq!(serde_json::from_str::<Effects>(&s).unwrap(), e);
        let bad = serde_json::from_str::<Effects>(r#"{"wall_bias":3}"#).unwrap_err();
        assert!(bad.to_string().contains("[-0.4, 0.4]"), "{bad}");
    }
}
