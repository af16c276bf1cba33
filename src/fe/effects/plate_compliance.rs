//! `plate_compliance`: compliance of the plate and load cell (mm/N).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `plate_compliance`: plate and load cell on a spring: the plate yields c·F under the force F.
pub struct PlateCompliance;

const INFO: EffectInfo = EffectInfo {
    name: "plate_compliance",
    meaning: "plate and load cell on a spring: the plate yields c·F under the force F",
    unit: "mm/N",
    neutral: 0.0,
    range: (0.0, 1.0),
    kind: Kind::Tolerance,
    source: "\"a digital scale with a 0.1 g sensitivity\"",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Compliance of the plate and load cell (mm/N).
    pub const PlateCompliance: Effect = Effect::builtin(15, &PlateCompliance);
}

impl CaseEffect for PlateCompliance {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::PlateCompliance
    }
}
