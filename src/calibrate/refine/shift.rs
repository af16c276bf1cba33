//! How far a refit moved from a verified set in what the recordings see.

use serde::{Deserialize, Serialize};

use crate::calibrate::objective::{Evaluator, ObservationSet, Recordings, Selection, Weights};
use crate::calibrate::params::ParamSpace;
use crate::calibrate::CalibrateError;
use crate::case::OgdenSet;
use crate::rom::Surrogate;

/// How far a refit moved from a verified set in what the recordings see
/// ([`data_space_shift`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DataSpaceShift {
    /// After which round's retraining.
    pub round: usize,
    /// The verified set.
    pub from: OgdenSet,
    /// The refit.
    pub to: OgdenSet,
    /// Recorded numbers compared (every output the recordings hold, at the calibration's
    /// configurations).
    pub observations: usize,
    /// Largest `|ŷ(to) − ŷ(from)| / σ` over them.
    pub max_abs_z: f64,
    /// Root mean square of the same.
    pub rms_z: f64,
    /// The recorded number that moves most, in words.
    pub worst: String,
    /// `χ²` of every recorded number (weight 1) at `from` and at `to`.
    pub chi2_from: f64,
    /// See `chi2_from`.
    pub chi2_to: f64,
}

impl DataSpaceShift {
    /// In words.
    pub fn describe(&self) -> String {
        format!(
            "through the surrogate retrained after round {}, the refit {} moves the {} recorded \
             numbers by {:.2} σ rms from the verified set {} (at most {:.2} σ: {}); χ² of all \
             of them {:.1} → {:.1}",
            self.round,
            self.to.spec(),
            self.observations,
            self.rms_z,
            self.from.spec(),
            self.max_abs_z,
            self.worst,
            self.chi2_from,
            self.chi2_to
        )
    }
}

/// The unit-box point of `p` in the model's training domain, allowing the 4-digit rounding of
/// a reported set to sit a hair outside it.
fn unit_of(space: &ParamSpace, p: &OgdenSet) -> Result<[f64; 4], CalibrateError> {
    let u = space.unit(p);
    if u.iter().any(|v| !(-1e-3..=1.0 + 1e-3).contains(v)) {
        return Err(CalibrateError::input(
            "material set",
            p.spec(),
            "a set inside the surrogate's training domain",
        ));
    }
    Ok(u.map(|v| v.clamp(0.0, 1.0)))
}

/// How far `to` lies from `from` in what the recordings `rec` see, through `model`: every
/// recorded number (tip Uz and Uy, angle, force, marker components: the outputs `rec` holds)
/// at the configurations `selection` keeps is predicted at both sets, and the difference is
/// measured in its standard deviation (the calibrator's noise model: measurement and the
/// surrogate's own error in quadrature).
///
/// # Errors
/// A set outside the model's training domain (beyond the rounding of a reported set), or
/// observations that cannot be built (see [`ObservationSet::build`]).
pub fn data_space_shift(
    model: &Surrogate,
    rec: &Recordings,
    selection: &Selection,
    from: &OgdenSet,
    to: &OgdenSet,
    round: usize,
) -> Result<DataSpaceShift, CalibrateError> {
    let has_bending = !rec.bending.is_empty();
    let weights = Weights {
        tip: f64::from(u8::from(has_bending)),
        angle: f64::from(u8::from(has_bending)),
        force: f64::from(u8::from(!rec.force.is_empty())),
        markers: f64::from(u8::from(!rec.markers.is_empty())),
    };
    let set = ObservationSet::build(model, rec, &weights, selection)?;
    let space = ParamSpace::training_domain(model)?;
    let mut ev = Evaluator::new(model, &set, space);
    let (ua, ub) = (unit_of(ev.space(), from)?, unit_of(ev.space(), to)?);
    let a = ev.predictions(&ua)?;
    let b = ev.predictions(&ub)?;
    let (mut max, mut sum2, mut worst) = (0.0_f64, 0.0, 0);
    let (mut chi_a, mut chi_b) = (0.0, 0.0);
    for (i, o) in set.obs.iter().enumerate() {
        let sigma = o.sigma();
        let z = (b[i] - a[i]) / sigma;
        chi_a += ((a[i] - o.value) / sigma).powi(2);
        chi_b += ((b[i] - o.value) / sigma).powi(2);
        sum2 += z * z;
        if z.abs() > max {
            max = z.abs();
            worst = i;
        }
    }
    let n = set.obs.len();
    let w = &set.obs[worst];
    Ok(DataSpaceShift {
        round,
        from: *from,
        to: *to,
        observations: n,
        max_abs_z: max,
        rms_z: (sum2 / n.max(1) as f64).sqrt(),
        worst: format!(
            "{} at {}, {:+.3} (σ {:.3})",
            w.output.name(),
            w.config.label(),
            b[worst] - a[worst],
            w.sigma()
        ),
        chi2_from: chi_a,
        chi2_to: chi_b,
    })
}
