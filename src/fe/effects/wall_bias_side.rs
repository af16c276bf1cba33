//! `wall_bias_side`: the side walls (normal ±x, printed as solid layers) off their modelled thickness (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `wall_bias_side`: only the side walls (normal ±x, solid layers of the print) off their modelled thickness.
pub struct WallBiasSide;

const INFO: EffectInfo = EffectInfo {
    name: "wall_bias_side",
    meaning: "only the side walls (normal ±x, solid layers of the print) off their modelled thickness",
    unit: "mm",
    neutral: 0.0,
    range: (-1.8, 1.8),
    kind: Kind::Unstated,
    source: "not stated: printed \"sideways, with the bending plane parallel to the building platform\", the side walls (normal x) are solid layers of 0.15 mm whose count is not given",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// The side walls (normal ±x, printed as solid layers) off their modelled thickness (mm).
    pub const WallBiasSide: Effect = Effect::builtin(3, &WallBiasSide);
}

impl CaseEffect for WallBiasSide {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    /// The side walls thicker by `bias` than they are, or than the skin where they follow it.
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        let side = p
            .side_wall_thickness
            .unwrap_or_else(|| p.skin_thickness.unwrap_or(p.wall_thickness));
        p.side_wall_thickness = Some(side + bias);
    }
}
