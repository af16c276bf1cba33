//! `duct_bias`: duct half-width off nominal (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::geometry::DesignParams;

/// `duct_bias`: air duct half-width off its nominal 2 mm.
pub struct DuctBias;

const INFO: EffectInfo = EffectInfo {
    name: "duct_bias",
    meaning: "air duct half-width off its nominal 2 mm",
    unit: "mm",
    neutral: 0.0,
    range: (-1.5, 2.0),
    kind: Kind::Unstated,
    source: "not stated: \"chambers connected by a central duct\"; 2 mm half-width is assumed",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Duct half-width off nominal (mm).
    pub const DuctBias: Effect = Effect::builtin(6, &DuctBias);
}

impl CaseEffect for DuctBias {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Geometry
    }
    fn print_design(&self, bias: f64, p: &mut DesignParams) {
        p.duct_half_width += bias;
    }
}
