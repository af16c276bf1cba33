//! `wall_bias`: every bellow wall off nominal (mm).

use super::effect::{Effect, EffectInfo, Kind};
use super::walls::{WallBiasOn, Walls};

/// `wall_bias`: every bellow wall printed T + bias thick (over/under-extrusion): the walls
/// facing the gaps and the outer skin (which the side walls follow unless the design sets them
/// apart).
const WALL_BIAS: WallBiasOn = WallBiasOn {
    info: EffectInfo {
        name: "wall_bias",
        meaning: "every bellow wall printed T + bias thick (over/under-extrusion)",
        unit: "mm",
        neutral: 0.0,
        range: (-0.4, 0.4),
        kind: Kind::Tolerance,
        source:
            "T = 1.6, 2.0, 2.4 mm: \"the deposition of 4, 5 and 6 shell layers\" of a 0.4 mm nozzle",
    },
    walls: Walls {
        bellows: true,
        skin: true,
    },
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Every bellow wall off nominal (mm).
    pub const WallBias: Effect = Effect::builtin(0, &WALL_BIAS);
}
