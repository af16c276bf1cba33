//! `wall_bias_bellows`: the walls facing the gaps off nominal (mm).

use super::effect::{Effect, EffectInfo, Kind};
use super::walls::{WallBiasOn, Walls};

/// `wall_bias_bellows`: only the walls facing the gaps (normal ±z) off nominal.
const WALL_BIAS_BELLOWS: WallBiasOn = WallBiasOn {
    info: EffectInfo {
        name: "wall_bias_bellows",
        meaning: "only the walls facing the gaps (normal ±z) off nominal",
        unit: "mm",
        neutral: 0.0,
        range: (-0.4, 0.4),
        kind: Kind::Tolerance,
        source: "the walls facing the gaps are shell layers (perimeters): T is stated",
    },
    walls: Walls {
        bellows: true,
        skin: false,
    },
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// The walls facing the gaps off nominal (mm).
    pub const WallBiasBellows: Effect = Effect::builtin(1, &WALL_BIAS_BELLOWS);
}
