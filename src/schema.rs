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
//!
//! The quantities are defined here; the ordered columns of each format ([`SNAPSHOT_COLUMNS`] …)
//! are in `formats`, the recording columns in other units ([`RECORDING_UNIT_COLUMNS`]) in
//! `unit_columns`, both re-exported here.

mod formats;
mod unit_columns;

pub use formats::{
    BENDING_COLUMNS, DOMAIN_INPUTS, FORCE_COLUMNS, MARKER_RECORDING_COLUMNS, OGDEN_COLUMNS,
    OGDEN_COORDINATES, OUTPUTS, PREDICTION_INPUT_COLUMNS, PROVENANCE_COLUMNS, QUERY_COLUMNS,
    SNAPSHOT_COLUMNS, SNAPSHOT_COLUMN_NAMES, VALIDATION_GROUPS,
};
pub use unit_columns::{UnitColumn, RECORDING_UNIT_COLUMNS};

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
