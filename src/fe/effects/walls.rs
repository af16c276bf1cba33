//! The shape the wall-bias effects share: a printed thickness `T + bias` of the walls each
//! names ([`Walls`]), the others as modelled.

use super::effect::{CaseEffect, EffectInfo, Target};
use crate::fe::geometry::DesignParams;

/// The walls a wall bias thickens.
pub(super) struct Walls {
    /// The walls facing the gaps (normal ±z).
    pub bellows: bool,
    /// The outer skin, and the side walls with it where the design sets them apart (otherwise
    /// they follow the skin).
    pub skin: bool,
}

/// A wall-bias effect: its description and the walls it thickens by its value (mm).
pub(super) struct WallBiasOn {
    /// Name, meaning, unit, neutral value, range, kind and source.
    pub info: EffectInfo,
    /// The walls it thickens.
    pub walls: Walls,
}

impl CaseEffect for WallBiasOn {
    fn info(&self) -> &EffectInfo {
        &self.info
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    /// The walls named thicker by `bias`: those facing the gaps, then the skin and the side
    /// walls set apart from it.
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        let t = p.wall_thickness;
        if self.walls.bellows {
            p.bellow_wall_thickness = Some(p.bellow_wall_thickness.unwrap_or(t) + bias);
        }
        if self.walls.skin {
            p.skin_thickness = Some(p.skin_thickness.unwrap_or(t) + bias);
            if let Some(s) = p.side_wall_thickness {
                p.side_wall_thickness = Some(s + bias);
            }
        }
    }
}
