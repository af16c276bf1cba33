//! `clamp_shear_compliance`: tangential compliance of the clamp (mm/MPa).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `clamp_shear_compliance`: clamped face on tangential springs of stiffness 1/c per unit area.
pub struct ClampShearCompliance;

const INFO: EffectInfo = EffectInfo {
    name: "clamp_shear_compliance",
    meaning: "clamped face on tangential springs of stiffness 1/c per unit area",
    unit: "mm/MPa",
    neutral: 0.0,
    range: (0.0, 0.5),
    kind: Kind::Tolerance,
    source: "as clamp_compliance",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Tangential compliance of the clamp (mm/MPa).
    pub const ClampShearCompliance: Effect = Effect::builtin(9, &ClampShearCompliance);
}

impl CaseEffect for ClampShearCompliance {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Clamp([true, true, false])
    }
}
