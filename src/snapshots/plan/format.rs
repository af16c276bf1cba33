//! The plan, its validation and its file: versioned JSON, the canonical form and its hash.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::cases::PlannedCase;
use super::ranges::Ranges;
use super::settings::PlanSettings;
use crate::fe::effects::Effect;
use crate::snapshots::{Shard, SnapshotError};

/// Version of the plan format written and accepted.
pub const FORMAT_VERSION: u32 = 1;

/// A sampling plan (see the [module docs](crate::snapshots::plan) and the format in
/// [`super`](crate::snapshots)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Must be [`FORMAT_VERSION`].
    pub format_version: u32,
    /// Seed of the sampler.
    pub seed: u64,
    /// How the cases were sampled.
    pub sampler: String,
    /// The sampling ranges.
    pub ranges: Ranges,
    /// FE settings of every case.
    pub settings: PlanSettings,
    /// The cases.
    pub cases: Vec<PlannedCase>,
}

/// Only the version, read before the rest so an old or new format gets a clear error.
#[derive(Deserialize)]
struct VersionProbe {
    format_version: Option<serde_json::Value>,
}

impl Plan {
    /// Checks version, ranges, settings and every case (ids unique).
    ///
    /// # Errors
    /// [`SnapshotError::PlanField`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SnapshotError> {
        if self.format_version != FORMAT_VERSION {
            return Err(SnapshotError::field(
                "format_version",
                self.format_version,
                &format!("{FORMAT_VERSION}"),
            ));
        }
        self.settings.validate()?;
        let geometry = self.settings.geometry();
        self.ranges.validate_in(&geometry)?;
        let sampled: Vec<Effect> = self
            .ranges
            .sampled_effects()?
            .into_iter()
            .map(|(e, _)| e)
            .collect();
        if let Some(e) = sampled
            .iter()
            .find(|e| self.settings.effects.iter().any(|(f, _)| f == **e))
        {
            return Err(SnapshotError::field(
                "settings.effects",
                e.name(),
                "an effect that ranges.effects does not sample (an effect is fixed or sampled, \
                 not both)",
            ));
        }
        if self.cases.is_empty() {
            return Err(SnapshotError::field("cases", "[]", "at least 1 case"));
        }
        let mut seen = std::collections::HashSet::new();
        for (i, c) in self.cases.iter().enumerate() {
            if !seen.insert(c.id) {
                return Err(SnapshotError::field(
                    format!("cases[{i}].id"),
                    c.id,
                    "an id not used by an earlier case",
                ));
            }
            c.validate(i, &geometry)?;
            c.validate_effects(i, &sampled)?;
        }
        Ok(())
    }

    /// Parses and validates plan JSON; `source` names it in errors.
    ///
    /// # Errors
    /// [`SnapshotError::PlanSyntax`] for invalid JSON, an unknown or missing field (the
    /// message names it, with line and column); [`SnapshotError::PlanField`] for a bad value.
    pub fn from_json(text: &str, source: &str) -> Result<Self, SnapshotError> {
        let syntax = |e: serde_json::Error| SnapshotError::PlanSyntax {
            path: source.to_owned(),
            message: e.to_string(),
        };
        let probe: VersionProbe = serde_json::from_str(text).map_err(syntax)?;
        let expected = serde_json::Value::from(FORMAT_VERSION);
        match probe.format_version {
            Some(v) if v == expected => {}
            Some(v) => {
                return Err(SnapshotError::field(
                    "format_version",
                    v,
                    &format!("{FORMAT_VERSION} (the plan format this program reads)"),
                ))
            }
            None => {
                return Err(SnapshotError::field(
                    "format_version",
                    "missing",
                    &FORMAT_VERSION.to_string(),
                ))
            }
        }
        let plan: Plan = serde_json::from_str(text).map_err(syntax)?;
        plan.validate()?;
        Ok(plan)
    }

    /// Reads and validates a plan file.
    ///
    /// # Errors
    /// I/O errors and those of [`Plan::from_json`].
    pub fn read(path: &Path) -> Result<Self, SnapshotError> {
        let text = std::fs::read_to_string(path).map_err(|e| SnapshotError::io(path, e))?;
        Self::from_json(&text, &path.display().to_string())
    }

    /// Canonical compact JSON (the hashed form).
    pub fn canonical_json(&self) -> String {
        // ok: plain numbers, strings and vectors; no map with non-string keys
        serde_json::to_string(self).expect("a plan always serialises")
    }

    /// Pretty JSON (what `snapshots plan` writes).
    pub fn pretty_json(&self) -> String {
        // ok: as above
        serde_json::to_string_pretty(self).expect("a plan always serialises")
    }

    /// The plan hash: CRC-32 of [`Plan::canonical_json`], 8 lowercase hex digits.
    pub fn hash(&self) -> String {
        format!("{:08x}", crc32fast::hash(self.canonical_json().as_bytes()))
    }

    /// The effects of the plan's snapshot columns: the fixed and the sampled ones, in the
    /// library's order (empty for a plan without effects).
    pub fn effect_columns(&self) -> Vec<Effect> {
        let mut all: Vec<Effect> = self.settings.effects.iter().map(|(e, _)| e).collect();
        if let Some(c) = self.cases.first() {
            all.extend(c.effects.iter().map(|(e, _)| e));
        }
        all.sort();
        all.dedup();
        all
    }

    /// The cases of `shard`, in plan order (see [`Shard`]).
    pub fn shard_cases(&self, shard: Shard) -> Vec<&PlannedCase> {
        self.cases
            .iter()
            .enumerate()
            .filter(|(i, _)| shard.owns(*i))
            .map(|(_, c)| c)
            .collect()
    }
}
