//! The parameters outputs are differentiated with respect to: the four Ogden parameters of the
//! material and every effect of the library ([`crate::fe::effects`]), or of a program's
//! [`EffectRegistry`] (the `*_with` functions).

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::SensitivityError;
use crate::fe::effects::{Effect, EffectRegistry};

/// A parameter of the second-order Ogden law (ANSYS convention).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OgdenParameter {
    /// `μ₁` (MPa).
    Mu1,
    /// `α₁`.
    Alpha1,
    /// `μ₂` (MPa).
    Mu2,
    /// `α₂`.
    Alpha2,
}

impl OgdenParameter {
    /// All four, in the law's order `[μ₁, α₁, μ₂, α₂]`.
    pub const ALL: [OgdenParameter; 4] = [Self::Mu1, Self::Alpha1, Self::Mu2, Self::Alpha2];

    /// Position in `[μ₁, α₁, μ₂, α₂]`.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// What an output is differentiated with respect to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// An Ogden parameter of the material (the bulk modulus follows `μ0` at the material's
    /// bulk ratio, as every material the crate builds does).
    Material(OgdenParameter),
    /// The value of an effect.
    Effect(Effect),
}

impl Serialize for Parameter {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Parameter {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Parameter::from_name(&name).map_err(serde::de::Error::custom)
    }
}

impl Parameter {
    /// Name on the command line and in files: `mu1`, `alpha1`, `mu2`, `alpha2`, or the
    /// effect's name.
    pub fn name(self) -> &'static str {
        match self {
            Parameter::Material(OgdenParameter::Mu1) => "mu1",
            Parameter::Material(OgdenParameter::Alpha1) => "alpha1",
            Parameter::Material(OgdenParameter::Mu2) => "mu2",
            Parameter::Material(OgdenParameter::Alpha2) => "alpha2",
            Parameter::Effect(e) => e.name(),
        }
    }

    /// Unit of the parameter.
    pub fn unit(self) -> &'static str {
        match self {
            Parameter::Material(OgdenParameter::Mu1 | OgdenParameter::Mu2) => "MPa",
            Parameter::Material(_) => "1",
            Parameter::Effect(e) => e.info().unit,
        }
    }

    /// Every parameter: the four material ones, then the effects in the library's order.
    pub fn all() -> Vec<Parameter> {
        Parameter::all_with(&EffectRegistry::builtin())
    }

    /// Every parameter a program knows: the four material ones, then the effects of
    /// `registry` in its order.
    pub fn all_with(registry: &EffectRegistry) -> Vec<Parameter> {
        OgdenParameter::ALL
            .into_iter()
            .map(Parameter::Material)
            .chain(registry.iter().map(Parameter::Effect))
            .collect()
    }

    /// The parameter called `name` (a material parameter or an effect of the library).
    ///
    /// # Errors
    /// [`SensitivityError::Unknown`] listing the names.
    pub fn from_name(name: &str) -> Result<Parameter, SensitivityError> {
        Parameter::from_name_with(name, &EffectRegistry::builtin())
    }

    /// The parameter called `name`: a material parameter or an effect of `registry`.
    ///
    /// # Errors
    /// [`SensitivityError::Unknown`] listing the names.
    pub fn from_name_with(
        name: &str,
        registry: &EffectRegistry,
    ) -> Result<Parameter, SensitivityError> {
        let all = Parameter::all_with(registry);
        all.iter()
            .copied()
            .find(|p| p.name() == name)
            .ok_or_else(|| SensitivityError::Unknown {
                name: name.to_string(),
                known: all.iter().map(|p| p.name()).collect::<Vec<_>>().join(", "),
            })
    }

    /// A list `NAME,NAME,…` or `all`, the effects among the library's.
    ///
    /// # Errors
    /// [`SensitivityError::Unknown`] for a name that is not a parameter (or an empty list),
    /// [`SensitivityError::Duplicate`] for one given twice.
    pub fn parse_list(text: &str) -> Result<Vec<Parameter>, SensitivityError> {
        Parameter::parse_list_with(text, &EffectRegistry::builtin())
    }

    /// A list `NAME,NAME,…` or `all`, the effects among those of `registry`.
    ///
    /// # Errors
    /// See [`Self::parse_list`].
    pub fn parse_list_with(
        text: &str,
        registry: &EffectRegistry,
    ) -> Result<Vec<Parameter>, SensitivityError> {
        if text.trim() == "all" {
            return Ok(Parameter::all_with(registry));
        }
        let mut out: Vec<Parameter> = Vec::new();
        for name in text.split(',').map(str::trim) {
            let p = Parameter::from_name_with(name, registry)?;
            if out.contains(&p) {
                return Err(SensitivityError::Duplicate {
                    name: name.to_string(),
                });
            }
            out.push(p);
        }
        Ok(out)
    }
}
