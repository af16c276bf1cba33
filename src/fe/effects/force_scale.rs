//! `force_scale`: load-cell scale (1).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `force_scale`: load cell's calibration: recorded force = scale × plate reaction.
pub struct ForceScale;

const INFO: EffectInfo = EffectInfo {
    name: "force_scale",
    meaning: "load cell's calibration: recorded force = scale × plate reaction",
    unit: "1",
    neutral: 1.0,
    range: (0.7, 1.3),
    kind: Kind::Tolerance,
    source: "as plate_compliance",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Load-cell scale (1).
    pub const ForceScale: Effect = Effect::builtin(16, &ForceScale);
}

impl CaseEffect for ForceScale {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::ForceReading
    }
}
