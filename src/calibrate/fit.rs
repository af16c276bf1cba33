//! The calibration pipeline: checks → observations → multistart fit → identifiability →
//! comparison with the literature set (→ the study's per-configuration procedure).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::baseline::{summarize, BaselineRow, BaselineSummary};
use super::checks::{check, DataFlag};
use super::experiments::bending_error;
use super::identify::{identify, Identifiability, IdentifySettings};
use super::objective::{
    Config, Evaluator, Exclusion, Observation, ObservationSet, Output, Recording, Recordings,
    Selection, Term, Weights,
};
use super::optimise::{multistart, Bound, LocalFit, MultistartSettings, Stop};
use super::params::{BoxFit, ParamSpace};
use super::study::{per_configuration_in, PerConfigurationStudy};
use super::CalibrateError;
use crate::case::Query;
use crate::case::{MaterialCoords, OgdenSet};
use crate::rom::{Prediction, Surrogate};

/// Settings of [`calibrate`].
#[derive(Clone, Debug)]
pub struct CalibrationSettings {
    /// Terms of the objective and their weights.
    pub weights: Weights,
    /// Configurations used and excluded.
    pub selection: Selection,
    /// Also exclude every row the data checks flag (listed in the report).
    pub exclude_flagged: bool,
    /// Starts and local settings.
    pub multistart: MultistartSettings,
    /// Profiles and confidence level.
    pub identify: IdentifySettings,
    /// The literature set: compared against, and one more start when the model's domain holds it.
    pub literature: OgdenSet,
    /// Run the study's per-configuration procedure in this relative box around the
    /// literature set (0.1 = ±10 %).
    pub per_configuration: Option<f64>,
}

impl Default for CalibrationSettings {
    fn default() -> Self {
        CalibrationSettings {
            weights: Weights::default(),
            selection: Selection::default(),
            exclude_flagged: false,
            multistart: MultistartSettings::default(),
            identify: IdentifySettings::default(),
            literature: OgdenSet {
                mu1_mpa: 1.13,
                alpha1: 3.11,
                mu2_mpa: -13.17,
                alpha2: -0.6,
            },
            per_configuration: None,
        }
    }
}

/// One start's end point, in words a reader can scan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StartReport {
    /// Where it started.
    pub start: OgdenSet,
    /// Where it ended.
    pub end: OgdenSet,
    /// `χ²` at the end.
    pub chi2: f64,
    /// Iterations.
    pub iterations: usize,
    /// Why it stopped.
    pub stop: Stop,
    /// Coordinates that end on a bound of the training domain (name and side).
    pub active_bounds: Vec<String>,
    /// Minimum it reached (0 = the best).
    pub minimum: usize,
}

/// Predictions of one configuration with the literature and the calibrated set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConfigRow {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Whether the row took part in the fit.
    pub fitted: bool,
    /// Measured tip Uz (mm).
    pub uz_exp_mm: f64,
    /// Measured tip Uy (mm).
    pub uy_exp_mm: f64,
    /// Measured angle (deg).
    pub angle_exp_deg: f64,
    /// Measured blocked force (N); NaN when not recorded.
    pub force_exp_n: f64,
    /// Surrogate with the literature set: tip Uz (mm).
    pub uz_lit_mm: f64,
    /// … tip Uy (mm).
    pub uy_lit_mm: f64,
    /// … angle (deg).
    pub angle_lit_deg: f64,
    /// … force (N).
    pub force_lit_n: f64,
    /// Surrogate with the calibrated set: tip Uz (mm).
    pub uz_cal_mm: f64,
    /// … tip Uy (mm).
    pub uy_cal_mm: f64,
    /// … angle (deg).
    pub angle_cal_deg: f64,
    /// … force (N).
    pub force_cal_n: f64,
    /// The surrogate's predictive std of the calibrated tip Uz (mm).
    pub uz_cal_std_mm: f64,
    /// … of the calibrated force (N).
    pub force_cal_std_n: f64,
    /// BE with the literature set (mm).
    pub be_lit_mm: f64,
    /// BE with the calibrated set (mm).
    pub be_cal_mm: f64,
}

/// One residual at the optimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResidualRow {
    /// Configuration.
    pub config: Config,
    /// Output.
    pub output: Output,
    /// Recorded value.
    pub recorded: f64,
    /// Predicted (calibrated).
    pub predicted: f64,
    /// `σ` used.
    pub sigma: f64,
    /// `(predicted − recorded) / σ`.
    pub standardised: f64,
    /// Share of `χ²` (weights included).
    pub chi2_share: f64,
}

/// The calibration report.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Calibration {
    /// Model file checksum and provenance.
    pub model: String,
    /// Every file read: the recordings (and, added by the caller that read it, the model),
    /// each with its checksum and whether it was a documented default.
    #[serde(default)]
    pub inputs: Vec<super::inputs::InputFile>,
    /// The objective (`tip=1,force=0.5`).
    pub objective: String,
    /// Observations fitted.
    pub n_observations: usize,
    /// Configurations fitted.
    pub n_configurations: usize,
    /// The box the fit moved in (the surrogate's training domain).
    pub domain: ParamSpace,
    /// The best set.
    pub best: OgdenSet,
    /// Its sampling coordinates.
    pub best_coords: MaterialCoords,
    /// `χ²` at the best set.
    pub chi2: f64,
    /// `χ²` of the literature set (same objective).
    pub chi2_literature: f64,
    /// The literature set.
    pub literature: OgdenSet,
    /// Bounds active at the best set.
    pub active_bounds: Vec<String>,
    /// The same bounds, by coordinate and side (a report written before the field reads as
    /// none: its words are in `active_bounds`).
    #[serde(default)]
    pub pressed: Vec<ActiveBound>,
    /// Every start's end point, best first.
    pub starts: Vec<StartReport>,
    /// Distinct minima found.
    pub minima: usize,
    /// Standard errors, correlations, directions, profiles.
    pub identifiability: Identifiability,
    /// Literature vs calibrated, per configuration (every recorded one).
    pub configurations: Vec<ConfigRow>,
    /// Error summary with the literature set (surrogate).
    pub literature_summary: BaselineSummary,
    /// Error summary with the calibrated set (surrogate).
    pub calibrated: BaselineSummary,
    /// Residuals at the optimum, largest share of `χ²` first.
    pub residuals: Vec<ResidualRow>,
    /// Data-check flags.
    pub flags: Vec<DataFlag>,
    /// Rows left out, and why.
    pub excluded: Vec<Exclusion>,
    /// The study's procedure, if asked for.
    pub per_configuration: Option<PerConfigurationStudy>,
    /// Why the study's procedure was asked for and not run: its box around the literature
    /// set leaves the model's training domain (a model trained over another material box).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub per_configuration_skipped: Option<String>,
    /// Wall time of the fit and the analysis (s).
    pub wall_time_s: f64,
}

/// A bound of the box the fit moved in on which the optimum sits, with the gradient of `χ²`
/// pushing outwards: the box truncates the optimum there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ActiveBound {
    /// Index of the box coordinate ([`ParamSpace::names`] order: `μ0, s, α₁, α₂` for the
    /// training domain).
    pub coordinate: usize,
    /// Its name.
    pub name: String,
    /// Which bound.
    pub side: Bound,
    /// The bound's physical value (`μ0` in MPa).
    pub value: f64,
}

impl std::fmt::Display for ActiveBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let side = match self.side {
            Bound::Lower => "lower",
            Bound::Upper => "upper",
        };
        write!(f, "{} at its {side} bound {}", self.name, self.value)
    }
}

/// The coordinates of `space` on which `active` marks a bound.
fn active_bounds(space: &ParamSpace, active: &[Option<Bound>; 4]) -> Vec<ActiveBound> {
    let names = space.names();
    active
        .iter()
        .enumerate()
        .filter_map(|(i, a)| {
            a.map(|side| ActiveBound {
                coordinate: i,
                name: names[i].to_string(),
                side,
                value: space.physical(
                    i,
                    match side {
                        Bound::Lower => 0.0,
                        Bound::Upper => 1.0,
                    },
                ),
            })
        })
        .collect()
}

/// The active bounds in words (`alpha1 at its lower bound 1.51`).
fn bound_names(space: &ParamSpace, active: &[Option<Bound>; 4]) -> Vec<String> {
    active_bounds(space, active)
        .iter()
        .map(ToString::to_string)
        .collect()
}

/// Runs the calibration (see the [module docs](super)); `progress` gets a line per stage.
///
/// # Errors
/// Bad recordings or settings ([`ObservationSet::build`]), a literature set outside the
/// training domain, or a surrogate error.
pub fn calibrate(
    model: &Surrogate,
    rec: &Recordings,
    s: &CalibrationSettings,
    progress: &dyn Fn(&str),
) -> Result<Calibration, CalibrateError> {
    let t0 = Instant::now();
    let flags = check(rec);
    let mut selection = s.selection.clone();
    if s.exclude_flagged {
        for f in &flags {
            if !selection.exclude.iter().any(|e| e.config.same(&f.config)) {
                selection.exclude.push(f.exclusion());
            }
        }
    }
    let set = ObservationSet::build(model, rec, &s.weights, &selection)?;
    if set.len() <= 4 {
        return Err(CalibrateError::input(
            "observations",
            format!("{} at {} configurations", set.len(), set.configs.len()),
            "more than the 4 Ogden parameters (more recordings or objective terms)",
        ));
    }
    let domain = ParamSpace::training_domain(model)?;
    progress(&format!(
        "fitting {} observations at {} configurations ({}), {} starts",
        set.len(),
        set.configs.len(),
        s.weights.describe(),
        s.multistart.starts + 1
    ));
    let ev = Evaluator::new(model, &set, domain.clone());
    let lit_inside = domain.contains(&s.literature);
    let extra: Vec<[f64; 4]> = if lit_inside {
        vec![domain.unit(&s.literature)]
    } else {
        Vec::new()
    };
    let fits = multistart(&ev, &extra, &s.multistart)?;
    let best_fit: &LocalFit = &fits[0];
    let best = domain.ogden(&best_fit.u)?;
    let chi2_literature = if lit_inside {
        ev.clone().chi2(&domain.unit(&s.literature))?
    } else {
        f64::NAN
    };
    let starts = fits
        .iter()
        .map(|f| {
            Ok(StartReport {
                start: domain.ogden(&f.start)?,
                end: domain.ogden(&f.u)?,
                chi2: f.chi2,
                iterations: f.iterations,
                stop: f.stop,
                active_bounds: bound_names(&domain, &f.active),
                minimum: f.minimum,
            })
        })
        .collect::<Result<Vec<_>, CalibrateError>>()?;
    let minima = fits.iter().map(|f| f.minimum).max().unwrap_or(0) + 1;
    progress("identifiability: standard errors, correlations, profiles");
    let candidates = extra_candidates(model, rec, &set, &s.weights);
    let identifiability = identify(&ev, &best_fit.u, best_fit.chi2, &s.identify, &candidates)?;
    let residuals = residual_rows(&ev, &best_fit.u)?;
    let configurations = compare(model, rec, &set, &s.literature, &best)?;
    let literature_summary = summarize(&as_baseline(&configurations, true));
    let calibrated = summarize(&as_baseline(&configurations, false));
    // the study's procedure fits each configuration within ±frac of the literature set: a
    // model whose training domain does not hold that box cannot replicate it, which is said,
    // not an error after the fit
    let mut per_configuration_skipped = None;
    let per_configuration = match s.per_configuration {
        Some(frac) => match ParamSpace::raw_box_in(&s.literature, frac, &domain)? {
            BoxFit::Inside(space) => {
                progress("the study's procedure: per-configuration fits");
                Some(per_configuration_in(
                    model,
                    rec,
                    &s.literature,
                    frac,
                    space,
                    &selection,
                    &s.multistart,
                )?)
            }
            BoxFit::Outside { .. } => {
                per_configuration_skipped = Some(format!(
                    "its box, ±{:.0} % of the literature set {}, leaves the model's training \
                     domain",
                    100.0 * frac,
                    s.literature.spec()
                ));
                None
            }
        },
        None => None,
    };
    Ok(Calibration {
        model: format!(
            "{} ({} training cases, {})",
            model.checksum()?,
            model.training.n_cases,
            model.training.source
        ),
        inputs: rec.files.clone(),
        objective: s.weights.describe(),
        n_observations: set.len(),
        n_configurations: set.configs.len(),
        domain: domain.clone(),
        best,
        best_coords: best.coords(),
        chi2: best_fit.chi2,
        chi2_literature,
        literature: s.literature,
        active_bounds: bound_names(&domain, &best_fit.active),
        pressed: active_bounds(&domain, &best_fit.active),
        starts,
        minima,
        identifiability,
        configurations,
        literature_summary,
        calibrated,
        residuals,
        flags,
        excluded: set.excluded.clone(),
        per_configuration,
        per_configuration_skipped,
        wall_time_s: t0.elapsed().as_secs_f64(),
    })
}

fn residual_rows(ev: &Evaluator<'_>, u: &[f64; 4]) -> Result<Vec<ResidualRow>, CalibrateError> {
    let mut e = ev.clone();
    let pred = e.predictions(u)?;
    let set = ev.set();
    let chi2: f64 = set
        .obs
        .iter()
        .zip(&pred)
        .map(|(o, p)| o.weight * ((p - o.value) / o.sigma()).powi(2))
        .sum();
    let mut rows: Vec<ResidualRow> = set
        .obs
        .iter()
        .zip(&pred)
        .map(|(o, &p)| {
            let z = (p - o.value) / o.sigma();
            ResidualRow {
                config: o.config,
                output: o.output,
                recorded: o.value,
                predicted: p,
                sigma: o.sigma(),
                standardised: z,
                chi2_share: o.weight * z * z / chi2.max(1e-300),
            }
        })
        .collect();
    rows.sort_by(|a, b| b.chi2_share.total_cmp(&a.chi2_share));
    Ok(rows)
}

/// Surrogate predictions (all outputs, with std) of one configuration and set.
fn predict(
    model: &Surrogate,
    pred: &mut Prediction,
    c: &Config,
    p: &OgdenSet,
) -> Result<(), CalibrateError> {
    let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, *p);
    model.predict_with_std_into(&q, pred)?;
    Ok(())
}

/// Literature vs calibrated at every recorded bending configuration.
fn compare(
    model: &Surrogate,
    rec: &Recordings,
    set: &ObservationSet,
    lit: &OgdenSet,
    cal: &OgdenSet,
) -> Result<Vec<ConfigRow>, CalibrateError> {
    let mut pl = model.new_prediction();
    let mut pc = model.new_prediction();
    let mut rows = Vec::new();
    for r in &rec.bending {
        let c = Config::of(r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
        if model
            .check_query(&Query::new(
                c.n_bellows,
                c.wall_thickness_mm,
                c.pressure_bar,
                *lit,
            ))
            .is_err()
            || !model.n_allowed.contains(&c.n_bellows)
        {
            continue;
        }
        predict(model, &mut pl, &c, lit)?;
        predict(model, &mut pc, &c, cal)?;
        let f_exp = rec
            .force
            .iter()
            .find(|f| {
                f.n_bellows == r.n_bellows
                    && f.wall_thickness_mm == r.wall_thickness_mm
                    && f.pressure_bar == r.pressure_bar
            })
            .map_or(f64::NAN, |f| f.force_n);
        rows.push(ConfigRow {
            n_bellows: c.n_bellows,
            wall_thickness_mm: c.wall_thickness_mm,
            pressure_bar: c.pressure_bar,
            fitted: set.configs.iter().any(|k| k.same(&c)),
            uz_exp_mm: r.tip_uz_mm,
            uy_exp_mm: r.tip_uy_mm,
            angle_exp_deg: r.angle_deg,
            force_exp_n: f_exp,
            uz_lit_mm: pl.tip_uz_mm(),
            uy_lit_mm: pl.tip_uy_mm(),
            angle_lit_deg: pl.angle_deg(),
            force_lit_n: pl.force_n(),
            uz_cal_mm: pc.tip_uz_mm(),
            uy_cal_mm: pc.tip_uy_mm(),
            angle_cal_deg: pc.angle_deg(),
            force_cal_n: pc.force_n(),
            uz_cal_std_mm: pc.std[crate::rom::Q_TIP_UZ],
            force_cal_std_n: pc.std[crate::rom::Q_FORCE],
            be_lit_mm: bending_error(r.tip_uz_mm, r.tip_uy_mm, pl.tip_uz_mm(), pl.tip_uy_mm()),
            be_cal_mm: bending_error(r.tip_uz_mm, r.tip_uy_mm, pc.tip_uz_mm(), pc.tip_uy_mm()),
        });
    }
    Ok(rows)
}

/// The rows as a baseline table (literature or calibrated columns), for the shared summary.
pub fn as_baseline(rows: &[ConfigRow], literature: bool) -> Vec<BaselineRow> {
    rows.iter()
        .map(|r| {
            let (uz, uy, a, f) = if literature {
                (r.uz_lit_mm, r.uy_lit_mm, r.angle_lit_deg, r.force_lit_n)
            } else {
                (r.uz_cal_mm, r.uy_cal_mm, r.angle_cal_deg, r.force_cal_n)
            };
            BaselineRow {
                n_bellows: r.n_bellows as usize,
                wall_thickness_mm: r.wall_thickness_mm,
                pressure_bar: r.pressure_bar,
                uz_exp_mm: r.uz_exp_mm,
                uz_sim_mm: uz,
                uy_exp_mm: r.uy_exp_mm,
                uy_sim_mm: uy,
                angle_exp_deg: r.angle_exp_deg,
                angle_sim_deg: a,
                be_mm: bending_error(r.uz_exp_mm, r.uy_exp_mm, uz, uy),
                force_exp_n: r.force_exp_n,
                force_sim_n: f,
                force_error_n: f - r.force_exp_n,
                error: String::new(),
            }
        })
        .collect()
}

/// Candidate extra measurements (for [`identify`]): their outputs at plausible noise levels.
fn extra_candidates(
    model: &Surrogate,
    rec: &Recordings,
    set: &ObservationSet,
    w: &Weights,
) -> Vec<(String, ObservationSet)> {
    let tip_sigma: Vec<f64> = set
        .obs
        .iter()
        .filter(|o| o.output.term() == Term::Tip)
        .map(|o| o.sigma_meas)
        .collect();
    let tip_s = if tip_sigma.is_empty() {
        3.0
    } else {
        tip_sigma.iter().sum::<f64>() / tip_sigma.len() as f64
    };
    let force_s = if rec.force.is_empty() {
        0.05
    } else {
        rec.force.iter().map(|f| f.force_std_n).sum::<f64>() / rec.force.len() as f64
    };
    let mut designs: Vec<(u32, f64)> = set
        .configs
        .iter()
        .map(|c| (c.n_bellows, c.wall_thickness_mm))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    let obs = |c: Config, o: Output, sigma: f64| Observation {
        config: c,
        output: o,
        value: 0.0,
        sigma_meas: sigma,
        sigma_model: 0.0,
        weight: 1.0,
        source: "candidate".into(),
    };
    let cfg = |n: u32, t: f64, p: f64| Config {
        n_bellows: n,
        wall_thickness_mm: t,
        pressure_bar: p,
    };
    let mut out: Vec<(String, Vec<Observation>)> = Vec::new();
    if w.force == 0.0 {
        out.push((
            format!("blocked force at the fitted configurations (σ {force_s:.3} N)"),
            set.configs
                .iter()
                .map(|&c| obs(c, Output::Force, force_s))
                .collect(),
        ));
    }
    if w.markers == 0.0 {
        let mut v = Vec::new();
        for &c in &set.configs {
            for k in 1..=8u8 {
                let s = (tip_s * f64::from(k) / 9.0).max(0.3);
                v.push(obs(c, Output::MarkerUz(k), s));
                v.push(obs(c, Output::MarkerUy(k), s));
            }
        }
        out.push((
            "markers 1–8 along the bottom face at the fitted configurations (σ ∝ distance from the support)".into(),
            v,
        ));
    }
    let p_max = *model.pressures.last().unwrap_or(&3.5);
    out.push((
        format!("tip at {p_max} bar for each fitted design (σ {tip_s:.1} mm)"),
        designs
            .iter()
            .flat_map(|&(n, t)| {
                [Output::TipUz, Output::TipUy].map(|o| obs(cfg(n, t, p_max), o, tip_s))
            })
            .collect(),
    ));
    out.push((
        format!("tip at 0.5 bar for each fitted design (σ {tip_s:.1} mm)"),
        designs
            .iter()
            .flat_map(|&(n, t)| {
                [Output::TipUz, Output::TipUy].map(|o| obs(cfg(n, t, 0.5), o, tip_s))
            })
            .collect(),
    ));
    let t_range = (model.inputs[1].min, model.inputs[1].max);
    let t_edge = [
        (t_range.0 * 10.0).ceil() / 10.0,
        (t_range.1 * 10.0).floor() / 10.0,
    ];
    let mut v = Vec::new();
    for &n in &model.n_allowed {
        for t in t_edge {
            for p in [1.0, 2.0, 3.0] {
                for o in [Output::TipUz, Output::TipUy] {
                    v.push(obs(cfg(n, t, p), o, tip_s));
                }
            }
        }
    }
    out.push((
        format!(
            "tip of new designs with T = {} and {} mm (the model's range), 1–3 bar",
            t_edge[0], t_edge[1]
        ),
        v,
    ));
    out.into_iter()
        .map(|(name, obs)| (name, ObservationSet::from_observations(obs)))
        .collect()
}

/// The exclusion list of the report: each user or data-check exclusion with its reason.
pub fn describe_exclusions(ex: &[Exclusion]) -> Vec<String> {
    ex.iter()
        .map(|e| {
            let what = match e.recording {
                Recording::Bending => "bending",
                Recording::Force => "force",
                Recording::Both => "bending and force",
            };
            format!("{} ({what}): {}", e.config.label(), e.reason)
        })
        .collect()
}
