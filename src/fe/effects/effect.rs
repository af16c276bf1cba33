//! What an effect is: the trait [`CaseEffect`] (its description, where it acts, how it is
//! applied and how it is differentiated) and the handle [`Effect`] the rest of the crate passes
//! around.

use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};

use serde::{Serialize, Serializer};
use thiserror::Error;

use crate::fe::geometry::DesignParams;
use crate::fe::material::{Material, MaterialError};

/// One effect: a named parameter of a case with a unit, a neutral value and a range, that acts
/// on one part of the case ([`Target`]) and is differentiated one way ([`Differentiation`]).
///
/// Required are the description ([`CaseEffect::info`]) and where it acts
/// ([`CaseEffect::target`]). How it is applied follows from the target: a geometry effect
/// changes the printed design ([`CaseEffect::print_design`]), a pressure effect the pressure
/// in the cavities ([`CaseEffect::pressure_bar`]), a material effect the material
/// ([`CaseEffect::print_material`]); for the other targets the value itself is the quantity
/// the target names (a factor on the self-weight, a compliance, a plate's offset, a scale of
/// the reported force). The hooks of other targets are never called. A hook is only called
/// with a value other than the neutral one: at its neutral value an effect changes nothing.
///
/// An implementation is a unit struct in a file of its own, or a value of a shape several
/// effects share (the wall biases'); [`Effect::new`] makes it a handle, and
/// [`BUILTIN_EFFECTS`](super::BUILTIN_EFFECTS) lists the library's. A program adds its own to
/// an [`EffectRegistry`](super::EffectRegistry) (for names on its command line or in its
/// files) or sets its handle straight into [`Effects`](super::Effects).
pub trait CaseEffect: Send + Sync {
    /// Name, meaning, unit, neutral value, range, kind and source.
    fn info(&self) -> &EffectInfo;

    /// The part of the case it acts on.
    fn target(&self) -> Target;

    /// How its derivatives are computed; by default the method of its target
    /// ([`Target::differentiation`]).
    fn differentiation(&self) -> Differentiation {
        self.target().differentiation()
    }

    /// [`Target::Geometry`]: applies `value` to `design` (the nominal design with the
    /// geometry effects before this one in the registry's order already applied).
    fn print_design(&self, value: f64, design: &mut DesignParams) {
        let _ = (value, design);
    }

    /// [`Target::Pressure`]: the pressure in the cavities (bar) from `pressure_bar` (the gauge
    /// pressure with the pressure effects before this one already applied).
    fn pressure_bar(&self, value: f64, pressure_bar: f64) -> f64 {
        let _ = value;
        pressure_bar
    }

    /// [`Target::Material`]: the material as printed from `material`.
    ///
    /// # Errors
    /// [`MaterialError`] when `material` cannot take this effect at `value`.
    fn print_material(&self, value: f64, material: &Material) -> Result<Material, MaterialError> {
        let _ = value;
        Ok(material.clone())
    }
}

/// The part of a case an effect acts on, and what its value means there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Target {
    /// The printed design (geometry): [`CaseEffect::print_design`].
    Geometry,
    /// The pressure in the cavities (loads): [`CaseEffect::pressure_bar`].
    Pressure,
    /// The self-weight (loads): the value is a factor on it (neutral 1); the factors of
    /// several such effects multiply.
    Gravity,
    /// The material: [`CaseEffect::print_material`].
    Material,
    /// The clamp (rig): the value is a compliance (mm/MPa, neutral 0) of springs holding the
    /// clamped face in the directions `x, y, z` marked; compliances in one direction add.
    Clamp([bool; 3]),
    /// The force plate's height (rig): the value moves the plate this much further below the
    /// sagged tip (mm, neutral 0); offsets add.
    PlateOffset,
    /// The force plate's support (rig): the value is its compliance (mm/N, neutral 0);
    /// compliances add.
    PlateCompliance,
    /// The reported blocked force (measurement): the value scales it (neutral 1); scales
    /// multiply.
    ForceReading,
}

impl Target {
    /// The rig it acts on.
    pub fn rig(self) -> Acts {
        match self {
            Target::PlateOffset | Target::PlateCompliance | Target::ForceReading => Acts::Force,
            _ => Acts::Both,
        }
    }

    /// The way an effect on this target is differentiated unless it says otherwise.
    pub fn differentiation(self) -> Differentiation {
        match self {
            Target::Geometry => Differentiation::MovedMesh,
            Target::Pressure | Target::Gravity => Differentiation::LoadLevel,
            Target::Material => Differentiation::Material,
            Target::Clamp(_) => Differentiation::ClampSprings,
            Target::PlateOffset | Target::PlateCompliance => Differentiation::Plate,
            Target::ForceReading => Differentiation::Reading,
        }
    }
}

/// How the outputs' derivatives with respect to an effect are computed
/// ([`crate::fe::sensitivity`]): `∂R/∂θ` from residual differences at fixed displacements on
/// the model perturbed as named, or analytically.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Differentiation {
    /// Residuals on the mesh moved onto the perturbed design (a geometry effect).
    MovedMesh,
    /// Residuals at the perturbed load level: its pressure ([`Target::Pressure`]) or its
    /// gravity factor ([`Target::Gravity`]).
    LoadLevel,
    /// Residuals with the perturbed material.
    Material,
    /// Residuals on a model of its own with the perturbed clamp springs; where the clamp is
    /// rigid (compliance 0) its limit: the clamped face moved by `−M⁻¹R_s` per unit.
    ClampSprings,
    /// The plate's height moved exactly (force rig only).
    Plate,
    /// Analytically: the reported force only, `dF/ds = F/s` (force rig only).
    Reading,
    /// Not differentiated: asking for its derivative is an error.
    Unsupported,
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
}

/// An effect: a handle on its [`CaseEffect`], compared, ordered and hashed by its place in
/// the library and its name, written as its name.
///
/// The library's effects are associated constants (`Effect::WallBias`, …) named as the
/// variants of the enumeration they were; a program's own is `Effect::new(&MINE)`.
#[derive(Clone, Copy)]
pub struct Effect {
    def: &'static dyn CaseEffect,
    /// Position in [`BUILTIN_EFFECTS`](super::BUILTIN_EFFECTS); `u32::MAX` for an effect
    /// outside the library (ordered after the library's, by name).
    rank: u32,
}

impl Effect {
    /// The handle of an effect outside the library (ordered after the library's, by name).
    pub const fn new(def: &'static dyn CaseEffect) -> Self {
        Self {
            def,
            rank: u32::MAX,
        }
    }

    /// The handle of the library's effect at position `rank` of
    /// [`BUILTIN_EFFECTS`](super::BUILTIN_EFFECTS).
    pub(super) const fn builtin(rank: u32, def: &'static dyn CaseEffect) -> Self {
        Self { def, rank }
    }

    /// Its position in the library (`None` outside it).
    pub fn rank(self) -> Option<usize> {
        (self.rank != u32::MAX).then_some(self.rank as usize)
    }

    /// Its description.
    pub fn info(self) -> &'static EffectInfo {
        self.def.info()
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The part of the case it acts on.
    pub fn target(self) -> Target {
        self.def.target()
    }

    /// How it is differentiated.
    pub fn differentiation(self) -> Differentiation {
        self.def.differentiation()
    }

    /// The rig it acts on.
    pub fn acts_on(self) -> Acts {
        self.target().rig()
    }

    /// The implementation.
    pub fn def(self) -> &'static dyn CaseEffect {
        self.def
    }

    /// Checks the description: a name, a range `lo < hi` with the neutral value inside.
    ///
    /// # Errors
    /// [`EffectError::Invalid`] saying what is wrong.
    pub fn check(self) -> Result<(), EffectError> {
        let i = self.info();
        let why = if i.name.is_empty() || i.name.contains(['=', ',']) || i.name.trim() != i.name {
            "a name without '=', ',' or surrounding spaces"
        } else if i.range.0.partial_cmp(&i.range.1) != Some(Ordering::Less) {
            "a range lo < hi"
        } else if !(i.range.0..=i.range.1).contains(&i.neutral) {
            "the neutral value inside the range"
        } else {
            return Ok(());
        };
        Err(EffectError::Invalid {
            name: i.name.to_string(),
            expected: why,
        })
    }
}

impl PartialEq for Effect {
    fn eq(&self, other: &Self) -> bool {
        self.rank == other.rank && self.name() == other.name()
    }
}

impl Eq for Effect {}

impl PartialOrd for Effect {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Effect {
    fn cmp(&self, other: &Self) -> Ordering {
        (self.rank, self.name()).cmp(&(other.rank, other.name()))
    }
}

impl Hash for Effect {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.rank.hash(state);
        self.name().hash(state);
    }
}

impl fmt::Debug for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Effect({})", self.name())
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Effect {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
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
    /// An effect whose description cannot be registered.
    #[error("effect {name:?} cannot be registered: expected {expected}")]
    Invalid {
        /// Its name.
        name: String,
        /// What a registered effect needs.
        expected: &'static str,
    },
}
