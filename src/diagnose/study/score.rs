//! Scoring one twin's diagnosis against its key.

use serde::{Deserialize, Serialize};

use super::plan::{StudyPlan, TwinGroup};
use super::twins::StudyDirs;
use crate::calibrate::baseline::{cached_ramps, recorded_designs};
use crate::calibrate::objective::Output;
use crate::calibrate::twin::TwinKey;
use crate::calibrate::Recordings;
use crate::case::Query;
use crate::diagnose::report::Diagnosis;
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;
use crate::fe::simulate::Mode;
use crate::rom::Surrogate;

/// One twin, scored.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwinScore {
    /// `<id>_s<seed>`.
    pub twin: String,
    /// The concealed effect (none: a null twin).
    pub truth: Option<String>,
    /// Its value.
    pub true_value: Option<f64>,
    /// The true material.
    pub material: String,
    /// `max |(ΔUz, ΔUy)| / σ_tip` of the noise-free twin against the surrogate at the true
    /// material (what the effect moves the tip by, in noise units).
    pub tip_move_sigma: f64,
    /// The effect named (none: nothing named).
    pub named: Option<String>,
    /// The first candidate of the ranking.
    pub first: Option<String>,
    /// Rank of the concealed effect among the candidates (1 = first).
    pub rank: Option<usize>,
    /// Whether the concealed effect is reported indistinguishable from the first candidate.
    pub indistinguishable_from_first: bool,
    /// How many other candidates the recordings cannot tell from the first (its tie set),
    /// and how many candidates were ranked.
    #[serde(default)]
    pub tied_with_first: (usize, usize),
    /// The Name stage's estimate of the concealed effect's value and its standard error.
    pub name_estimate: Option<(f64, f64)>,
    /// The refit's value of the named effect and its interval.
    pub refit_value: Option<(f64, f64, f64)>,
    /// Held-out tip BE before and after the refit (mm), and the noise level (mm).
    pub held_out_be: Option<(f64, f64, f64)>,
    /// The Name stage's verdict.
    pub verdict: String,
    /// Whether the model's own mesh error explained the residual best (the verdict then
    /// names no physics).
    #[serde(default)]
    pub model_error_best: bool,
}

/// Scores a diagnosis against its key; `model` gives the tip at the true material and
/// `truth_tip(n, t, p)` the twin's noise-free tip.
pub fn score_twin(
    twin: &str,
    d: &Diagnosis,
    key: &TwinKey,
    model: &Surrogate,
    truth_tip: &dyn Fn(u32, f64, f64) -> Option<(f64, f64)>,
) -> Result<TwinScore, DiagnoseError> {
    let truth = key
        .effects
        .iter()
        .next()
        .map(|(e, v)| (e.name().to_string(), v));
    let m = key
        .material_parameters
        .ogden_set()
        .ok_or_else(|| DiagnoseError::input("key material", &key.material, "an Ogden material"))?;
    let mut tip_move: f64 = 0.0;
    let mut pred = model.new_prediction();
    for c in d.locate.cells.iter().filter(|c| c.output == Output::TipUz) {
        let Some((uz, uy)) = truth_tip(c.n_bellows, c.wall_thickness_mm, c.pressure_bar) else {
            continue;
        };
        let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, m);
        model
            .predict_scalars_into(&q, &mut pred)
            .map_err(crate::calibrate::CalibrateError::from)?;
        let (sz, sy) = (
            pred.values[crate::rom::Q_TIP_UZ],
            pred.values[crate::rom::Q_TIP_UY],
        );
        tip_move = tip_move.max((uz - sz).hypot(uy - sy) / c.sigma);
    }
    let naming = d.naming();
    let first = naming.and_then(|n| n.candidates.first().map(|c| c.effect.clone()));
    let (mut rank, mut name_estimate, mut indistinguishable) = (None, None, false);
    if let (Some(n), Some((t, _))) = (naming, &truth) {
        if let Some(i) = n.candidates.iter().position(|c| &c.effect == t) {
            rank = Some(i + 1);
            let c = &n.candidates[i];
            Effect::from_name(t)
                .map_err(|e| DiagnoseError::input("key effect", t, &e.to_string()))?;
            name_estimate = Some((c.size(), c.std_error));
        }
        if let Some(f) = &first {
            indistinguishable = n
                .indistinguishable
                .iter()
                .any(|p| (&p.a == f && &p.b == t) || (&p.b == f && &p.a == t));
        }
    }
    let tied_with_first = naming.map_or((0, 0), |n| {
        let tied = first.as_ref().map_or(0, |f| {
            n.indistinguishable
                .iter()
                .filter(|p| &p.a == f || &p.b == f)
                .count()
        });
        (tied, n.candidates.len())
    });
    let refit = d.refitted();
    Ok(TwinScore {
        twin: twin.to_string(),
        truth: truth.as_ref().map(|t| t.0.clone()),
        true_value: truth.as_ref().map(|t| t.1),
        material: key.material.clone(),
        tip_move_sigma: tip_move,
        named: naming.and_then(|n| n.named().map(|c| c.effect.clone())),
        first,
        rank,
        indistinguishable_from_first: indistinguishable,
        tied_with_first,
        name_estimate,
        refit_value: refit
            .and_then(|r| r.effects.first())
            .map(|e| (e.value, e.interval.0, e.interval.1)),
        held_out_be: refit.and_then(|r| {
            let h = r.held_out.as_ref()?;
            Some((h.mean_be_before_mm?, h.mean_be_after_mm?, r.noise_be_mm?))
        }),
        verdict: naming.map_or(String::new(), |n| n.verdict.clone()),
        model_error_best: naming.is_some_and(|n| n.model_error().is_some()),
    })
}

/// A twin's noise-free tip at one configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrueTip {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Tip Uz (mm).
    pub tip_uz_mm: f64,
    /// Tip Uy (mm).
    pub tip_uy_mm: f64,
}

/// The noise-free tip of a twin group: its cached FE ramps (none run here).
///
/// # Errors
/// A group that does not parse, an invalid design.
pub fn truth_tips(
    plan: &StudyPlan,
    group: &TwinGroup,
    noise_from: &Recordings,
    dirs: &StudyDirs,
) -> Result<Vec<TrueTip>, DiagnoseError> {
    let s = group.settings(plan, 0, &dirs.cache)?;
    let ramps = cached_ramps(
        &s.sweep,
        &recorded_designs(&noise_from.bending),
        &s.ramp_dir(),
    )
    .map_err(crate::calibrate::CalibrateError::from)?;
    let mut out = Vec::new();
    for r in ramps.iter().filter(|r| r.mode == Mode::Bending) {
        for st in &r.steps {
            out.push(TrueTip {
                n_bellows: r.n_bellows as u32,
                wall_thickness_mm: r.wall_thickness_mm,
                pressure_bar: st.pressure_bar,
                tip_uz_mm: st.tip_uz_mm,
                tip_uy_mm: st.tip_uy_mm,
            });
        }
    }
    Ok(out)
}
