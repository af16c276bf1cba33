//! `density`: self-weight scale (1).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `density`: self-weight scaled (print not fully dense, grade).
pub struct Density;

const INFO: EffectInfo = EffectInfo {
    name: "density",
    meaning: "self-weight scaled (print not fully dense, grade)",
    unit: "1",
    neutral: 1.0,
    range: (0.5, 1.5),
    kind: Kind::Tolerance,
    source: "NinjaFlex TPU; the print's density is not stated",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Self-weight scale (1).
    pub const Density: Effect = Effect::builtin(12, &Density);
}

impl CaseEffect for Density {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Gravity
    }
}
