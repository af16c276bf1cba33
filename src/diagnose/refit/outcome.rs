//! What Model and show is asked and what it reports: the settings, each effect's size,
//! the fit before and after, the held-out designs and the FE rounds.

use serde::{Deserialize, Serialize};

use crate::case::OgdenSet;
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;

/// Settings of [`refit`](super::refit()).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefitSettings {
    /// The effects to add to the material (one or more).
    pub effects: Vec<Effect>,
    /// Level of the confidence intervals (0.95).
    pub confidence: f64,
    /// Whether to leave each design out in turn.
    pub held_out: bool,
}

impl RefitSettings {
    /// Refit with `effects`, 95 % intervals, designs held out.
    pub fn new(effects: Vec<Effect>) -> Self {
        Self {
            effects,
            confidence: 0.95,
            held_out: true,
        }
    }

    pub(crate) fn validate(&self) -> Result<(), DiagnoseError> {
        if self.effects.is_empty() {
            return Err(DiagnoseError::input(
                "refit effects",
                "none",
                "at least one effect of the library",
            ));
        }
        for (i, e) in self.effects.iter().enumerate() {
            if self.effects[..i].contains(e) {
                return Err(DiagnoseError::input(
                    "refit effects",
                    e.name(),
                    "each effect at most once",
                ));
            }
        }
        if !(self.confidence > 0.5 && self.confidence < 1.0) {
            return Err(DiagnoseError::input(
                "confidence",
                self.confidence,
                "a level in (0.5, 1)",
            ));
        }
        Ok(())
    }
}

/// One effect's refitted size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EffectSize {
    /// The effect.
    pub effect: String,
    /// Its unit.
    pub unit: String,
    /// Its value (the sweep's value + estimate), what `--effect NAME=VALUE` takes.
    pub value: f64,
    /// Its estimate from the sweep's value (the neutral value unless the sweep fixed it,
    /// [`crate::calibrate::baseline::SweepSensitivities::base`]).
    pub estimate: f64,
    /// Standard error.
    pub std_error: f64,
    /// Confidence interval of the value `[lo, hi]`.
    pub interval: (f64, f64),
    /// A library bound that stopped the fit, in words.
    pub at_bound: Option<String>,
}

/// How well a set of predictions meets the recordings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quality {
    /// Cells.
    pub n_cells: usize,
    /// `Σ z²`.
    pub chi2: f64,
    /// Mean tip bending error over the configurations with tip Uz and Uy (mm; none without).
    pub mean_be_mm: Option<f64>,
    /// Mean force error, predicted − recorded (N; none without force cells).
    pub mean_force_error_n: Option<f64>,
    /// Mean absolute force error (N).
    pub mean_abs_force_error_n: Option<f64>,
    /// Root mean square `z` per output family (`tip Uz`, …).
    pub rms_z: Vec<(String, f64)>,
}

/// One fit of the material (and effects).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FitSummary {
    /// The material.
    pub material: OgdenSet,
    /// Effect values (neutral + estimate), in the order of the settings (empty: material only).
    pub effects: Vec<f64>,
    /// Quality on the cells fitted.
    pub quality: Quality,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// How the fit stopped.
    pub stop: String,
    /// Bounds active at the optimum, in words.
    pub active_bounds: Vec<String>,
}

/// A design left out of both fits, and how each predicts it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeldOutDesign {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// The material-only fit on the rest, on this design.
    pub before: Quality,
    /// The material + effect fit on the rest, on this design.
    pub after: Quality,
    /// The effects' values fitted without this design.
    pub effects: Vec<f64>,
}

/// The held-out comparison, every design in turn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeldOut {
    /// Each design.
    pub designs: Vec<HeldOutDesign>,
    /// Mean tip BE over every held-out configuration, material only (mm).
    pub mean_be_before_mm: Option<f64>,
    /// The same with the effect(s).
    pub mean_be_after_mm: Option<f64>,
    /// Mean absolute force error over every held-out configuration, material only (N).
    pub mean_abs_force_error_before_n: Option<f64>,
    /// The same with the effect(s).
    pub mean_abs_force_error_after_n: Option<f64>,
    /// `Σ z²` over every held-out cell, material only.
    pub chi2_before: f64,
    /// The same with the effect(s).
    pub chi2_after: f64,
}

/// What the Model-and-show stage found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Refit {
    /// Cells used (those with sensitivities).
    pub n_cells: usize,
    /// Where the linearisation comes from (material and mesh of the sweep).
    pub linearised_at: String,
    /// The effects' sizes.
    pub effects: Vec<EffectSize>,
    /// Material alone, every used cell.
    pub before: FitSummary,
    /// Material and effect(s).
    pub after: FitSummary,
    /// The nested F statistic of adding the effect(s).
    pub f: f64,
    /// Its p-value.
    pub p_value: f64,
    /// The mean tip BE a perfect model would show under the recordings' noise (mm).
    pub noise_be_mm: Option<f64>,
    /// Every design left out in turn (none if not asked for).
    pub held_out: Option<HeldOut>,
    /// The FE model with the effect(s) on at the refitted values, if run.
    pub fe: Vec<FeRound>,
    /// The stage in words.
    pub verdict: String,
}

/// One round of the FE confirmation ([`confirm_with_fe`](super::confirm_with_fe)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeRound {
    /// Material the FE ran with.
    pub material: OgdenSet,
    /// Effect values the FE ran with.
    pub effects: Vec<f64>,
    /// The FE predictions against the recordings.
    pub quality: Quality,
    /// Root mean square of (FE − linearised prediction)/σ over the used cells.
    pub rms_fe_minus_linear: f64,
    /// Largest |FE − linearised|/σ, and where.
    pub worst: (f64, String),
    /// FE ramps run (the others came from the cache).
    pub ramps_run: usize,
    /// Each used cell's `(FE − recorded)/σ`, in the refit's cell order (the FE's own
    /// prediction where its ramp reached the cell's pressure, the linearised one elsewhere).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub z: Vec<f64>,
    /// Ramps that stopped early, in words.
    pub failed: Vec<String>,
}
