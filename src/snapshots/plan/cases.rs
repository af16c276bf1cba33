//! One case of a plan: its design, material and effects, its checks and its name.

use serde::{Deserialize, Serialize};

use super::settings::{no_effects, PlanSettings};
use crate::case::OgdenSet;
use crate::fe::effects::{Effect, EffectError, Effects};
use crate::fe::geometry::{Design, DesignParams, GeometryError};
use crate::fe::material::{Material, MaterialError, MaterialLaw, Ogden2};
use crate::fe::preset::{Geometry, PresetError};
use crate::schema;
use crate::snapshots::SnapshotError;

/// One case of a plan: a design and an Ogden material.
///
/// Its file shape is flat (`id, n_bellows, wall_thickness_mm, mu1_mpa, alpha1, mu2_mpa,
/// alpha2, effects`), the shape plans were written and hashed in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "PlannedCaseFile", into = "PlannedCaseFile")]
pub struct PlannedCase {
    /// Identifier, unique in the plan (names the case file).
    pub id: usize,
    /// Number of bellows `N`.
    pub n_bellows: usize,
    /// Wall thickness `T` (mm).
    pub wall_thickness_mm: f64,
    /// The Ogden material.
    pub material: OgdenSet,
    /// Values of the plan's sampled effects (none: not written).
    pub effects: Effects,
}

/// The file shape of [`PlannedCase`]: the material's four fields inline, no other field
/// (`deny_unknown_fields` does not combine with `#[serde(flatten)]`).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PlannedCaseFile {
    id: usize,
    n_bellows: usize,
    wall_thickness_mm: f64,
    mu1_mpa: f64,
    alpha1: f64,
    mu2_mpa: f64,
    alpha2: f64,
    #[serde(default, skip_serializing_if = "no_effects")]
    effects: Effects,
}

impl From<PlannedCaseFile> for PlannedCase {
    fn from(f: PlannedCaseFile) -> Self {
        PlannedCase {
            id: f.id,
            n_bellows: f.n_bellows,
            wall_thickness_mm: f.wall_thickness_mm,
            material: OgdenSet::from_array([f.mu1_mpa, f.alpha1, f.mu2_mpa, f.alpha2]),
            effects: f.effects,
        }
    }
}

impl From<PlannedCase> for PlannedCaseFile {
    fn from(c: PlannedCase) -> Self {
        let [mu1_mpa, alpha1, mu2_mpa, alpha2] = c.material.as_array();
        PlannedCaseFile {
            id: c.id,
            n_bellows: c.n_bellows,
            wall_thickness_mm: c.wall_thickness_mm,
            mu1_mpa,
            alpha1,
            mu2_mpa,
            alpha2,
            effects: c.effects,
        }
    }
}

impl PlannedCase {
    /// The case's design (SPEC defaults with this `N` and `T`).
    ///
    /// # Errors
    /// [`GeometryError`] if `N` or `T` is out of range or leaves no cavity.
    pub fn design(&self) -> Result<Design, GeometryError> {
        DesignParams::new(self.n_bellows, self.wall_thickness_mm).validate()
    }

    /// The case's material with `κ = bulk_ratio · μ0`.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] for an inadmissible Ogden set or bulk ratio.
    pub fn material(&self, bulk_ratio: f64) -> Result<Material, MaterialError> {
        let law = Ogden2::try_from(self.material)?;
        Material::new(MaterialLaw::Ogden(law), bulk_ratio)
    }

    /// The effects of the case's FE runs: the plan's fixed effects and the case's sampled ones.
    ///
    /// # Errors
    /// An effect both fixed and sampled with different values (a validated plan has none).
    pub fn effects_with(&self, settings: &PlanSettings) -> Result<Effects, EffectError> {
        let mut all = settings.effects.clone();
        for (e, v) in self.effects.iter() {
            let fixed = settings.effects.iter().find(|&(f, _)| f == e);
            if let Some((_, first)) = fixed.filter(|&(_, first)| first != v) {
                return Err(EffectError::Duplicate {
                    name: e.name(),
                    first,
                    second: v,
                });
            }
            all.set(e, v)?;
        }
        Ok(all)
    }

    /// Checks that the case carries a value of every sampled effect and no other.
    pub(super) fn validate_effects(
        &self,
        index: usize,
        sampled: &[Effect],
    ) -> Result<(), SnapshotError> {
        let mine: Vec<Effect> = self.effects.iter().map(|(e, _)| e).collect();
        if mine != sampled {
            let names = |v: &[Effect]| v.iter().map(|e| e.name()).collect::<Vec<_>>().join(", ");
            return Err(SnapshotError::field(
                format!("cases[{index}] (id {}).effects", self.id),
                format!("{{{}}}", names(&mine)),
                &format!(
                    "a value of each effect sampled by the plan (ranges.effects: {{{}}}) and no other",
                    names(sampled)
                ),
            ));
        }
        Ok(())
    }

    /// The case's design built with `geometry`'s dimensions; [`Self::design`] bit for bit
    /// for [`Geometry::as_modelled`].
    ///
    /// # Errors
    /// [`PresetError`] if the preset is out of range or leaves this design no valid actuator.
    pub fn design_with(&self, geometry: &Geometry) -> Result<Design, PresetError> {
        geometry.design(self.n_bellows, self.wall_thickness_mm)
    }

    /// Checks design (with `geometry`) and material; errors name `cases[index]`.
    pub(super) fn validate(&self, index: usize, geometry: &Geometry) -> Result<(), SnapshotError> {
        let at = |f: &str| format!("cases[{index}] (id {}).{f}", self.id);
        let design = match self.design_with(geometry) {
            Ok(d) => Ok(d),
            // a design that the preset's own dimensions break (a wall law that closes a short
            // cavity) is a T beyond this N's buildability limit with the preset
            Err(PresetError::Design { source, .. }) if !geometry.is_as_modelled() => {
                let limit = geometry
                    .max_wall_thickness(self.n_bellows)
                    .map_or("no T in range".to_owned(), |t| format!("T ≤ {t:.3} mm"));
                return Err(SnapshotError::field(
                    at(schema::WALL_THICKNESS.name),
                    self.wall_thickness_mm,
                    &format!(
                        "a thickness buildable with geometry '{}' (N = {} needs {limit}: {source})",
                        geometry.name, self.n_bellows
                    ),
                ));
            }
            Err(PresetError::Design { source, .. }) => Err(source),
            Err(e) => {
                return Err(SnapshotError::field(
                    at("design"),
                    &geometry.name,
                    &e.to_string(),
                ))
            }
        };
        match design {
            Ok(_) => {}
            Err(GeometryError::OutOfRange {
                field,
                value,
                expected,
            }) => {
                let name = if field == "wall_thickness" {
                    schema::WALL_THICKNESS.name
                } else {
                    field
                };
                return Err(SnapshotError::field(at(name), value, &expected));
            }
            Err(e @ GeometryError::NoCavity { .. }) => {
                return Err(SnapshotError::field(
                    at(schema::WALL_THICKNESS.name),
                    self.wall_thickness_mm,
                    &format!("a thickness that leaves a cavity ({e})"),
                ));
            }
        }
        match Ogden2::try_from(self.material) {
            Ok(_) => Ok(()),
            Err(MaterialError::Inadmissible {
                field,
                value,
                expected,
            }) => Err(SnapshotError::field(at(&field), value, &expected)),
            Err(e) => Err(SnapshotError::field(at("material"), "?", &e.to_string())),
        }
    }
}

/// The `case_id` of a plan case.
pub fn case_name(id: usize) -> String {
    format!("case_{id:06}")
}
