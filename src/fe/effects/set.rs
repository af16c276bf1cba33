//! The effects of a case ([`Effects`]): each effect's value, and what they do together to the
//! design, the pressure, the self-weight, the material, the clamp, the force plate and the
//! reported force. Effects are applied in the library's order, a program's own after them.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::effect::{Effect, EffectError, Target};
use crate::fe::geometry::DesignParams;
use crate::fe::material::{Material, MaterialError};

/// The effects of a case: each effect's value, neutral where not set.
///
/// Serialised as a map `{name: value}` of the effects that are set; a case without effects
/// writes none (`#[serde(skip_serializing_if = "Effects::is_neutral")]`), so its files and
/// hashes are those of a case written before effects existed. Read back, the names are the
/// library's; a program's own are read through its
/// [`EffectRegistry`](super::EffectRegistry) (a `DeserializeSeed`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "BTreeMap<String, f64>", into = "BTreeMap<String, f64>")]
pub struct Effects {
    values: BTreeMap<Effect, f64>,
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

    /// The effects that are set, with their values, in the order they are applied.
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

    /// The effects on `target` away from their neutral values, in the order they apply.
    fn acting(&self, target: Target) -> impl Iterator<Item = (Effect, f64)> + '_ {
        self.iter()
            .filter(move |&(e, v)| e.target() == target && v != e.info().neutral)
    }

    /// The values of the effects on `target` (neutral ones included).
    fn values_on(&self, target: Target) -> impl Iterator<Item = f64> + '_ {
        self.iter()
            .filter(move |(e, _)| e.target() == target)
            .map(|(_, v)| v)
    }

    /// The design as printed: the nominal design with the geometry effects applied
    /// ([`Target::Geometry`]). Neutral effects leave it unchanged (the same value, not a
    /// recomputed one).
    pub fn printed_design(&self, nominal: &DesignParams) -> DesignParams {
        let mut p = nominal.clone();
        for (e, v) in self.acting(Target::Geometry) {
            e.def().print_design(v, &mut p);
        }
        p
    }

    /// The pressure that acts in the cavities (bar) for a gauge pressure `gauge` (bar), the
    /// pressure effects applied in turn ([`Target::Pressure`]); the gauge pressure itself when
    /// they are neutral.
    pub fn effective_pressure_bar(&self, gauge: f64) -> f64 {
        self.acting(Target::Pressure)
            .fold(gauge, |p, (e, v)| e.def().pressure_bar(v, p))
    }

    /// The self-weight's scale: the product of the gravity effects' factors.
    pub fn gravity_scale(&self) -> f64 {
        self.values_on(Target::Gravity).product()
    }

    /// Extra distance of the plate below the nominal 5 mm (mm): the sum of the plate offsets.
    pub fn plate_offset_mm(&self) -> f64 {
        self.values_on(Target::PlateOffset).fold(0.0, |a, v| a + v)
    }

    /// Compliance of the plate's support (mm/N): the plate moves `c·F` away from the tip
    /// under the blocked force `F` (the whole actuator's, N).
    pub fn plate_compliance_mm_per_n(&self) -> f64 {
        self.values_on(Target::PlateCompliance)
            .fold(0.0, |a, v| a + v)
    }

    /// The material as printed: `material` with the material effects applied in turn
    /// ([`Target::Material`]); `material` itself (cloned) when they are neutral.
    ///
    /// # Errors
    /// The first effect's [`MaterialError`] (e.g. the anisotropy refusing a material that
    /// already has a fibre term).
    pub fn printed_material(&self, material: &Material) -> Result<Material, MaterialError> {
        let mut m = material.clone();
        for (e, v) in self.acting(Target::Material) {
            m = e.def().print_material(v, &m)?;
        }
        Ok(m)
    }

    /// The load cell's scale: the product of the reading effects' scales.
    pub fn force_scale(&self) -> f64 {
        self.values_on(Target::ForceReading).product()
    }

    /// Spring stiffness per unit area of the clamped face in x, y, z (MPa/mm), `None` where the
    /// face stays rigidly held: in each direction `1/c`, `c` the sum of the compliances of the
    /// clamp effects in that direction (`clamp_shear_compliance` in x and y,
    /// `clamp_compliance` in z).
    pub fn clamp_springs(&self) -> [Option<f64>; 3] {
        let mut c = [0.0; 3];
        for (e, v) in self.iter() {
            if let Target::Clamp(dirs) = e.target() {
                for (ci, on) in c.iter_mut().zip(dirs) {
                    if on {
                        *ci += v;
                    }
                }
            }
        }
        c.map(|c| (c > 0.0).then(|| 1.0 / c))
    }
}
