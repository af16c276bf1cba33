//! `wall_bias`: every bellow wall off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `wall_bias`: every bellow wall printed T + bias thick (over/under-extrusion).
pub struct WallBias;

const INFO: EffectInfo = EffectInfo {
    name: "wall_bias",
    meaning: "every bellow wall printed T + bias thick (over/under-extrusion)",
    unit: "mm",
    neutral: 0.0,
    range: (-0.4, 0.4),
    kind: Kind::Tolerance,
    source:
        "T = 1.6, 2.0, 2.4 mm: \"the deposition of 4, 5 and 6 shell layers\" of a 0.4 mm nozzle",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Every bellow wall off nominal (mm).
    pub const WallBias: Effect = Effect::builtin(0, &WallBias);
}

impl CaseEffect for WallBias {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    /// Every wall of the skin and the bellows thicker by `bias`: the walls facing the gaps and
    /// the outer skin (which the side walls follow unless the design sets them apart).
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        let t = p.wall_thickness;
        p.bellow_wall_thickness = Some(p.bellow_wall_thickness.unwrap_or(t) + bias);
        p.skin_thickness = Some(p.skin_thickness.unwrap_or(t) + bias);
        if let Some(s) = p.side_wall_thickness {
            p.side_wall_thickness = Some(s + bias);
        }
    }
}
