//! `wall_bias_bellows`: the walls facing the gaps off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `wall_bias_bellows`: only the walls facing the gaps (normal ±z) off nominal.
pub struct WallBiasBellows;

const INFO: EffectInfo = EffectInfo {
    name: "wall_bias_bellows",
    meaning: "only the walls facing the gaps (normal ±z) off nominal",
    unit: "mm",
    neutral: 0.0,
    range: (-0.4, 0.4),
    kind: Kind::Tolerance,
    source: "the walls facing the gaps are shell layers (perimeters): T is stated",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// The walls facing the gaps off nominal (mm).
    pub const WallBiasBellows: Effect = Effect::builtin(1, &WallBiasBellows);
}

impl CaseEffect for WallBiasBellows {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        let t = p.wall_thickness;
        p.bellow_wall_thickness = Some(p.bellow_wall_thickness.unwrap_or(t) + bias);
    }
}
