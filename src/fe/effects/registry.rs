//! The library's effects in one list ([`BUILTIN_EFFECTS`]), and registries that extend it
//! with a program's own ([`EffectRegistry`]): the names the command line, the files and the
//! sensitivities know.

use std::cell::RefCell;
use std::collections::BTreeMap;

use serde::de::{DeserializeSeed, Error as _};
use serde::{Deserialize, Deserializer};

use super::effect::{Effect, EffectError};
use super::set::Effects;

/// The library, in the order listed by `surrogate effects` and applied to a case. A new
/// effect of the library is one file implementing [`CaseEffect`](super::CaseEffect) and one
/// line here (its position is its rank in the handle, tested).
pub const BUILTIN_EFFECTS: &[Effect] = &[
    Effect::WallBias,
    Effect::WallBiasBellows,
    Effect::WallBiasSkin,
    Effect::WallBiasSide,
    Effect::GapBias,
    Effect::BaseBias,
    Effect::DuctBias,
    Effect::FreeLengthBias,
    Effect::ClampCompliance,
    Effect::ClampShearCompliance,
    Effect::PressureLoss,
    Effect::PressureOffset,
    Effect::Density,
    Effect::Anisotropy,
    Effect::PlateOffset,
    Effect::PlateCompliance,
    Effect::ForceScale,
];

/// The effect called `name` among `effects`.
fn find(effects: &[Effect], name: &str) -> Result<Effect, EffectError> {
    effects
        .iter()
        .copied()
        .find(|e| e.name() == name)
        .ok_or_else(|| EffectError::Unknown {
            name: name.to_string(),
            known: effects
                .iter()
                .map(|e| e.name())
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// Parses `NAME=VALUE` assignments, the names among `effects`.
fn parse<'a>(
    effects: &[Effect],
    items: impl IntoIterator<Item = &'a str>,
) -> Result<Effects, EffectError> {
    let mut out = Effects::default();
    for text in items {
        let (name, value) = text.split_once('=').ok_or_else(|| EffectError::Syntax {
            text: text.to_string(),
        })?;
        let e = find(effects, name.trim())?;
        let v: f64 = value.trim().parse().map_err(|_| EffectError::Syntax {
            text: text.to_string(),
        })?;
        if let Some((_, first)) = out.iter().find(|(k, _)| *k == e) {
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

/// The effects of a `{name: value}` map (a file's), the names among `effects`.
fn from_map(effects: &[Effect], values: BTreeMap<String, f64>) -> Result<Effects, EffectError> {
    let mut out = Effects::default();
    for (name, v) in values {
        out.set(find(effects, &name)?, v)?;
    }
    Ok(out)
}

impl Effect {
    /// The library's effect called `name`.
    ///
    /// # Errors
    /// [`EffectError::Unknown`] listing the known names.
    pub fn from_name(name: &str) -> Result<Self, EffectError> {
        find(BUILTIN_EFFECTS, name)
    }

    /// The effect called `name` as a file names it: among the registry of the current
    /// [`EffectRegistry::reading`] scope on this thread, else the library's.
    ///
    /// # Errors
    /// [`EffectError::Unknown`] listing the names known there.
    pub fn read_name(name: &str) -> Result<Self, EffectError> {
        with_reading(|effects| find(effects, name))
    }

    /// Every effect of the library.
    pub fn all() -> impl Iterator<Item = Effect> {
        BUILTIN_EFFECTS.iter().copied()
    }
}

thread_local! {
    /// The registry of an [`EffectRegistry::reading`] scope on this thread, if any.
    static READING: RefCell<Option<Vec<Effect>>> = const { RefCell::new(None) };
}

/// Calls `f` with the effects that names read from files resolve to on this thread: those of
/// the innermost [`EffectRegistry::reading`] scope, else the library's.
fn with_reading<T>(f: impl FnOnce(&[Effect]) -> T) -> T {
    READING.with(|r| match r.borrow().as_deref() {
        Some(effects) => f(effects),
        None => f(BUILTIN_EFFECTS),
    })
}

/// Restores the scope that was in force when a [`EffectRegistry::reading`] scope began, also
/// when its closure panics.
struct ReadingScope {
    outer: Option<Vec<Effect>>,
}

impl Drop for ReadingScope {
    fn drop(&mut self) {
        let outer = self.outer.take();
        READING.with(|r| *r.borrow_mut() = outer);
    }
}

/// An effect read by name: among the registry of the current [`EffectRegistry::reading`]
/// scope, else the library's.
impl<'de> Deserialize<'de> for Effect {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Effect::read_name(&name).map_err(serde::de::Error::custom)
    }
}

impl Effects {
    /// Parses `NAME=VALUE` assignments of the library's effects (the command line's repeated
    /// `--effect`).
    ///
    /// # Errors
    /// [`EffectError::Syntax`], [`EffectError::Unknown`], [`EffectError::OutOfRange`] or
    /// [`EffectError::Duplicate`] for the first bad assignment.
    pub fn parse<'a>(items: impl IntoIterator<Item = &'a str>) -> Result<Self, EffectError> {
        parse(BUILTIN_EFFECTS, items)
    }
}

/// The effects a program knows by name: the library's and its own, in that order.
///
/// ```
/// use surrogate::fe::effects::{Effect, EffectRegistry};
/// let registry = EffectRegistry::builtin();
/// assert_eq!(registry.find("wall_bias"), Ok(Effect::WallBias));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct EffectRegistry {
    effects: Vec<Effect>,
}

impl Default for EffectRegistry {
    fn default() -> Self {
        Self::builtin()
    }
}

impl EffectRegistry {
    /// The library ([`BUILTIN_EFFECTS`]).
    pub fn builtin() -> Self {
        Self {
            effects: BUILTIN_EFFECTS.to_vec(),
        }
    }

    /// This registry with `effect` added after the others.
    ///
    /// # Errors
    /// [`EffectError::Invalid`] for a name already registered, or a description
    /// [`Effect::check`] refuses.
    pub fn with(mut self, effect: Effect) -> Result<Self, EffectError> {
        effect.check()?;
        if self.effects.iter().any(|e| e.name() == effect.name()) {
            return Err(EffectError::Invalid {
                name: effect.name().to_string(),
                expected: "a name not already registered",
            });
        }
        self.effects.push(effect);
        Ok(self)
    }

    /// The registered effect called `name`.
    ///
    /// # Errors
    /// [`EffectError::Unknown`] listing the registered names.
    pub fn find(&self, name: &str) -> Result<Effect, EffectError> {
        find(&self.effects, name)
    }

    /// Every registered effect, the library's first.
    pub fn iter(&self) -> impl Iterator<Item = Effect> + '_ {
        self.effects.iter().copied()
    }

    /// Parses `NAME=VALUE` assignments of the registered effects ([`Effects::parse`]).
    ///
    /// # Errors
    /// See [`Effects::parse`].
    pub fn parse<'a>(
        &self,
        items: impl IntoIterator<Item = &'a str>,
    ) -> Result<Effects, EffectError> {
        parse(&self.effects, items)
    }

    /// The effects of a `{name: value}` map read from a file, the names among the registered
    /// ones (what [`Effects`] read from JSON are, with the library's names only).
    ///
    /// # Errors
    /// [`EffectError::Unknown`] or [`EffectError::OutOfRange`] for the first bad entry.
    pub fn effects_from_map(&self, values: BTreeMap<String, f64>) -> Result<Effects, EffectError> {
        from_map(&self.effects, values)
    }

    /// Runs `read` with this registry as the one that effect names in files resolve to, on
    /// this thread: a plan, a case file, a provenance record or any other file that holds
    /// [`Effects`] or an [`Effect`] reads a program's own effects inside the scope (outside
    /// it, only the library's). Scopes nest; the outer one is back when `read` returns or
    /// panics. Reads on other threads (a `rayon` pool) are not in the scope: start one there.
    ///
    /// ```
    /// use surrogate::fe::effects::{Effect, EffectRegistry, Effects};
    /// let registry = EffectRegistry::builtin();
    /// let e: Effects = registry
    ///     .reading(|| serde_json::from_str(r#"{"gap_bias":-0.2}"#))
    ///     .unwrap();
    /// assert_eq!(e.get(Effect::GapBias), -0.2);
    /// ```
    pub fn reading<T>(&self, read: impl FnOnce() -> T) -> T {
        let outer = READING.with(|r| r.borrow_mut().replace(self.effects.clone()));
        let _restore = ReadingScope { outer };
        read()
    }
}

/// Reads [`Effects`] (a `{name: value}` object) with the registered names:
/// `registry.deserialize(&mut serde_json::Deserializer::from_str(text))`.
impl<'de> DeserializeSeed<'de> for &EffectRegistry {
    type Value = Effects;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Effects, D::Error> {
        let values = BTreeMap::<String, f64>::deserialize(d)?;
        self.effects_from_map(values).map_err(D::Error::custom)
    }
}

/// The effects of a `{name: value}` map (how [`Effects`] are read from files): the names among
/// the registry of the current [`EffectRegistry::reading`] scope, else the library's.
impl TryFrom<BTreeMap<String, f64>> for Effects {
    type Error = EffectError;
    fn try_from(values: BTreeMap<String, f64>) -> Result<Self, EffectError> {
        with_reading(|effects| from_map(effects, values))
    }
}
