//! The reference study's procedure, reproduced for comparison: the four Ogden parameters
//! fitted separately for each configuration `(N, T, P)` to its tip (Uz, Uy) inside a box of
//! ±10 % around the literature set, the spread of the fitted sets, and one set fitted in the
//! same box to all the configurations at once.
//!
//! Two numbers per configuration cannot determine four parameters: each per-configuration fit
//! lands somewhere on a three-dimensional set of equally good parameters (or on the box), and
//! where depends on the start. That is the scatter the study found; the spread reported here
//! shows it, and the one-set fit shows what a single material achieves in the same box.

use serde::{Deserialize, Serialize};

use super::baseline::in_paper_nine;
use super::experiments::bending_error;
use super::objective::{Config, Evaluator, ObservationSet, Recordings, Selection, Weights};
use super::optimise::{multistart, MultistartSettings};
use super::params::ParamSpace;
use super::CalibrateError;
use crate::case::material::NAMES;
use crate::case::OgdenSet;
use crate::case::Query;
use crate::rom::Surrogate;

/// One per-configuration fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConfigFit {
    /// The configuration.
    pub config: Config,
    /// Whether it is one of the reference study's nine (T and P together).
    #[serde(alias = "l9")]
    pub paper_nine: bool,
    /// The fitted set.
    pub params: OgdenSet,
    /// BE with the literature set (mm).
    pub be_literature_mm: f64,
    /// BE with the fitted set (mm).
    pub be_fitted_mm: f64,
    /// BE with the one set fitted to all configurations in the same box (mm).
    pub be_one_set_mm: f64,
    /// Parameters that end on the ±10 % box.
    pub on_box: Vec<String>,
}

/// Spread of one parameter over the per-configuration sets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// Parameter name.
    pub name: String,
    /// Mean.
    pub mean: f64,
    /// Standard deviation.
    pub std: f64,
    /// Coefficient of variation `std / |mean|`.
    pub cv: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// How many fits end on the box for this parameter.
    pub on_box: usize,
}

/// Errors over a set of configurations.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BeSummary {
    /// Configurations.
    pub n: usize,
    /// Mean BE (mm).
    pub mean_mm: f64,
    /// Median BE (mm).
    pub median_mm: f64,
}

/// The study's procedure and its comparison with one set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PerConfigurationStudy {
    /// Relative half-width of the box (0.1 = ±10 %).
    pub fraction: f64,
    /// The box.
    pub space: ParamSpace,
    /// The per-configuration fits.
    pub fits: Vec<ConfigFit>,
    /// Spread of each parameter.
    pub spread: Vec<Spread>,
    /// The one set fitted to all configurations in the same box.
    pub one_set: OgdenSet,
    /// BE summaries (all configurations, and the reference study's nine): literature, per configuration,
    /// one set.
    pub all: [BeSummary; 3],
    /// The same over the reference study's nine.
    #[serde(alias = "l9")]
    pub paper_nine: [BeSummary; 3],
}

fn summary(v: &[f64]) -> BeSummary {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    let median = if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    };
    BeSummary {
        n,
        mean_mm: s.iter().sum::<f64>() / n.max(1) as f64,
        median_mm: median,
    }
}

/// Runs the procedure over the selected, not excluded bending configurations.
///
/// # Errors
/// A box that leaves the training domain, an empty selection, or a surrogate error.
pub fn per_configuration(
    model: &Surrogate,
    rec: &Recordings,
    center: &OgdenSet,
    fraction: f64,
    selection: &Selection,
    ms: &MultistartSettings,
) -> Result<PerConfigurationStudy, CalibrateError> {
    let domain = ParamSpace::training_domain(model)?;
    let space = ParamSpace::raw_box(center, fraction, &domain)?;
    per_configuration_in(model, rec, center, fraction, space, selection, ms)
}

/// [`per_configuration`] in `space`, the box `center · (1 ± fraction)` already built and
/// checked against the model's domain ([`ParamSpace::raw_box_in`]).
///
/// # Errors
/// An empty selection, or a surrogate error.
pub fn per_configuration_in(
    model: &Surrogate,
    rec: &Recordings,
    center: &OgdenSet,
    fraction: f64,
    space: ParamSpace,
    selection: &Selection,
    ms: &MultistartSettings,
) -> Result<PerConfigurationStudy, CalibrateError> {
    let tip = Weights::default();
    let all = ObservationSet::build(model, rec, &tip, selection)?;
    let local = MultistartSettings {
        starts: 8,
        seed: ms.seed,
        local: ms.local,
    };
    let center_u = space.unit(center);
    // one set for all
    let ev_all = Evaluator::new(model, &all, space.clone());
    let one = multistart(&ev_all, &[center_u], &local)?;
    let one_set = space.ogden(&one[0].u)?;
    let levels = |f: &dyn Fn(&Config) -> f64| {
        let mut v: Vec<f64> = all.configs.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        v
    };
    let ln: Vec<usize> = levels(&|c| f64::from(c.n_bellows))
        .into_iter()
        .map(|v| v as usize)
        .collect();
    let lt = levels(&|c| c.wall_thickness_mm);
    let lp = levels(&|c| c.pressure_bar);
    let mut fits = Vec::new();
    let mut pred = model.new_prediction();
    for c in &all.configs {
        let obs: Vec<_> = all
            .obs
            .iter()
            .filter(|o| o.config.same(c))
            .cloned()
            .collect();
        let set = ObservationSet::from_observations(obs);
        let ev = Evaluator::new(model, &set, space.clone());
        let f = multistart(&ev, &[center_u], &local)?;
        let params = space.ogden(&f[0].u)?;
        let (uz, uy) = (set.obs[0].value, set.obs[1].value);
        let mut be = |p: &OgdenSet| -> Result<f64, CalibrateError> {
            let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, *p);
            model.predict_scalars_into(&q, &mut pred)?;
            Ok(bending_error(uz, uy, pred.tip_uz_mm(), pred.tip_uy_mm()))
        };
        let on_box = (0..4)
            .filter(|&i| f[0].u[i] <= 1e-9 || f[0].u[i] >= 1.0 - 1e-9)
            .map(|i| NAMES[i].to_string())
            .collect();
        fits.push(ConfigFit {
            config: *c,
            paper_nine: in_paper_nine(
                &ln,
                &lt,
                &lp,
                c.n_bellows as usize,
                c.wall_thickness_mm,
                c.pressure_bar,
            ) == Some(true),
            be_literature_mm: be(center)?,
            be_fitted_mm: be(&params)?,
            be_one_set_mm: be(&one_set)?,
            params,
            on_box,
        });
    }
    let spread = (0..4)
        .map(|i| {
            let v: Vec<f64> = fits.iter().map(|f| f.params.as_array()[i]).collect();
            let n = v.len() as f64;
            let mean = v.iter().sum::<f64>() / n;
            let std =
                (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
            Spread {
                name: NAMES[i].to_string(),
                mean,
                std,
                cv: std / mean.abs(),
                min: v.iter().copied().fold(f64::INFINITY, f64::min),
                max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                on_box: fits
                    .iter()
                    .filter(|f| f.on_box.iter().any(|b| b == NAMES[i]))
                    .count(),
            }
        })
        .collect();
    let col = |nine_only: bool, k: usize| -> Vec<f64> {
        fits.iter()
            .filter(|f| !nine_only || f.paper_nine)
            .map(|f| [f.be_literature_mm, f.be_fitted_mm, f.be_one_set_mm][k])
            .collect()
    };
    Ok(PerConfigurationStudy {
        fraction,
        space,
        spread,
        one_set,
        all: [0, 1, 2].map(|k| summary(&col(false, k))),
        paper_nine: [0, 1, 2].map(|k| summary(&col(true, k))),
        fits,
    })
}
