//! Recording columns in other units than their format's, each with the column it stands for
//! and the factor that converts it.

use super::{
    q, Quantity, ANGLE, ANGLE_STD, FORCE, FORCE_STD, MARKER_RECORDED_STD, MARKER_RECORDED_UY,
    MARKER_RECORDED_UZ, PRESSURE, TIP_UY, TIP_UZ, WALL_THICKNESS,
};

// ---- recording columns in other units ---------------------------------------------------

/// A recording column in another unit than its format's: accepted by the recording readers in
/// place of [`UnitColumn::canonical`] and converted on reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitColumn {
    /// The column as written: its name, unit and meaning.
    pub column: Quantity,
    /// The format's column it stands for.
    pub canonical: Quantity,
    /// `value × to_canonical` is the value in the canonical column's unit.
    pub to_canonical: f64,
}

const fn alt(column: Quantity, canonical: Quantity, to_canonical: f64) -> UnitColumn {
    UnitColumn {
        column,
        canonical,
        to_canonical,
    }
}

const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;

/// The recording columns in other units that the readers accept (the module docs' second
/// table), each with the column it stands for.
pub const RECORDING_UNIT_COLUMNS: [UnitColumn; 13] = [
    alt(
        q(
            "pressure_kpa",
            "kPa",
            "gauge pressure P in kPa, read as `pressure_bar` × 0.01",
        ),
        PRESSURE,
        0.01,
    ),
    alt(
        q(
            "pressure_mpa",
            "MPa",
            "gauge pressure P in MPa, read as `pressure_bar` × 10",
        ),
        PRESSURE,
        10.0,
    ),
    alt(
        q(
            "pressure_psi",
            "psi",
            "gauge pressure P in psi, read as `pressure_bar` × 0.0689476",
        ),
        PRESSURE,
        0.068_947_572_931_683_6,
    ),
    alt(
        q(
            "wall_thickness_cm",
            "cm",
            "wall thickness T in cm, read as `wall_thickness_mm` × 10",
        ),
        WALL_THICKNESS,
        10.0,
    ),
    alt(
        q("tip_uz_cm", "cm", "tip Uz in cm, read as `tip_uz_mm` × 10"),
        TIP_UZ,
        10.0,
    ),
    alt(
        q("tip_uy_cm", "cm", "tip Uy in cm, read as `tip_uy_mm` × 10"),
        TIP_UY,
        10.0,
    ),
    alt(
        q(
            "angle_rad",
            "rad",
            "bending angle in radians, read as `angle_deg` × 180/π",
        ),
        ANGLE,
        DEG_PER_RAD,
    ),
    alt(
        q(
            "angle_std_rad",
            "rad",
            "its standard deviation in radians, read as `angle_std_deg` × 180/π",
        ),
        ANGLE_STD,
        DEG_PER_RAD,
    ),
    alt(
        q(
            "force_mn",
            "mN",
            "blocked force in mN, read as `force_n` × 0.001",
        ),
        FORCE,
        0.001,
    ),
    alt(
        q(
            "force_std_mn",
            "mN",
            "its standard deviation in mN, read as `force_std_n` × 0.001",
        ),
        FORCE_STD,
        0.001,
    ),
    alt(
        q(
            "uz_cm",
            "cm",
            "recorded marker Uz in cm, read as `uz_mm` × 10",
        ),
        MARKER_RECORDED_UZ,
        10.0,
    ),
    alt(
        q(
            "uy_cm",
            "cm",
            "recorded marker Uy in cm, read as `uy_mm` × 10",
        ),
        MARKER_RECORDED_UY,
        10.0,
    ),
    alt(
        q(
            "std_cm",
            "cm",
            "standard deviation of each marker component in cm, read as `std_mm` × 10",
        ),
        MARKER_RECORDED_STD,
        10.0,
    ),
];
