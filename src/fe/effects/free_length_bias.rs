//! `free_length_bias`: free length off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `free_length_bias`: free length off its nominal 92 mm (where the clamp grips).
pub struct FreeLengthBias;

const INFO: EffectInfo = EffectInfo {
    name: "free_length_bias",
    meaning: "free length off its nominal 92 mm (where the clamp grips)",
    unit: "mm",
    neutral: 0.0,
    range: (-6.0, 6.0),
    kind: Kind::Unstated,
    source: "not stated: \"the overall length of the actuator is set at 115 mm\" includes the clamped inlet; 92 mm free is assumed",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Free length off nominal (mm).
    pub const FreeLengthBias: Effect = Effect::builtin(7, &FreeLengthBias);
}

impl CaseEffect for FreeLengthBias {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        p.free_length += bias;
    }
}
