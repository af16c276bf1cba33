//! `base_bias`: base thickness off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `base_bias`: strain-limiting base off its nominal 4 mm.
pub struct BaseBias;

const INFO: EffectInfo = EffectInfo {
    name: "base_bias",
    meaning: "strain-limiting base off its nominal 4 mm",
    unit: "mm",
    neutral: 0.0,
    range: (-0.8, 3.0),
    kind: Kind::Unstated,
    source: "not stated: the drawing gives only the height 22 and width 16; 4 mm is assumed",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Base thickness off nominal (mm).
    pub const BaseBias: Effect = Effect::builtin(5, &BaseBias);
}

impl CaseEffect for BaseBias {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        p.base_thickness += bias;
    }
}
