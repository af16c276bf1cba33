//! `pressure_offset`: pressure lost as an offset (bar).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};

/// `pressure_offset`: pressure p0 lost as an offset (leak, gauge zero): effective (1 − f)·P − p0.
pub struct PressureOffset;

const INFO: EffectInfo = EffectInfo {
    name: "pressure_offset",
    meaning: "pressure p0 lost as an offset (leak, gauge zero): effective (1 − f)·P − p0",
    unit: "bar",
    neutral: 0.0,
    range: (0.0, 0.3),
    kind: Kind::Tolerance,
    source: "as pressure_loss",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Pressure lost as an offset (bar).
    pub const PressureOffset: Effect = Effect::builtin(11, &PressureOffset);
}

impl CaseEffect for PressureOffset {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Pressure
    }
    /// `max(0, P − p₀)`.
    fn pressure_bar(&self, p0: f64, pressure_bar: f64) -> f64 {
        (pressure_bar - p0).max(0.0)
    }
}
