//! The load parameter of a state: [`LoadLevel`], a named vector of load factors
//! ([`LoadFactor`]: pressure, gravity, dead traction, prescribed displacement, and any factor
//! registered with its load term) along which the solver continues.
//!
//! A level is serialised as a map from factor name to value. The built-in factors are always
//! written, so a level without registered factors reads as it always has:
//! `{"pressure":0.1,"gravity":1.0,"traction":0.0,"prescribed":0.0}`; a registered factor is
//! written where it is not zero. Missing factors read as 0, unknown names are an error.

pub mod factor;

use std::fmt;
use std::ops::{Index, IndexMut};

use serde::de::{self, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

pub use factor::{FactorInfo, LoadFactor, LoadFactorError, LOAD_FACTORS, MAX_LOAD_FACTORS};

/// Load factors of one state, one value per [`LoadFactor`] (0 for a factor not applied).
#[derive(Clone, Copy, Default, PartialEq)]
pub struct LoadLevel {
    values: [f64; MAX_LOAD_FACTORS],
}

impl LoadLevel {
    /// No load.
    pub const ZERO: Self = Self {
        values: [0.0; MAX_LOAD_FACTORS],
    };

    /// The level with `factor` set to `value`.
    #[must_use]
    pub fn with(mut self, factor: LoadFactor, value: f64) -> Self {
        self.values[factor.index()] = value;
        self
    }

    /// Value of `factor`.
    pub fn get(&self, factor: LoadFactor) -> f64 {
        self.values[factor.index()]
    }

    /// Cavity pressure (MPa).
    pub fn pressure(&self) -> f64 {
        self.get(LoadFactor::PRESSURE)
    }

    /// Gravity factor (1 = full self-weight).
    pub fn gravity(&self) -> f64 {
        self.get(LoadFactor::GRAVITY)
    }

    /// Dead-traction factor.
    pub fn traction(&self) -> f64 {
        self.get(LoadFactor::TRACTION)
    }

    /// Prescribed-displacement factor.
    pub fn prescribed(&self) -> f64 {
        self.get(LoadFactor::PRESCRIBED)
    }

    /// Linear interpolation between two levels, factor by factor.
    pub fn lerp(&self, other: &Self, s: f64) -> Self {
        let mut out = *self;
        for (o, (a, b)) in out
            .values
            .iter_mut()
            .zip(self.values.iter().zip(&other.values))
        {
            *o = a + s * (b - a);
        }
        out
    }

    /// The factors whose values differ between `self` and `other`, in slot order.
    pub fn changing<'a>(&'a self, other: &'a Self) -> impl Iterator<Item = LoadFactor> + 'a {
        (0..MAX_LOAD_FACTORS)
            .filter(|&i| self.values[i] != other.values[i])
            .filter_map(LoadFactor::from_index)
    }

    /// Size of the step from `self` to `other` that the solver's increment bounds apply to:
    /// `Σ |Δλ|` over the factors with [`FactorInfo::bounds_increment`] (in their units; the
    /// pressure change in MPa for the built-in ones).
    pub fn bounded_increment(&self, other: &Self) -> f64 {
        self.changing(other)
            .filter(|f| f.info().bounds_increment)
            .fold(0.0, |d, f| d + (other.get(f) - self.get(f)).abs())
    }

    /// The factors to write: the built-in ones, then the registered ones that are not zero.
    fn written(&self) -> impl Iterator<Item = (LoadFactor, f64)> + '_ {
        LoadFactor::all()
            .map(|f| (f, self.get(f)))
            .filter(|&(f, v)| f.is_builtin() || v != 0.0)
    }
}

impl Index<LoadFactor> for LoadLevel {
    type Output = f64;
    fn index(&self, factor: LoadFactor) -> &f64 {
        &self.values[factor.index()]
    }
}

impl IndexMut<LoadFactor> for LoadLevel {
    fn index_mut(&mut self, factor: LoadFactor) -> &mut f64 {
        &mut self.values[factor.index()]
    }
}

/// `LoadLevel { pressure: 0.1, gravity: 1.0, traction: 0.0, prescribed: 0.0 }` (the built-in
/// factors, then the registered ones that are not zero).
impl fmt::Debug for LoadLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = f.debug_struct("LoadLevel");
        for (factor, v) in self.written() {
            s.field(factor.name(), &v);
        }
        s.finish()
    }
}

/// The factors that are not zero, `name=value` (4 decimals unless a precision is given), or
/// `no load`.
impl fmt::Display for LoadLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let digits = f.precision().unwrap_or(4);
        let mut first = true;
        for factor in LoadFactor::all().filter(|&g| self.get(g) != 0.0) {
            let sep = if first { "" } else { " " };
            write!(f, "{sep}{}={:.*}", factor.name(), digits, self.get(factor))?;
            first = false;
        }
        if first {
            f.write_str("no load")?;
        }
        Ok(())
    }
}

impl Serialize for LoadLevel {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let n = self.written().count();
        let mut map = serializer.serialize_map(Some(n))?;
        for (factor, v) in self.written() {
            map.serialize_entry(factor.name(), &v)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for LoadLevel {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(LevelVisitor)
    }
}

struct LevelVisitor;

impl<'de> Visitor<'de> for LevelVisitor {
    type Value = LoadLevel;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a map from load factor name to value")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<LoadLevel, A::Error> {
        let mut level = LoadLevel::ZERO;
        let mut seen = [false; MAX_LOAD_FACTORS];
        while let Some(name) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            let Some(factor) = LoadFactor::by_name(&name) else {
                let known: Vec<&str> = LoadFactor::all().map(LoadFactor::name).collect();
                return Err(de::Error::custom(format_args!(
                    "unknown load factor `{name}`, expected one of {known:?}"
                )));
            };
            if std::mem::replace(&mut seen[factor.index()], true) {
                return Err(de::Error::custom(format_args!(
                    "load factor `{name}` given twice"
                )));
            }
            level[factor] = map.next_value()?;
        }
        Ok(level)
    }
}
