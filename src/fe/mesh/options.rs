//! Mesh refinement levels and the options that override them.

use serde::{Deserialize, Serialize};

/// Mesh refinement levels of the actuator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MeshLevel {
    /// Quick looks, tests and snapshots: h = 6 mm, one element through a wall.
    Coarse,
    /// Production level: h = 3 mm, two elements through a wall.
    Standard,
    /// Convergence studies: h = 2 mm, three elements through a wall.
    Fine,
}

impl MeshLevel {
    /// Target element size h (mm) and minimum number of elements through a wall.
    pub fn sizing(self) -> (f64, usize) {
        match self {
            MeshLevel::Coarse => (6.0, 1),
            MeshLevel::Standard => (3.0, 2),
            MeshLevel::Fine => (2.0, 3),
        }
    }
    /// Name as used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MeshLevel::Coarse => "coarse",
            MeshLevel::Standard => "standard",
            MeshLevel::Fine => "fine",
        }
    }
}

impl std::str::FromStr for MeshLevel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "coarse" => Ok(Self::Coarse),
            "standard" => Ok(Self::Standard),
            "fine" => Ok(Self::Fine),
            _ => Err(format!(
                "unknown mesh level '{s}': expected coarse, standard or fine"
            )),
        }
    }
}

/// Mesh options: a level, optionally overridden by an explicit element size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshOptions {
    /// Refinement level.
    pub level: MeshLevel,
    /// Element size override (mm); through-wall count becomes ceil(T / h).
    pub element_size: Option<f64>,
    /// Override of the minimum number of elements through a wall.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_elements: Option<usize>,
}

impl MeshOptions {
    /// Checks the overrides: an element size in (0.2, 50] mm, 1 to 8 elements through a wall.
    ///
    /// # Errors
    /// [`crate::fe::InvalidSetting`] naming `element_size` or `wall_elements`.
    pub fn validate(&self) -> Result<(), crate::fe::InvalidSetting> {
        if let Some(h) = self.element_size {
            if !(h.is_finite() && h > 0.2 && h <= 50.0) {
                return Err(crate::fe::InvalidSetting::new(
                    "element_size",
                    h,
                    "an element size in (0.2, 50] mm",
                ));
            }
        }
        if let Some(k) = self.wall_elements {
            if !(1..=8).contains(&k) {
                return Err(crate::fe::InvalidSetting::new(
                    "wall_elements",
                    k as f64,
                    "1 to 8 elements through a wall",
                ));
            }
        }
        Ok(())
    }

    /// Options of a level without override.
    pub fn level(level: MeshLevel) -> Self {
        Self {
            level,
            element_size: None,
            wall_elements: None,
        }
    }
    pub(super) fn sizing(&self) -> (f64, usize) {
        let (h, div) = match self.element_size {
            Some(h) => (h, 1),
            None => self.level.sizing(),
        };
        (h, self.wall_elements.unwrap_or(div).max(1))
    }
}
