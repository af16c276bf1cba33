//! `wall_bias_skin`: the outer skin (side wall, top) off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `wall_bias_skin`: only the outer skin (side wall and top) off nominal.
pub struct WallBiasSkin;

const INFO: EffectInfo = EffectInfo {
    name: "wall_bias_skin",
    meaning: "only the outer skin (side wall and top) off nominal",
    unit: "mm",
    neutral: 0.0,
    range: (-0.4, 0.4),
    kind: Kind::Tolerance,
    source:
        "side wall and top drawn T thick in the model; the drawing labels only \"wall thickness\"",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// The outer skin (side wall, top) off nominal (mm).
    pub const WallBiasSkin: Effect = Effect::builtin(2, &WallBiasSkin);
}

impl CaseEffect for WallBiasSkin {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    /// The outer skin thicker by `bias`, and the side walls with it where the design sets them
    /// apart (otherwise they follow the skin).
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        let t = p.wall_thickness;
        p.skin_thickness = Some(p.skin_thickness.unwrap_or(t) + bias);
        if let Some(s) = p.side_wall_thickness {
            p.side_wall_thickness = Some(s + bias);
        }
    }
}
