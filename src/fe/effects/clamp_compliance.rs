//! `clamp_compliance`: normal compliance of the clamp (mm/MPa).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `clamp_compliance`: clamped face on normal springs of stiffness 1/c per unit area (yielding jaws).
pub struct ClampCompliance;

const INFO: EffectInfo = EffectInfo {
    name: "clamp_compliance",
    meaning: "clamped face on normal springs of stiffness 1/c per unit area (yielding jaws)",
    unit: "mm/MPa",
    neutral: 0.0,
    range: (0.0, 0.5),
    kind: Kind::Tolerance,
    source: "\"mounted horizontally on a 3D-printed custom support\": a rigid clamp is assumed",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Normal compliance of the clamp (mm/MPa).
    pub const ClampCompliance: Effect = Effect::builtin(8, &ClampCompliance);
}

impl CaseEffect for ClampCompliance {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Clamp([false, false, true])
    }
}
