//! `gap_bias`: gap between bellows off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `gap_bias`: gap between neighbouring bellows off its nominal 1 mm.
pub struct GapBias;

const INFO: EffectInfo = EffectInfo {
    name: "gap_bias",
    meaning: "gap between neighbouring bellows off its nominal 1 mm",
    unit: "mm",
    neutral: 0.0,
    range: (-0.8, 1.0),
    kind: Kind::Unstated,
    source: "not stated: the drawing shows \"repeated slots\", the text \"narrow gaps\"; 1 mm is assumed",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Gap between bellows off nominal (mm).
    pub const GapBias: Effect = Effect::builtin(4, &GapBias);
}

impl CaseEffect for GapBias {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        p.gap += bias;
    }
}
