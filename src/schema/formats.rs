//! The ordered columns of each file format.

use super::{
    names, Quantity, ALPHA1, ALPHA2, ANGLE, ANGLE_STD, BULK_RATIO, CASE_ID, CODE_VERSION,
    CONVERGED, CUTBACKS, ELEMENT_SIZE, ERROR, FORCE, FORCE_STD, GRAVITY, MARKER, MARKERS,
    MARKER_RECORDED_STD, MARKER_RECORDED_UY, MARKER_RECORDED_UZ, MARKER_UY, MARKER_UZ, MESH,
    MIN_GAP, MU0, MU1, MU2, NEWTON_ITERATIONS, N_BELLOWS, PRESSURE, RESIDUAL, SOLVER_RTOL,
    SUBSTEPS, TERM1_SHARE, TIP_UY, TIP_UZ, WALL_THICKNESS,
};

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
/// [`MATERIAL`](super::MATERIAL) column; the raw calibration parameters).
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
