//! `plate_offset`: plate further below the sagged tip than 5 mm (mm).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `plate_offset`: force plate this much further than 5 mm below the sagged tip (negative: closer).
pub struct PlateOffset;

const INFO: EffectInfo = EffectInfo {
    name: "plate_offset",
    meaning: "force plate this much further than 5 mm below the sagged tip (negative: closer)",
    unit: "mm",
    neutral: 0.0,
    range: (-4.5, 2.0),
    kind: Kind::Unstated,
    source: "not stated: the actuator \"was positioned 5 mm above the scale's plate to allow it to bend and apply force to a 3D-printed square\" of unstated height",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Plate further below the sagged tip than 5 mm (mm).
    pub const PlateOffset: Effect = Effect::builtin(14, &PlateOffset);
}

impl CaseEffect for PlateOffset {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::PlateOffset
    }
}
