//! `wall_bias_skin`: the outer skin (side wall, top) off nominal (mm).

use super::effect::{Effect, EffectInfo, Kind};
use super::walls::{WallBiasOn, Walls};

/// `wall_bias_skin`: only the outer skin (side wall and top) off nominal, and the side walls
/// with it where the design sets them apart (otherwise they follow the skin).
const WALL_BIAS_SKIN: WallBiasOn = WallBiasOn {
    info: EffectInfo {
        name: "wall_bias_skin",
        meaning: "only the outer skin (side wall and top) off nominal",
        unit: "mm",
        neutral: 0.0,
        range: (-0.4, 0.4),
        kind: Kind::Tolerance,
        source: "side wall and top drawn T thick in the model; the drawing labels only \"wall thickness\"",
    },
    walls: Walls {
        bellows: false,
        skin: true,
    },
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// The outer skin (side wall, top) off nominal (mm).
    pub const WallBiasSkin: Effect = Effect::builtin(2, &WALL_BIAS_SKIN);
}
