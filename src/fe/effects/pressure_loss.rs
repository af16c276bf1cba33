//! `pressure_loss`: fraction of the gauge pressure lost (1).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `pressure_loss`: fraction f of the gauge pressure lost: effective (1 − f)·P − p0.
pub struct PressureLoss;

const INFO: EffectInfo = EffectInfo {
    name: "pressure_loss",
    meaning: "fraction f of the gauge pressure lost: effective (1 − f)·P − p0",
    unit: "1",
    neutral: 0.0,
    range: (0.0, 0.3),
    kind: Kind::Tolerance,
    source: "\"regulated by a pressure gauge at the compressor's outlet\" and an electro-pneumatic transducer",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Fraction of the gauge pressure lost (1).
    pub const PressureLoss: Effect = Effect::builtin(10, &PressureLoss);
}

impl CaseEffect for PressureLoss {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Pressure
    }
    /// `(1 − f)·P`.
    fn pressure_bar(&self, f: f64, pressure_bar: f64) -> f64 {
        (1.0 - f) * pressure_bar
    }
}
