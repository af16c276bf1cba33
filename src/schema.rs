//! The names, units and meanings of every column and quantity the crate reads or writes, and the
//! ordered columns of each file format. Every other module takes its names from here.
//!
//! A name carries its unit as a suffix (`_mm`, `_deg`, `_n`, `_bar`, `_mpa`); the unit written
//! into model files (`inputs[].unit`) is [`Quantity::unit`], `1` for a dimensionless number
//! and empty for text and flags (`—` below).
//!
//! ## Formats
//!
//! | tag | file | columns, in order |
//! |---|---|---|
//! | snapshots | snapshot CSV (`surrogate snapshots`, `training_data/snapshots_*.csv`): the training data | [`SNAPSHOT_COLUMNS`] (the trainer's contract), then [`PROVENANCE_COLUMNS`] (ignored by the trainer), then for a plan with effects one [`effect_column`] per effect |
//! | query | `surrogate predict --csv`: the query | [`QUERY_COLUMNS`] and either [`MATERIAL`] or [`OGDEN_COLUMNS`], in any order; other columns are passed through |
//! | prediction | `surrogate predict --csv --out`: the predictions | the passed-through columns, [`PREDICTION_INPUT_COLUMNS`], [`OUTPUTS`], with `--std` each output with [`STD_SUFFIX`] (the surrogate against the FE model), for a model with a model-form error each output it covers with [`MODEL_FORM_SUFFIX`], [`IN_DOMAIN`], [`OUTSIDE_DOMAIN`] |
//! | model | model JSON (`models/*.json`) | `inputs[]`: [`PREDICTION_INPUT_COLUMNS`] with units; `outputs`: [`OUTPUTS`]; `validation.outputs[]` and the end-to-end check: [`VALIDATION_GROUPS`] |
//! | domain | training domain: violations (`outside_domain`), plan `ranges` | [`DOMAIN_INPUTS`] |
//! | calibration | calibration reports: parameter names | [`OGDEN_COLUMNS`] (raw space), [`OGDEN_COORDINATES`] (training space) |
//! | bending | `training_data/bending_experiments.csv` | [`BENDING_COLUMNS`] |
//! | force | `training_data/blocked_force_experiments.csv` | [`FORCE_COLUMNS`] |
//! | markers | a marker recording (`surrogate calibrate --markers`) | [`MARKER_RECORDING_COLUMNS`] |
//! | units | a recording column in another unit (bending, force, markers) | [`RECORDING_UNIT_COLUMNS`], each in place of the column it stands for |
//!
//! A reader of the experiment files requires exactly their columns, in any order, each either
//! as named or as one of its [`RECORDING_UNIT_COLUMNS`]; the snapshot reader requires
//! [`SNAPSHOT_COLUMNS`] first and in order.
//!
//! ## Columns and quantities
//!
//! Markers `k = 1 … 9` are the bottom-face points at `z = k·Lf/9` (9 is the tip); displacements
//! follow the experiments' convention `Uz = −Δz`, `Uy = Δy` (`docs/MODEL.md`).
//!
//! | column | unit | meaning | files |
//! |---|---|---|---|
//! | `case_id` | — | case identifier (`case_<id, 6 digits>` in a snapshot store) | snapshots |
//! | `n_bellows` | 1 | number of bellows N | snapshots, query, prediction, model, domain, bending, force, markers |
//! | `wall_thickness_mm` | mm | wall thickness T | snapshots, query, prediction, model, domain, bending, force, markers |
//! | `mu1_mpa` | MPa | Ogden μ₁ | snapshots, query, prediction, model, calibration |
//! | `alpha1` | 1 | Ogden α₁ | snapshots, query, prediction, model, domain, calibration |
//! | `mu2_mpa` | MPa | Ogden μ₂ | snapshots, query, prediction, model, calibration |
//! | `alpha2` | 1 | Ogden α₂ | snapshots, query, prediction, model, domain, calibration |
//! | `mu0_mpa` | MPa | initial shear modulus μ0 = ½ (μ₁α₁ + μ₂α₂) | domain, calibration |
//! | `term1_share` | 1 | share of Ogden term 1, s = μ₁α₁ / (2 μ0) | domain, calibration |
//! | `material` | — | material spec: a literature name or `mu1,alpha1,mu2,alpha2` | query |
//! | `pressure_bar` | bar | gauge pressure P | snapshots, query, prediction, model, domain, bending, force, markers |
//! | `converged` | — | whether the FE step converged (`true`, `false`) | snapshots |
//! | `tip_uz_mm` | mm | tip Uz = −Δz (marker 9) | snapshots, prediction, model, bending |
//! | `tip_uy_mm` | mm | tip Uy = Δy (marker 9) | snapshots, prediction, model, bending |
//! | `angle_deg` | deg | bending angle α = atan2(−y_tip, z_tip) | snapshots, prediction, model, bending |
//! | `force_n` | N | blocked force: the plate's vertical reaction, whole actuator | snapshots, prediction, model, force |
//! | `m1_uz_mm` … `m9_uz_mm` | mm | marker k Uz = −Δz | snapshots, prediction, model |
//! | `m1_uy_mm` … `m9_uy_mm` | mm | marker k Uy = Δy | snapshots, prediction, model |
//! | `markers_mm` | mm | the 18 marker components as one output group | model |
//! | `newton_iterations` | 1 | Newton iterations to reach the step (empty if not reached) | snapshots |
//! | `substeps` | 1 | load substeps to reach the step | snapshots |
//! | `cutbacks` | 1 | load-step cut-backs to reach the step | snapshots |
//! | `residual` | 1 | final normalised residual of the step | snapshots |
//! | `min_gap_mm` | mm | smallest deformed gap between bellows (negative: interpenetration) | snapshots |
//! | `mesh` | — | mesh level | snapshots |
//! | `element_size_mm` | mm | element-size override (empty: none) | snapshots |
//! | `bulk_ratio` | 1 | bulk modulus as a multiple of μ0 | snapshots |
//! | `gravity` | — | whether self-weight is applied (`true`, `false`) | snapshots |
//! | `solver_rtol` | 1 | relative residual tolerance of the Newton solver | snapshots |
//! | `code_version` | — | version of the program that wrote the row | snapshots |
//! | `error` | — | why the step has no result (empty for converged steps) | snapshots |
//! | `in_domain` | — | whether every input lies in the training domain (`true`, `false`) | prediction |
//! | `outside_domain` | — | the inputs outside the domain, `;`-separated, clamped or extrapolated | prediction |
//! | `angle_std_deg` | deg | standard deviation of the measured bending angle | bending |
//! | `force_std_n` | N | standard deviation of the measured blocked force | force |
//! | `marker` | 1 | marker number k, 1 … 9 | markers |
//! | `uz_mm` | mm | recorded Uz = −Δz of the marker | markers |
//! | `uy_mm` | mm | recorded Uy = Δy of the marker | markers |
//! | `std_mm` | mm | standard deviation of each recorded component | markers |
//!
//! ## Recording columns in other units
//!
//! A recording (formats `bending`, `force`, `markers`) may carry one of these columns instead
//! of the format's column of the same quantity; the reader converts it on reading and lists
//! the conversion with the file it read ([`RECORDING_UNIT_COLUMNS`]). Values in the format's
//! own units are checked for scale and sign (`crate::calibrate::units`).
//!
//! | column | unit | meaning | files |
//! |---|---|---|---|
//! | `pressure_kpa` | kPa | gauge pressure P in kPa, read as `pressure_bar` × 0.01 | units |
//! | `pressure_mpa` | MPa | gauge pressure P in MPa, read as `pressure_bar` × 10 | units |
//! | `pressure_psi` | psi | gauge pressure P in psi, read as `pressure_bar` × 0.0689476 | units |
//! | `wall_thickness_cm` | cm | wall thickness T in cm, read as `wall_thickness_mm` × 10 | units |
//! | `tip_uz_cm` | cm | tip Uz in cm, read as `tip_uz_mm` × 10 | units |
//! | `tip_uy_cm` | cm | tip Uy in cm, read as `tip_uy_mm` × 10 | units |
//! | `angle_rad` | rad | bending angle in radians, read as `angle_deg` × 180/π | units |
//! | `angle_std_rad` | rad | its standard deviation in radians, read as `angle_std_deg` × 180/π | units |
//! | `force_mn` | mN | blocked force in mN, read as `force_n` × 0.001 | units |
//! | `force_std_mn` | mN | its standard deviation in mN, read as `force_std_n` × 0.001 | units |
//! | `uz_cm` | cm | recorded marker Uz in cm, read as `uz_mm` × 10 | units |
//! | `uy_cm` | cm | recorded marker Uy in cm, read as `uy_mm` × 10 | units |
//! | `std_cm` | cm | standard deviation of each marker component in cm, read as `std_mm` × 10 | units |

/// A column or quantity: its name in files, its unit and what it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Quantity {
    /// Name in CSV headers and JSON files.
    pub name: &'static str,
    /// Unit: `mm`, `deg`, `N`, `bar`, `MPa`; `1` for a dimensionless number; empty for text.
    pub unit: &'static str,
    /// One line of meaning.
    pub meaning: &'static str,
}

/// The names of `columns`, in order.
pub const fn names<const N: usize>(columns: &[Quantity; N]) -> [&'static str; N] {
    let mut out = [""; N];
    let mut i = 0;
    while i < N {
        out[i] = columns[i].name;
        i += 1;
    }
    out
}

const fn q(name: &'static str, unit: &'static str, meaning: &'static str) -> Quantity {
    Quantity {
        name,
        unit,
        meaning,
    }
}

// ---- design, material, load -------------------------------------------------------------

/// `case_id`.
pub const CASE_ID: Quantity = q(
    "case_id",
    "",
    "case identifier (`case_<id, 6 digits>` in a snapshot store)",
);
/// `n_bellows`.
pub const N_BELLOWS: Quantity = q("n_bellows", "1", "number of bellows N");
/// `wall_thickness_mm`.
pub const WALL_THICKNESS: Quantity = q("wall_thickness_mm", "mm", "wall thickness T");
/// `mu1_mpa`.
pub const MU1: Quantity = q("mu1_mpa", "MPa", "Ogden μ₁");
/// `alpha1`.
pub const ALPHA1: Quantity = q("alpha1", "1", "Ogden α₁");
/// `mu2_mpa`.
pub const MU2: Quantity = q("mu2_mpa", "MPa", "Ogden μ₂");
/// `alpha2`.
pub const ALPHA2: Quantity = q("alpha2", "1", "Ogden α₂");
/// `mu0_mpa`.
pub const MU0: Quantity = q(
    "mu0_mpa",
    "MPa",
    "initial shear modulus μ0 = ½ (μ₁α₁ + μ₂α₂)",
);
/// `term1_share`.
pub const TERM1_SHARE: Quantity = q(
    "term1_share",
    "1",
    "share of Ogden term 1, s = μ₁α₁ / (2 μ0)",
);
/// `material`.
pub const MATERIAL: Quantity = q(
    "material",
    "",
    "material spec: a literature name or `mu1,alpha1,mu2,alpha2`",
);
/// `pressure_bar`.
pub const PRESSURE: Quantity = q("pressure_bar", "bar", "gauge pressure P");
/// `converged`.
pub const CONVERGED: Quantity = q(
    "converged",
    "",
    "whether the FE step converged (`true`, `false`)",
);

// ---- outputs ----------------------------------------------------------------------------

/// `tip_uz_mm`.
pub const TIP_UZ: Quantity = q("tip_uz_mm", "mm", "tip Uz = −Δz (marker 9)");
/// `tip_uy_mm`.
pub const TIP_UY: Quantity = q("tip_uy_mm", "mm", "tip Uy = Δy (marker 9)");
/// `angle_deg`.
pub const ANGLE: Quantity = q("angle_deg", "deg", "bending angle α = atan2(−y_tip, z_tip)");
/// `force_n`.
pub const FORCE: Quantity = q(
    "force_n",
    "N",
    "blocked force: the plate's vertical reaction, whole actuator",
);

macro_rules! marker {
    ($k:literal, $component:literal, $meaning:literal) => {
        q(
            concat!("m", $k, "_", $component, "_mm"),
            "mm",
            concat!("marker ", $k, " ", $meaning),
        )
    };
}

/// `m1_uz_mm` … `m9_uz_mm`: marker `k` at index `k − 1`.
pub const MARKER_UZ: [Quantity; 9] = [
    marker!(1, "uz", "Uz = −Δz"),
    marker!(2, "uz", "Uz = −Δz"),
    marker!(3, "uz", "Uz = −Δz"),
    marker!(4, "uz", "Uz = −Δz"),
    marker!(5, "uz", "Uz = −Δz"),
    marker!(6, "uz", "Uz = −Δz"),
    marker!(7, "uz", "Uz = −Δz"),
    marker!(8, "uz", "Uz = −Δz"),
    marker!(9, "uz", "Uz = −Δz"),
];
/// `m1_uy_mm` … `m9_uy_mm`: marker `k` at index `k − 1`.
pub const MARKER_UY: [Quantity; 9] = [
    marker!(1, "uy", "Uy = Δy"),
    marker!(2, "uy", "Uy = Δy"),
    marker!(3, "uy", "Uy = Δy"),
    marker!(4, "uy", "Uy = Δy"),
    marker!(5, "uy", "Uy = Δy"),
    marker!(6, "uy", "Uy = Δy"),
    marker!(7, "uy", "Uy = Δy"),
    marker!(8, "uy", "Uy = Δy"),
    marker!(9, "uy", "Uy = Δy"),
];
/// `markers_mm`: the marker components as one group (validation and end-to-end entries).
pub const MARKERS: Quantity = q(
    "markers_mm",
    "mm",
    "the 18 marker components as one output group",
);

// ---- provenance of a snapshot row -------------------------------------------------------

/// `newton_iterations`.
pub const NEWTON_ITERATIONS: Quantity = q(
    "newton_iterations",
    "1",
    "Newton iterations to reach the step (empty if not reached)",
);
/// `substeps`.
pub const SUBSTEPS: Quantity = q("substeps", "1", "load substeps to reach the step");
/// `cutbacks`.
pub const CUTBACKS: Quantity = q("cutbacks", "1", "load-step cut-backs to reach the step");
/// `residual`.
pub const RESIDUAL: Quantity = q("residual", "1", "final normalised residual of the step");
/// `min_gap_mm`.
pub const MIN_GAP: Quantity = q(
    "min_gap_mm",
    "mm",
    "smallest deformed gap between bellows (negative: interpenetration)",
);
/// `mesh`.
pub const MESH: Quantity = q("mesh", "", "mesh level");
/// `element_size_mm`.
pub const ELEMENT_SIZE: Quantity = q(
    "element_size_mm",
    "mm",
    "element-size override (empty: none)",
);
/// `bulk_ratio`.
pub const BULK_RATIO: Quantity = q("bulk_ratio", "1", "bulk modulus as a multiple of μ0");
/// `gravity`.
pub const GRAVITY: Quantity = q(
    "gravity",
    "",
    "whether self-weight is applied (`true`, `false`)",
);
/// `solver_rtol`.
pub const SOLVER_RTOL: Quantity = q(
    "solver_rtol",
    "1",
    "relative residual tolerance of the Newton solver",
);
/// `code_version`.
pub const CODE_VERSION: Quantity = q(
    "code_version",
    "",
    "version of the program that wrote the row",
);
/// `error`.
pub const ERROR: Quantity = q(
    "error",
    "",
    "why the step has no result (empty for converged steps)",
);

// ---- prediction flags -------------------------------------------------------------------

/// `in_domain`.
pub const IN_DOMAIN: Quantity = q(
    "in_domain",
    "",
    "whether every input lies in the training domain (`true`, `false`)",
);
/// `outside_domain`.
pub const OUTSIDE_DOMAIN: Quantity = q(
    "outside_domain",
    "",
    "the inputs outside the domain, `;`-separated, clamped or extrapolated",
);
/// Suffix of the column holding an output's standard deviation (`tip_uz_mm_std`): the
/// surrogate's error against the FE model it was trained on, not against real actuators.
pub const STD_SUFFIX: &str = "_std";
/// Suffix of the column holding an output's model-form error (`angle_deg_model_form`): the
/// rms residual of the calibrated model against the recordings it was calibrated on, at the
/// row's pressure, in the output's unit (`surrogate::rom::model_form`).
pub const MODEL_FORM_SUFFIX: &str = "_model_form";

// ---- effects ----------------------------------------------------------------------------

/// Prefix of a snapshot column holding the value of an effect ([`effect_column`]).
pub const EFFECT_PREFIX: &str = "effect_";

/// The snapshot column of an effect (`crate::fe::effects`) of name `name` and unit `unit`:
/// `effect_<name>` with the unit as suffix like every other column (`mm` → `_mm`, `bar` →
/// `_bar`, `MPa` → `_mpa`, `mm/MPa` → `_mm_per_mpa`; none for a dimensionless `1`), holding
/// the effect's value in that unit.
///
/// ```
/// assert_eq!(surrogate::schema::effect_column("wall_bias", "mm"), "effect_wall_bias_mm");
/// assert_eq!(surrogate::schema::effect_column("density", "1"), "effect_density");
/// ```
pub fn effect_column(name: &str, unit: &str) -> String {
    let suffix = unit.to_lowercase().replace('/', "_per_");
    if suffix.is_empty() || suffix == "1" {
        format!("{EFFECT_PREFIX}{name}")
    } else {
        format!("{EFFECT_PREFIX}{name}_{suffix}")
    }
}

// ---- experiments ------------------------------------------------------------------------

/// `angle_std_deg`.
pub const ANGLE_STD: Quantity = q(
    "angle_std_deg",
    "deg",
    "standard deviation of the measured bending angle",
);
/// `force_std_n`.
pub const FORCE_STD: Quantity = q(
    "force_std_n",
    "N",
    "standard deviation of the measured blocked force",
);
/// `marker`.
pub const MARKER: Quantity = q("marker", "1", "marker number k, 1 … 9");
/// `uz_mm`.
pub const MARKER_RECORDED_UZ: Quantity = q("uz_mm", "mm", "recorded Uz = −Δz of the marker");
/// `uy_mm`.
pub const MARKER_RECORDED_UY: Quantity = q("uy_mm", "mm", "recorded Uy = Δy of the marker");
/// `std_mm`.
pub const MARKER_RECORDED_STD: Quantity = q(
    "std_mm",
    "mm",
    "standard deviation of each recorded component",
);

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

// ---- formats ----------------------------------------------------------------------------

/// The snapshot CSV's required columns (the training data), in order.
pub const SNAPSHOT_COLUMNS: [Quantity; 31] = [
    CASE_ID,
    N_BELLOWS,
    WALL_THICKNESS,
    MU1,
    ALPHA1,
    MU2,
    ALPHA2,
    PRESSURE,
    CONVERGED,
    TIP_UZ,
    TIP_UY,
    ANGLE,
    FORCE,
    MARKER_UZ[0],
    MARKER_UY[0],
    MARKER_UZ[1],
    MARKER_UY[1],
    MARKER_UZ[2],
    MARKER_UY[2],
    MARKER_UZ[3],
    MARKER_UY[3],
    MARKER_UZ[4],
    MARKER_UY[4],
    MARKER_UZ[5],
    MARKER_UY[5],
    MARKER_UZ[6],
    MARKER_UY[6],
    MARKER_UZ[7],
    MARKER_UY[7],
    MARKER_UZ[8],
    MARKER_UY[8],
];

/// The names of [`SNAPSHOT_COLUMNS`], in order: the header a snapshot CSV starts with.
pub const SNAPSHOT_COLUMN_NAMES: [&str; 31] = names(&SNAPSHOT_COLUMNS);

/// The provenance columns a snapshot store writes after [`SNAPSHOT_COLUMNS`].
pub const PROVENANCE_COLUMNS: [Quantity; 12] = [
    NEWTON_ITERATIONS,
    SUBSTEPS,
    CUTBACKS,
    RESIDUAL,
    MIN_GAP,
    MESH,
    ELEMENT_SIZE,
    BULK_RATIO,
    GRAVITY,
    SOLVER_RTOL,
    CODE_VERSION,
    ERROR,
];

/// The 22 predicted quantities in storage order: the marker components, then the scalars.
pub const OUTPUTS: [Quantity; 22] = [
    MARKER_UZ[0],
    MARKER_UY[0],
    MARKER_UZ[1],
    MARKER_UY[1],
    MARKER_UZ[2],
    MARKER_UY[2],
    MARKER_UZ[3],
    MARKER_UY[3],
    MARKER_UZ[4],
    MARKER_UY[4],
    MARKER_UZ[5],
    MARKER_UY[5],
    MARKER_UZ[6],
    MARKER_UY[6],
    MARKER_UZ[7],
    MARKER_UY[7],
    MARKER_UZ[8],
    MARKER_UY[8],
    TIP_UZ,
    TIP_UY,
    ANGLE,
    FORCE,
];

/// The output groups of a model's validation and end-to-end entries: the markers, then each
/// scalar.
pub const VALIDATION_GROUPS: [Quantity; 5] = [MARKERS, TIP_UZ, TIP_UY, ANGLE, FORCE];

/// The design and load columns a query must have.
pub const QUERY_COLUMNS: [Quantity; 3] = [N_BELLOWS, WALL_THICKNESS, PRESSURE];

/// The Ogden parameters `[μ₁, α₁, μ₂, α₂]` (a query's material when it has no
/// [`MATERIAL`] column; the raw calibration parameters).
pub const OGDEN_COLUMNS: [Quantity; 4] = [MU1, ALPHA1, MU2, ALPHA2];

/// The material's sampling coordinates `(μ0, s, α₁, α₂)` (the calibration's training space).
pub const OGDEN_COORDINATES: [Quantity; 4] = [MU0, TERM1_SHARE, ALPHA1, ALPHA2];

/// The inputs of a prediction (the input columns of a predicted batch; a model's `inputs`).
pub const PREDICTION_INPUT_COLUMNS: [Quantity; 7] = [
    N_BELLOWS,
    WALL_THICKNESS,
    PRESSURE,
    MU1,
    ALPHA1,
    MU2,
    ALPHA2,
];

/// The inputs checked against a training domain, in the order violations are reported.
pub const DOMAIN_INPUTS: [Quantity; 7] = [
    N_BELLOWS,
    WALL_THICKNESS,
    PRESSURE,
    MU0,
    TERM1_SHARE,
    ALPHA1,
    ALPHA2,
];

/// The columns of a bending experiment file.
pub const BENDING_COLUMNS: [Quantity; 7] = [
    N_BELLOWS,
    WALL_THICKNESS,
    PRESSURE,
    TIP_UZ,
    TIP_UY,
    ANGLE,
    ANGLE_STD,
];

/// The columns of a blocked-force experiment file.
pub const FORCE_COLUMNS: [Quantity; 5] = [N_BELLOWS, WALL_THICKNESS, PRESSURE, FORCE, FORCE_STD];

/// The columns of a marker recording (points tracked along the actuator, in the convention
/// of the tip columns).
pub const MARKER_RECORDING_COLUMNS: [Quantity; 7] = [
    N_BELLOWS,
    WALL_THICKNESS,
    PRESSURE,
    MARKER,
    MARKER_RECORDED_UZ,
    MARKER_RECORDED_UY,
    MARKER_RECORDED_STD,
];

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::{BTreeMap, BTreeSet};
    use std::io::BufRead;

    fn shipped(path: &str) -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
    }

    /// The header line of a shipped file.
    fn header(path: &str) -> String {
        let file = std::fs::File::open(shipped(path)).unwrap();
        let mut line = String::new();
        std::io::BufReader::new(file).read_line(&mut line).unwrap();
        line.trim_end().to_string()
    }

    fn joined(columns: &[Quantity]) -> String {
        columns.iter().map(|c| c.name).collect::<Vec<_>>().join(",")
    }

    /// Every quantity by the tag of the formats it belongs to (the docs' `files` column).
    fn formats() -> Vec<(&'static str, Vec<Quantity>)> {
        vec![
            (
                "snapshots",
                [&SNAPSHOT_COLUMNS[..], &PROVENANCE_COLUMNS].concat(),
            ),
            (
                "query",
                [&QUERY_COLUMNS[..], &[MATERIAL], &OGDEN_COLUMNS].concat(),
            ),
            (
                "prediction",
                [
                    &PREDICTION_INPUT_COLUMNS[..],
                    &OUTPUTS,
                    &[IN_DOMAIN, OUTSIDE_DOMAIN],
                ]
                .concat(),
            ),
            (
                "model",
                [&PREDICTION_INPUT_COLUMNS[..], &OUTPUTS, &VALIDATION_GROUPS].concat(),
            ),
            ("domain", DOMAIN_INPUTS.to_vec()),
            (
                "calibration",
                [&OGDEN_COLUMNS[..], &OGDEN_COORDINATES].concat(),
            ),
            ("bending", BENDING_COLUMNS.to_vec()),
            ("force", FORCE_COLUMNS.to_vec()),
            ("markers", MARKER_RECORDING_COLUMNS.to_vec()),
            (
                "units",
                RECORDING_UNIT_COLUMNS.iter().map(|u| u.column).collect(),
            ),
        ]
    }

    #[test]
    fn unit_columns_stand_for_a_recording_column_of_the_same_quantity() {
        let recordings = [
            &BENDING_COLUMNS[..],
            &FORCE_COLUMNS,
            &MARKER_RECORDING_COLUMNS,
        ]
        .concat();
        for u in RECORDING_UNIT_COLUMNS {
            assert!(recordings.contains(&u.canonical), "{}", u.column.name);
            // the same stem, another unit suffix
            let stem = |name: &'static str| name.rsplit_once('_').map_or(name, |(s, _)| s);
            assert_eq!(stem(u.column.name), stem(u.canonical.name));
            assert_ne!(u.column.unit, u.canonical.unit);
            assert!(u.to_canonical.is_finite() && u.to_canonical > 0.0);
            assert!(!recordings.iter().any(|c| c.name == u.column.name));
        }
    }

    #[test]
    fn names_are_unique_within_each_list() {
        let lists: [(&str, &[Quantity]); 14] = [
            ("SNAPSHOT_COLUMNS", &SNAPSHOT_COLUMNS),
            ("PROVENANCE_COLUMNS", &PROVENANCE_COLUMNS),
            (
                "snapshot store",
                &[&SNAPSHOT_COLUMNS[..], &PROVENANCE_COLUMNS].concat(),
            ),
            ("OUTPUTS", &OUTPUTS),
            ("VALIDATION_GROUPS", &VALIDATION_GROUPS),
            ("QUERY_COLUMNS", &QUERY_COLUMNS),
            ("OGDEN_COLUMNS", &OGDEN_COLUMNS),
            ("OGDEN_COORDINATES", &OGDEN_COORDINATES),
            (
                "prediction",
                &[
                    &PREDICTION_INPUT_COLUMNS[..],
                    &OUTPUTS,
                    &[IN_DOMAIN, OUTSIDE_DOMAIN],
                ]
                .concat(),
            ),
            ("DOMAIN_INPUTS", &DOMAIN_INPUTS),
            ("BENDING_COLUMNS", &BENDING_COLUMNS),
            ("FORCE_COLUMNS", &FORCE_COLUMNS),
            ("MARKER_RECORDING_COLUMNS", &MARKER_RECORDING_COLUMNS),
            ("markers", &[&MARKER_UZ[..], &MARKER_UY].concat()),
        ];
        for (list, columns) in lists {
            let mut seen = BTreeSet::new();
            for c in columns {
                assert!(seen.insert(c.name), "{list}: `{}` twice", c.name);
            }
        }
        // one meaning and unit per name, wherever it is listed
        let mut by_name = BTreeMap::new();
        for (_, columns) in formats() {
            for c in columns {
                assert_eq!(*by_name.entry(c.name).or_insert(c), c, "{}", c.name);
            }
        }
    }

    #[test]
    fn column_lists_are_the_shipped_files_headers() {
        let store = [&SNAPSHOT_COLUMNS[..], &PROVENANCE_COLUMNS].concat();
        assert_eq!(header("training_data/snapshots_coarse.csv"), joined(&store));
        assert_eq!(
            header("training_data/bending_experiments.csv"),
            joined(&BENDING_COLUMNS)
        );
        assert_eq!(
            header("training_data/blocked_force_experiments.csv"),
            joined(&FORCE_COLUMNS)
        );
        // a model file: inputs with units, outputs, validation groups
        let text = std::fs::read_to_string(shipped("models/actuator.json")).unwrap();
        let model: serde_json::Value = serde_json::from_str(&text).unwrap();
        let model = &model["model"];
        let inputs: Vec<(&str, &str)> = model["inputs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|i| (i["name"].as_str().unwrap(), i["unit"].as_str().unwrap()))
            .collect();
        let expected: Vec<(&str, &str)> = PREDICTION_INPUT_COLUMNS
            .iter()
            .map(|c| (c.name, c.unit))
            .collect();
        assert_eq!(inputs, expected);
        let strings = |v: &serde_json::Value| -> Vec<String> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|s| s.as_str().unwrap().to_string())
                .collect()
        };
        assert_eq!(strings(&model["outputs"]), names(&OUTPUTS));
        let groups: Vec<&str> = model["validation"]["outputs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| o["name"].as_str().unwrap())
            .collect();
        assert_eq!(groups, names(&VALIDATION_GROUPS));
        // a plan's ranges are the domain inputs but the pressure (a plan has a pressure ramp)
        let text =
            std::fs::read_to_string(shipped("training_data/snapshots_coarse.plan.json")).unwrap();
        let plan: serde_json::Value = serde_json::from_str(&text).unwrap();
        let ranges: BTreeSet<&str> = plan["ranges"]
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        let expected: BTreeSet<&str> = DOMAIN_INPUTS
            .iter()
            .filter(|c| **c != PRESSURE)
            .map(|c| c.name)
            .collect();
        assert_eq!(ranges, expected);
    }

    /// The module docs' table: column → (unit, meaning, tags).
    fn doc_table() -> BTreeMap<String, (String, String, BTreeSet<String>)> {
        let mut rows = BTreeMap::new();
        for line in include_str!("schema.rs").lines() {
            let Some(row) = line.strip_prefix("//! | `") else {
                continue;
            };
            let cells: Vec<&str> = row.trim_end_matches(" |").split(" | ").collect();
            assert_eq!(cells.len(), 4, "{line}");
            let tags = cells[3].split(", ").map(str::to_string).collect();
            let (unit, meaning) = (cells[1].to_string(), cells[2].to_string());
            let column = cells[0].trim_end_matches('`');
            // `m1_uz_mm` … `m9_uz_mm`: one row for the nine markers, meaning with `k`
            let expanded: Vec<(String, String)> = match column.split_once("` … `") {
                Some((first, _)) => (1..=9)
                    .map(|k| {
                        let name = first.replacen('1', &k.to_string(), 1);
                        (name, meaning.replacen(" k ", &format!(" {k} "), 1))
                    })
                    .collect(),
                None => vec![(column.to_string(), meaning)],
            };
            for (name, meaning) in expanded {
                let old = rows.insert(name, (unit.clone(), meaning, BTreeSet::clone(&tags)));
                assert!(old.is_none(), "{line}: given twice");
            }
        }
        rows
    }

    #[test]
    fn docs_table_lists_every_quantity_with_its_unit_meaning_and_files() {
        let table = doc_table();
        let mut listed = BTreeSet::new();
        for (tag, columns) in formats() {
            for c in columns {
                let (unit, meaning, tags) = table
                    .get(c.name)
                    .unwrap_or_else(|| panic!("`{}` is not in the docs' table", c.name));
                let want_unit = if c.unit.is_empty() { "—" } else { c.unit };
                assert_eq!(unit, want_unit, "{}", c.name);
                assert_eq!(meaning, c.meaning, "{}", c.name);
                assert!(tags.contains(tag), "`{}`: files lack {tag}", c.name);
                listed.insert(c.name.to_string());
            }
        }
        for (name, (_, _, tags)) in &table {
            for tag in tags {
                let format = formats().into_iter().find(|(t, _)| t == tag);
                let (_, columns) = format.unwrap_or_else(|| panic!("`{name}`: unknown file {tag}"));
                assert!(
                    columns.iter().any(|c| c.name == name),
                    "`{name}` is not in {tag}"
                );
            }
        }
        assert_eq!(table.keys().cloned().collect::<BTreeSet<_>>(), listed);
    }
}
