//! Settings of an identification: the unknowns, the start, the FE mesh, the iteration budget,
//! the noise model's model-form floor; and how the iteration stops.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::correction::MeshCorrection;
use super::unknown::{JointPoint, Unknown};
use crate::calibrate::objective::Exclusion;
use crate::calibrate::CalibrateError;
use crate::fe::mesh::MeshOptions;

/// Settings of an identification.
#[derive(Clone, Debug)]
pub struct JointSettings {
    /// The unknowns.
    pub unknowns: Vec<Unknown>,
    /// Where it starts.
    pub start: JointPoint,
    /// The FE mesh.
    pub mesh: MeshOptions,
    /// Largest number of FE sweeps (each one evaluation of `θ` with its Jacobian).
    pub max_sweeps: usize,
    /// Initial damping `λ` (relative to `diag(JᵀJ)`).
    pub lambda0: f64,
    /// Initial trust radius: the largest move of an unknown in one step, as a fraction of its
    /// range ([`bounded_lm`](super::lm::bounded_lm)).
    pub max_step: f64,
    /// The model-form floor of the noise model.
    pub model_sigma: ModelSigma,
    /// Cache directory of the ramps (resumable).
    pub cache: Option<PathBuf>,
    /// Start each sweep's ramps from the previous sweep's converged states of the same design
    /// and rig, moved by their displacement sensitivities ([`crate::fe::campaign::WarmPool`]):
    /// the same answers to the solver's tolerance in a fraction of the Newton iterations. The
    /// first sweep, and the ramps of a sweep that follows one read from the cache, start cold.
    pub warm_start: bool,
    /// Recorded rows left out of the fit (by the user, or flagged by the data checks,
    /// [`crate::calibrate::checks`]): their FE values are still computed and reported, marked,
    /// and the means are given without and with them.
    pub exclude: Vec<Exclusion>,
    /// Fit what a finer mesh would give: the FE values of every configuration are shifted by
    /// the difference between the two meshes at a reference point ([`MeshCorrection`]).
    /// `None`: the values of [`mesh`](Self::mesh) as they are.
    pub correction: Option<MeshCorrection>,
}

/// The model-form floor of the identification's noise model: added in quadrature to each
/// recorded scatter, so that no output's small recorded scatter lets it outweigh the others
/// in `χ²` beyond the accuracy the model can have.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelSigma {
    /// On each tip coordinate (mm).
    pub tip_mm: f64,
    /// On the blocked force (N).
    pub force_n: f64,
}

impl Default for ModelSigma {
    /// 2 mm on a tip coordinate (a 3 mm tip BE), 0.15 N on the force: the targets' scale.
    fn default() -> Self {
        ModelSigma {
            tip_mm: 2.0,
            force_n: 0.15,
        }
    }
}

impl ModelSigma {
    /// Checks that both are finite and non-negative.
    ///
    /// # Errors
    /// [`CalibrateError::Input`] naming the field.
    pub fn validate(&self) -> Result<(), CalibrateError> {
        for (name, v) in [
            ("model sigma tip_mm", self.tip_mm),
            ("model sigma force_n", self.force_n),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(CalibrateError::input(name, v, "a finite value ≥ 0"));
            }
        }
        Ok(())
    }
}

/// How the identification stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointStop {
    /// `χ²` fell by less than a relative 1e-3 over an accepted step, or the next step, not
    /// held by the trust box, promises a decrease below the minimum gain
    /// ([`MIN_GAIN_CHI2`] for the identification).
    Converged,
    /// The damping grew past 1e8 without a successful step.
    NoDescent,
    /// The sweep budget ran out.
    Budget,
}

/// The identification stops when its next step, not held by the trust box, promises a
/// decrease of `χ²` (in units of the noise model's variances) below this: a hundredth of the
/// `Δχ² = 1` that bounds a parameter's one-σ interval, not worth a sweep.
pub const MIN_GAIN_CHI2: f64 = 0.01;
