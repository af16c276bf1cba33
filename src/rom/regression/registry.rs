//! The registry of regressors: names, type-erased fitted regressors and their model-file form.
//!
//! [`Entry::of`] turns a [`Regressor`] type into a registry line (its name, its fit in a
//! training run, its reading from a model file); a [`Registry`] is a list of them (the
//! built-ins, [`BUILTIN`], plus any added with [`Registry::with`]). A fitted regressor
//! is held as a [`DynRegressor`] (implemented for every [`Regressor`]), and a model's fitted
//! regressors as [`Regressors`], written into the model object under their names, in order.

use std::any::Any;
use std::borrow::Cow;
use std::fmt;
use std::ops::Range;

use serde::de::{MapAccess, Visitor};
use serde::ser::{Error as _, SerializeMap};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::value::RawValue;

use super::gp::Gp;
use super::poly::Poly;
use super::regressor::{Data, EmbeddedRegressor, LinearBasis, Regressor, TrainingSettings};
use crate::rom::RomError;

/// The built-in regressors, in the order training fits them and model files hold them: a new
/// regressor is one file (its `mod` line in [`super`]) and one line here.
pub const BUILTIN: &[Entry] = &[Entry::of::<Gp>(), Entry::of::<Poly>()];

/// The keys of a model object that are not regressors (the fields of
/// [`Surrogate`](crate::rom::Surrogate)): no regressor may take one as its name.
const RESERVED: &[&str] = &[
    "inputs",
    "outputs",
    "n_allowed",
    "pressures",
    "features",
    "blocks",
    "output_block",
    "output_slot",
    "std_scale",
    "validation",
    "training",
];

/// The regressor of a block, by name (`"gp"`, `"poly"`, or a registered regressor's
/// [`Regressor::NAME`]); written as the name in the model file.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct RegressorKind(Cow<'static, str>);

impl RegressorKind {
    /// The Gaussian process ([`Gp`]).
    pub const GP: RegressorKind = RegressorKind::of::<Gp>();
    /// The ridge polynomial ([`Poly`]).
    pub const POLY: RegressorKind = RegressorKind::of::<Poly>();

    /// The kind of regressor type `R`.
    pub const fn of<R: Regressor>() -> Self {
        RegressorKind(Cow::Borrowed(R::NAME))
    }

    /// A kind by name (checked against a registry where it is used).
    pub fn named(name: &str) -> Self {
        RegressorKind(Cow::Owned(name.to_string()))
    }

    /// Name.
    pub fn name(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for RegressorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// A fitted regressor behind a pointer: every [`Regressor`] is one. The methods are those of
/// [`Regressor`] (see there), plus the model-file text and the comparisons a model needs.
pub trait DynRegressor: fmt::Debug + Send + Sync {
    /// [`Regressor::NAME`].
    fn name(&self) -> &'static str;
    /// [`Regressor::n_inputs`].
    fn n_inputs(&self) -> usize;
    /// [`Regressor::n_outputs`].
    fn n_outputs(&self) -> usize;
    /// [`Regressor::scratch_len`].
    fn scratch_len(&self) -> usize;
    /// [`Regressor::predict_cols_into`].
    fn predict_cols_into(&self, x: &[f64], cols: Range<usize>, out: &mut [f64], s: &mut [f64]);
    /// [`Regressor::predict_into`].
    fn predict_into(&self, x: &[f64], out: &mut [f64], scratch: &mut [f64]);
    /// [`Regressor::jacobian_into`].
    fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]);
    /// [`Regressor::variance_into`].
    fn variance_into(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]);
    /// [`Regressor::check`].
    ///
    /// # Errors
    /// A message naming the inconsistent table.
    fn check(&self, blocks: &[Range<usize>]) -> Result<(), String>;
    /// [`Regressor::linear_basis`].
    fn linear_basis(&self) -> Option<LinearBasis<'_>>;
    /// [`Regressor::basis_into`].
    fn basis_into(&self, group: usize, x: &[f64], phi: &mut [f64]);
    /// [`Regressor::prepare`].
    fn prepare(&self);
    /// [`Regressor::embedded`].
    fn embedded(&self) -> Option<EmbeddedRegressor>;
    /// The regressor's model-file text.
    ///
    /// # Errors
    /// Serialisation failure (non-finite numbers).
    fn to_raw_json(&self) -> Result<Box<RawValue>, serde_json::Error>;
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn DynRegressor>;
    /// Whether `other` is the same type with equal tables.
    fn eq_dyn(&self, other: &dyn DynRegressor) -> bool;
    /// The concrete regressor (for [`Regressors::get`]).
    fn as_any(&self) -> &dyn Any;
    /// The concrete regressor, mutable.
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<R: Regressor> DynRegressor for R {
    fn name(&self) -> &'static str {
        R::NAME
    }
    fn n_inputs(&self) -> usize {
        Regressor::n_inputs(self)
    }
    fn n_outputs(&self) -> usize {
        Regressor::n_outputs(self)
    }
    fn scratch_len(&self) -> usize {
        Regressor::scratch_len(self)
    }
    #[inline]
    fn predict_cols_into(&self, x: &[f64], cols: Range<usize>, out: &mut [f64], s: &mut [f64]) {
        Regressor::predict_cols_into(self, x, cols, out, s)
    }
    fn predict_into(&self, x: &[f64], out: &mut [f64], scratch: &mut [f64]) {
        Regressor::predict_into(self, x, out, scratch)
    }
    fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], scratch: &mut [f64]) {
        Regressor::jacobian_into(self, x, out, jac, scratch)
    }
    fn variance_into(&self, x: &[f64], var: &mut [f64], scratch: &mut [f64]) {
        Regressor::variance_into(self, x, var, scratch)
    }
    fn check(&self, blocks: &[Range<usize>]) -> Result<(), String> {
        Regressor::check(self, blocks)
    }
    fn linear_basis(&self) -> Option<LinearBasis<'_>> {
        Regressor::linear_basis(self)
    }
    #[inline]
    fn basis_into(&self, group: usize, x: &[f64], phi: &mut [f64]) {
        Regressor::basis_into(self, group, x, phi)
    }
    fn prepare(&self) {
        Regressor::prepare(self)
    }
    fn embedded(&self) -> Option<EmbeddedRegressor> {
        Regressor::embedded(self)
    }
    fn to_raw_json(&self) -> Result<Box<RawValue>, serde_json::Error> {
        serde_json::value::to_raw_value(self)
    }
    fn clone_box(&self) -> Box<dyn DynRegressor> {
        Box::new(self.clone())
    }
    fn eq_dyn(&self, other: &dyn DynRegressor) -> bool {
        other.as_any().downcast_ref::<R>() == Some(self)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// Fits `R` with its training settings.
type FitFn = fn(&Data<'_>, &TrainingSettings<'_>) -> Result<Box<dyn DynRegressor>, RomError>;
/// Reads `R` from its model-file text.
type LoadFn = fn(&str) -> Result<Box<dyn DynRegressor>, serde_json::Error>;

fn fit_boxed<R: Regressor>(
    data: &Data<'_>,
    settings: &TrainingSettings<'_>,
) -> Result<Box<dyn DynRegressor>, RomError> {
    Ok(Box::new(R::fit(data, &R::training_params(settings))?))
}

fn load_boxed<R: Regressor>(text: &str) -> Result<Box<dyn DynRegressor>, serde_json::Error> {
    Ok(Box::new(serde_json::from_str::<R>(text)?))
}

/// One line of a registry: a regressor type's name, fit and reading.
#[derive(Clone, Copy)]
pub struct Entry {
    name: &'static str,
    fit: FitFn,
    load: LoadFn,
}

impl Entry {
    /// The line of regressor type `R`.
    pub const fn of<R: Regressor>() -> Self {
        Entry {
            name: R::NAME,
            fit: fit_boxed::<R>,
            load: load_boxed::<R>,
        }
    }

    /// The regressor's name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The regressor's kind (its name, as blocks refer to it).
    pub fn kind(&self) -> RegressorKind {
        RegressorKind(Cow::Borrowed(self.name))
    }

    /// Fits the regressor with its settings of a training run
    /// ([`Regressor::training_params`]).
    ///
    /// # Errors
    /// As the regressor's fit.
    pub fn fit(
        &self,
        data: &Data<'_>,
        settings: &TrainingSettings<'_>,
    ) -> Result<Box<dyn DynRegressor>, RomError> {
        (self.fit)(data, settings)
    }

    /// Reads the regressor from its model-file text.
    ///
    /// # Errors
    /// Text that is not this regressor's tables.
    pub fn load(&self, text: &str) -> Result<Box<dyn DynRegressor>, serde_json::Error> {
        (self.load)(text)
    }
}

impl fmt::Debug for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("Entry").field(&self.name).finish()
    }
}

/// The regressors training fits and model loading reads, by name, in order.
#[derive(Clone, Debug)]
pub struct Registry {
    entries: Vec<Entry>,
}

impl Default for Registry {
    fn default() -> Self {
        Registry::builtin()
    }
}

impl Registry {
    /// The built-in regressors ([`BUILTIN`]).
    pub fn builtin() -> Self {
        Registry {
            entries: BUILTIN.to_vec(),
        }
    }

    /// This registry with regressor `R` added at the end.
    ///
    /// # Errors
    /// [`RomError::InvalidInput`] for a name already registered, a name of a model field
    /// (`blocks`, `training` …), or a name that is not lowercase ASCII letters, digits and `_`.
    pub fn with<R: Regressor>(mut self) -> Result<Self, RomError> {
        let name = R::NAME;
        let well_formed = !name.is_empty()
            && name
                .bytes()
                .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_');
        if !well_formed || RESERVED.contains(&name) || self.get(name).is_some() {
            return Err(RomError::invalid(
                "regressor name",
                name,
                &format!(
                    "a new name of lowercase letters, digits and `_`, none of {:?} nor of a \
                     model's fields",
                    self.names()
                ),
            ));
        }
        self.entries.push(Entry::of::<R>());
        Ok(self)
    }

    /// The entries, in order.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// The entry named `name`.
    pub fn get(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// The names, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.entries.iter().map(|e| e.name).collect()
    }
}

/// A model's fitted regressors, each over all blocks' coefficients, in order; serialised as
/// one entry per regressor (`"gp": {…}`) into the model object.
#[derive(Debug, Default)]
pub struct Regressors(Vec<Box<dyn DynRegressor>>);

impl Clone for Regressors {
    fn clone(&self) -> Self {
        Regressors(self.0.iter().map(|r| r.clone_box()).collect())
    }
}

impl PartialEq for Regressors {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len() && self.0.iter().zip(&other.0).all(|(a, b)| a.eq_dyn(&**b))
    }
}

impl Serialize for Regressors {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for r in &self.0 {
            let raw = r.to_raw_json().map_err(S::Error::custom)?;
            map.serialize_entry(r.name(), &raw)?;
        }
        map.end()
    }
}

impl Regressors {
    /// The fitted regressors, in order.
    pub fn new(regressors: Vec<Box<dyn DynRegressor>>) -> Self {
        Regressors(regressors)
    }

    /// Number of regressors.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Regressor `i`.
    ///
    /// # Panics
    /// `i ≥ len()`.
    pub fn at(&self, i: usize) -> &dyn DynRegressor {
        &*self.0[i]
    }

    /// The regressors, in order.
    pub fn iter(&self) -> impl Iterator<Item = &dyn DynRegressor> {
        self.0.iter().map(|r| &**r)
    }

    /// The index of the regressor of kind `kind`.
    pub fn position(&self, kind: &RegressorKind) -> Option<usize> {
        self.0.iter().position(|r| r.name() == kind.name())
    }

    /// The regressor of type `R`, if the model holds one.
    pub fn get<R: Regressor>(&self) -> Option<&R> {
        self.0.iter().find_map(|r| r.as_any().downcast_ref::<R>())
    }

    /// The regressor of type `R`, mutable (the model's derived tables are then stale: rebuild
    /// the model with `derived: Default::default()`).
    pub fn get_mut<R: Regressor>(&mut self) -> Option<&mut R> {
        self.0
            .iter_mut()
            .find_map(|r| r.as_any_mut().downcast_mut::<R>())
    }

    /// The names, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.0.iter().map(|r| r.name()).collect()
    }

    /// Reads the regressors of the model object `model` (its text) that `registry` knows, in
    /// the order of the file; other keys are left to the model's own fields.
    ///
    /// # Errors
    /// A message naming the regressor whose tables do not parse.
    pub fn from_model_json(model: &str, registry: &Registry) -> Result<Self, String> {
        let fields: Fields<'_> = serde_json::from_str(model)
            .map_err(|e| format!("model content is not a JSON object: {e}"))?;
        let mut out = Vec::new();
        for (key, raw) in fields.0 {
            if let Some(entry) = registry.get(&key) {
                let r = entry
                    .load(raw.get())
                    .map_err(|e| format!("regressor `{key}`: {e}"))?;
                out.push(r);
            }
        }
        Ok(Regressors(out))
    }
}

/// The entries of a JSON object, in order, their values unparsed.
struct Fields<'a>(Vec<(Cow<'a, str>, &'a RawValue)>);

impl<'de> Deserialize<'de> for Fields<'de> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Fields<'de>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut out = Vec::new();
                while let Some(key) = map.next_key::<Cow<'de, str>>()? {
                    out.push((key, map.next_value::<&'de RawValue>()?));
                }
                Ok(Fields(out))
            }
        }
        deserializer.deserialize_map(V)
    }
}
