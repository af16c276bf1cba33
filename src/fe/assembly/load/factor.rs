//! The load factors: [`LoadFactor`], an id into a [`LoadLevel`](super::LoadLevel)'s vector,
//! and the registry of their names ([`LOAD_FACTORS`] for the built-in ones, [`LoadFactor::register`]
//! for one that a case or a test adds with its own load term).
//!
//! A new load term with its own factor in the crate is one file implementing the term (which
//! names its factor with `const MINE: LoadFactor = LoadFactor::builtin("mine");` and declares
//! it through [`ElementTerm::load_factor`](crate::fe::assembly::terms::term::ElementTerm::load_factor))
//! plus one line here in [`LOAD_FACTORS`] and one in
//! [`ELEMENT_TERMS`](crate::fe::assembly::ELEMENT_TERMS). Outside the crate the factor is
//! registered where the model is built ([`LoadFactor::register`]) and the term added with
//! [`FeModel::add_element_term`](crate::fe::assembly::FeModel::add_element_term).

use std::sync::{Mutex, MutexGuard};

/// Largest number of load factors (built-in and registered) a [`LoadLevel`](super::LoadLevel) holds.
pub const MAX_LOAD_FACTORS: usize = 8;

/// What the solver and the serialised form need to know about a load factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FactorInfo {
    /// Name: the key of the factor in a serialised level, and in traces.
    pub name: &'static str,
    /// What the factor scales, with its unit.
    pub description: &'static str,
    /// Whether the solver's increment bounds
    /// ([`SolverSettings::initial_pressure_increment`](crate::fe::solver::SolverSettings::initial_pressure_increment),
    /// [`max_pressure_increment`](crate::fe::solver::SolverSettings::max_pressure_increment))
    /// apply to the factor's change over a step (in its unit); the other factors are ramped
    /// by the fraction of the step alone.
    pub bounds_increment: bool,
}

/// The built-in load factors, in the order of their slots in a level.
pub const LOAD_FACTORS: &[FactorInfo] = &[
    FactorInfo {
        name: "pressure",
        description: "cavity pressure (MPa)",
        bounds_increment: true,
    },
    FactorInfo {
        name: "gravity",
        description: "gravity factor (1 = full self-weight)",
        bounds_increment: false,
    },
    FactorInfo {
        name: "traction",
        description: "dead-traction factor",
        bounds_increment: false,
    },
    FactorInfo {
        name: "prescribed",
        description: "prescribed-displacement factor",
        bounds_increment: false,
    },
];

const _: () = assert!(LOAD_FACTORS.len() <= MAX_LOAD_FACTORS);

/// The factors registered at run time, after the built-in ones.
static REGISTERED: Mutex<Vec<FactorInfo>> = Mutex::new(Vec::new());

fn registered() -> MutexGuard<'static, Vec<FactorInfo>> {
    // the list is only ever pushed to: a panic elsewhere cannot leave it inconsistent
    REGISTERED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Why a load factor cannot be registered.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LoadFactorError {
    /// Every slot of a level is taken.
    #[error("load factor `{name}` cannot be registered: all {capacity} slots are taken")]
    Full {
        /// The factor's name.
        name: &'static str,
        /// [`MAX_LOAD_FACTORS`].
        capacity: usize,
    },
    /// A factor of that name exists with other properties.
    #[error("load factor `{name}` is already registered with other properties")]
    Conflict {
        /// The factor's name.
        name: &'static str,
    },
    /// The name is empty.
    #[error("a load factor needs a non-empty name")]
    EmptyName,
}

/// A load factor: its slot in a [`LoadLevel`](super::LoadLevel).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LoadFactor(u8);

const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

impl LoadFactor {
    /// Cavity pressure (MPa), read by the follower pressure.
    pub const PRESSURE: Self = Self::builtin("pressure");
    /// Gravity factor, scaling the model's body force.
    pub const GRAVITY: Self = Self::builtin("gravity");
    /// Dead-traction factor, scaling the model's dead tractions.
    pub const TRACTION: Self = Self::builtin("traction");
    /// Prescribed-displacement factor, scaling the constraints' values.
    pub const PRESCRIBED: Self = Self::builtin("prescribed");

    /// The built-in factor named `name` in [`LOAD_FACTORS`], for a constant:
    /// `const MINE: LoadFactor = LoadFactor::builtin("mine");` does not compile unless
    /// `mine` is listed there.
    ///
    /// # Panics
    /// If `name` is not in [`LOAD_FACTORS`] (at compile time in a constant); at run time use
    /// [`Self::by_name`].
    pub const fn builtin(name: &str) -> Self {
        let mut i = 0;
        while i < LOAD_FACTORS.len() {
            if same(LOAD_FACTORS[i].name, name) {
                return Self(i as u8);
            }
            i += 1;
        }
        panic!("not a load factor of LOAD_FACTORS")
    }

    /// Registers a factor (after the built-in ones) and returns its id; registering the same
    /// factor again returns the same id.
    ///
    /// # Errors
    /// [`LoadFactorError`] if the name is empty, taken by a factor with other properties, or
    /// all [`MAX_LOAD_FACTORS`] slots are taken.
    pub fn register(info: FactorInfo) -> Result<Self, LoadFactorError> {
        if info.name.is_empty() {
            return Err(LoadFactorError::EmptyName);
        }
        let mut list = registered();
        let all = LOAD_FACTORS.iter().chain(list.iter());
        if let Some((i, old)) = all.enumerate().find(|(_, f)| f.name == info.name) {
            return if *old == info {
                Ok(Self(i as u8))
            } else {
                Err(LoadFactorError::Conflict { name: info.name })
            };
        }
        let index = LOAD_FACTORS.len() + list.len();
        if index >= MAX_LOAD_FACTORS {
            return Err(LoadFactorError::Full {
                name: info.name,
                capacity: MAX_LOAD_FACTORS,
            });
        }
        list.push(info);
        Ok(Self(index as u8))
    }

    /// The factor named `name`, built-in or registered.
    pub fn by_name(name: &str) -> Option<Self> {
        if let Some(i) = LOAD_FACTORS.iter().position(|f| f.name == name) {
            return Some(Self(i as u8));
        }
        let list = registered();
        let i = list.iter().position(|f| f.name == name)?;
        Some(Self((LOAD_FACTORS.len() + i) as u8))
    }

    /// Every factor, built-in then registered, in slot order.
    pub fn all() -> impl Iterator<Item = Self> {
        let n = LOAD_FACTORS.len() + registered().len();
        (0..n).map(|i| Self(i as u8))
    }

    /// Its slot in a level's vector.
    pub const fn index(self) -> usize {
        self.0 as usize
    }

    /// Whether it is one of [`LOAD_FACTORS`].
    pub const fn is_builtin(self) -> bool {
        self.index() < LOAD_FACTORS.len()
    }

    /// Its name and properties.
    pub fn info(self) -> FactorInfo {
        match LOAD_FACTORS.get(self.index()) {
            Some(f) => *f,
            // an id is only made by `builtin` or `register`: a slot past the built-in ones
            // is in the registered list
            None => registered()[self.index() - LOAD_FACTORS.len()],
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The factor of slot `index`, if that slot is in use.
    // public for the tests in tests/fe/
    #[doc(hidden)]
    pub fn from_index(index: usize) -> Option<Self> {
        let in_use = index < LOAD_FACTORS.len() || index < LOAD_FACTORS.len() + registered().len();
        in_use.then_some(Self(index as u8))
    }
}
