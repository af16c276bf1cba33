//! The top candidates of the Name stage ranked by FE-confirmed nonlinear fits rather than by
//! their linearised `Δχ²`.
//!
//! The Name stage tests each effect's signature linearised at the sweep's material. Where an
//! effect and the material trade off nonlinearly (thinner walls are softer and lighter; once
//! the material has taken the softness, what is left of the linearised signature can look
//! like self-weight), the linearised ranking can put the wrong candidate first with a large
//! F. Here each of the top candidates is refitted with the material ([`super::refit`]), run
//! on the FE model at its refitted values and refitted around the FE
//! ([`super::confirm_with_fe`], space mapping's output correction), and the candidates are
//! ranked by the `χ²` of the FE at their last round: the FE's own prediction with the effect
//! on, not a linearisation.
//!
//! Two FE fits with the same number of parameters are compared by the likelihood ratio of the
//! two non-nested models (Vuong's test): with `dᵢ = (z²ᵦ,ᵢ − z²ₐ,ᵢ)/2` over the cells, `z =
//! Σdᵢ / (√n · sd(d))`; the first is significantly better than another when `z` exceeds the
//! two-sided normal quantile of the level, otherwise the two stay tied.

use serde::{Deserialize, Serialize};

use super::confirm::{confirm_with_fe, FeConfirmSettings};
use super::outcome::{Refit, RefitSettings};
use super::refit;
use crate::calibrate::baseline::SweepSensitivities;
use crate::case::OgdenSet;
use crate::diagnose::cells::Cell;
use crate::diagnose::name::{two_sided_z, Candidate, Naming};
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;
use crate::rom::Surrogate;

/// Settings of [`rank_with_fe`].
#[derive(Clone, Debug, PartialEq)]
pub struct FeRankSettings {
    /// How many of the Name stage's candidates (significant, at a plausible size, physics
    /// only, in its order) are fitted with FE: 2 or more.
    pub top: usize,
    /// Level of the pairwise likelihood-ratio tests.
    pub alpha: f64,
}

impl Default for FeRankSettings {
    /// The top 3 at α = 0.05.
    fn default() -> Self {
        Self {
            top: 3,
            alpha: 0.05,
        }
    }
}

impl FeRankSettings {
    fn validate(&self) -> Result<(), DiagnoseError> {
        if self.top < 2 {
            return Err(DiagnoseError::input(
                "FE ranking: candidates",
                self.top,
                "at least 2 (a ranking compares candidates)",
            ));
        }
        if !(self.alpha > 0.0 && self.alpha < 0.5) {
            return Err(DiagnoseError::input(
                "FE ranking: alpha",
                self.alpha,
                "a level in (0, 0.5)",
            ));
        }
        Ok(())
    }
}

/// One candidate's FE-confirmed fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeRanked {
    /// The effect.
    pub effect: String,
    /// Its unit.
    pub unit: String,
    /// Its place in the Name stage's linearised ranking (1: first).
    pub linear_rank: usize,
    /// Its linearised `Δχ²` in the Name stage.
    pub linear_delta_chi2: f64,
    /// Its value at the last FE round.
    pub value: f64,
    /// The material at the last FE round.
    pub material: OgdenSet,
    /// `χ²` of the FE at the last round against the recordings (the cells of the refit).
    pub fe_chi2: f64,
    /// Mean tip BE of the FE there (mm).
    pub fe_mean_be_mm: Option<f64>,
    /// Mean absolute force error of the FE there (N).
    pub fe_mean_abs_force_error_n: Option<f64>,
    /// Root mean square of (FE − linearised)/σ at the last round.
    pub rms_fe_minus_linear: f64,
    /// Whether the FE confirmed the refit within the tolerance.
    pub confirmed: bool,
    /// FE rounds run.
    pub rounds: usize,
    /// The likelihood-ratio z of the FE-first against this one (positive: the first fits
    /// better); none for the first.
    pub vuong_z: Option<f64>,
    /// Whether this one cannot be told from the FE-first (for the first: false).
    pub tied_with_first: bool,
}

/// The FE-confirmed ranking of the top candidates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeRanking {
    /// Mesh of the FE runs.
    pub mesh: String,
    /// Cells compared.
    pub n_cells: usize,
    /// Level of the pairwise tests.
    pub alpha: f64,
    /// The candidates, lowest FE `χ²` first.
    pub candidates: Vec<FeRanked>,
    /// Whether the FE puts first the candidate the linearised ranking put first.
    pub agrees: bool,
    /// The ranking in words.
    pub verdict: String,
}

impl FeRanking {
    /// The FE's first candidate.
    pub fn first(&self) -> Option<&FeRanked> {
        self.candidates.first()
    }

    /// The candidates the FE cannot tell from its first.
    pub fn tied(&self) -> impl Iterator<Item = &FeRanked> {
        self.candidates.iter().filter(|c| c.tied_with_first)
    }
}

/// A candidate the FE ranking fits, as the Name stage ranked it.
#[derive(Clone, Debug, PartialEq)]
pub struct Picked {
    /// Its place in the Name stage's ranking (1: first).
    pub linear_rank: usize,
    /// The effect's name.
    pub effect: String,
    /// Its unit.
    pub unit: String,
    /// Its linearised `Δχ²`.
    pub linear_delta_chi2: f64,
}

/// The candidates of `naming` that the FE ranking fits: significant, at a plausible size,
/// physics (not an error of the model), in the Name stage's order, at most `top`.
pub fn ranked_candidates(naming: &Naming, top: usize) -> Vec<Picked> {
    naming
        .candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.significant && c.plausible && !c.model_error)
        .take(top)
        .map(|(i, c): (usize, &Candidate)| Picked {
            linear_rank: i + 1,
            effect: c.effect.clone(),
            unit: c.unit.clone(),
            linear_delta_chi2: c.delta_chi2,
        })
        .collect()
}

/// The likelihood-ratio z of fit `a` against fit `b` from their per-cell `z` (positive: `a`
/// fits better); none without cells or when the two fits agree cell by cell.
pub fn vuong_z(za: &[f64], zb: &[f64]) -> Option<f64> {
    if za.len() != zb.len() || za.len() < 2 {
        return None;
    }
    let d: Vec<f64> = za
        .iter()
        .zip(zb)
        .map(|(a, b)| 0.5 * (b * b - a * a))
        .collect();
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (var > 0.0).then(|| mean * n.sqrt() / var.sqrt())
}

/// Ranks the top candidates of `naming` by FE-confirmed nonlinear fits (see the
/// [module docs](self)): each refitted with the material from `start` on `cells` through
/// `model` (the effect linearised with `sens`), then confirmed by the FE with `fe` (each
/// candidate's ramps cached in `rank_<effect>/` inside `fe.cache`). `progress` gets a line
/// per candidate, `ramp_progress(done, total)` one per FE ramp.
///
/// # Errors
/// Bad settings; fewer than 2 candidates to rank; as [`super::refit()`] and
/// [`confirm_with_fe`].
#[allow(clippy::too_many_arguments)]
pub fn rank_with_fe(
    cells: &[Cell],
    sens: &SweepSensitivities,
    model: &Surrogate,
    start: &OgdenSet,
    naming: &Naming,
    s: &FeRankSettings,
    fe: &FeConfirmSettings,
    progress: &dyn Fn(&str),
    ramp_progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<FeRanking, DiagnoseError> {
    s.validate()?;
    let picked = ranked_candidates(naming, s.top);
    if picked.len() < 2 {
        return Err(DiagnoseError::input(
            "FE ranking: candidates significant at a plausible size",
            picked.len(),
            "at least 2 (with one, there is nothing to rank)",
        ));
    }
    let mut confirmed = Vec::with_capacity(picked.len());
    for c in &picked {
        let effect = Effect::from_name(&c.effect)
            .map_err(|e| DiagnoseError::input("FE ranking: effect", &c.effect, &e.to_string()))?;
        progress(&format!(
            "FE ranking: {} (linearised rank {}): material + effect refitted, then run on the FE \
             model",
            c.effect, c.linear_rank
        ));
        let rs = RefitSettings {
            held_out: false,
            ..RefitSettings::new(vec![effect])
        };
        let first = refit(cells, sens, model, start, &rs)?;
        let fe_c = FeConfirmSettings {
            cache: fe.cache.join(format!("rank_{}", c.effect)),
            ..fe.clone()
        };
        confirmed.push(confirm_with_fe(
            cells,
            sens,
            model,
            first,
            &rs,
            &fe_c,
            ramp_progress,
        )?);
    }
    rank_confirmed(
        &picked,
        &confirmed,
        s,
        fe.tolerance,
        fe.sweep.mesh.level.name(),
    )
}

/// The ranking of `picked` by their FE-confirmed refits `confirmed` (in the same order; each
/// with at least one FE round, [`super::confirm_with`]): lowest FE `χ²` first, each against
/// the first by the likelihood ratio of their per-cell `z`. `tolerance` is the confirmation's
/// (rms FE − linearised, σ), `mesh` the FE's mesh in words.
///
/// # Errors
/// Bad settings; `picked` and `confirmed` of different lengths, fewer than 2, or a refit
/// without an FE round.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn rank_confirmed(
    picked: &[Picked],
    confirmed: &[Refit],
    s: &FeRankSettings,
    tolerance: f64,
    mesh: &str,
) -> Result<FeRanking, DiagnoseError> {
    s.validate()?;
    if picked.len() != confirmed.len() || picked.len() < 2 {
        return Err(DiagnoseError::input(
            "FE ranking: confirmed refits",
            confirmed.len(),
            &format!(
                "one per candidate, at least 2 ({} candidates)",
                picked.len()
            ),
        ));
    }
    let mut ranked = Vec::with_capacity(picked.len());
    let mut zs: Vec<&[f64]> = Vec::with_capacity(picked.len());
    let mut n_cells = 0;
    for (c, r) in picked.iter().zip(confirmed) {
        let last = r.fe.last().ok_or_else(|| {
            DiagnoseError::input(
                "FE ranking",
                &c.effect,
                "a refit with at least one FE round",
            )
        })?;
        n_cells = last.z.len();
        zs.push(&last.z);
        ranked.push(FeRanked {
            effect: c.effect.clone(),
            unit: c.unit.clone(),
            linear_rank: c.linear_rank,
            linear_delta_chi2: c.linear_delta_chi2,
            value: last.effects.first().copied().unwrap_or(f64::NAN),
            material: last.material,
            fe_chi2: last.quality.chi2,
            fe_mean_be_mm: last.quality.mean_be_mm,
            fe_mean_abs_force_error_n: last.quality.mean_abs_force_error_n,
            rms_fe_minus_linear: last.rms_fe_minus_linear,
            confirmed: last.rms_fe_minus_linear <= tolerance,
            rounds: r.fe.len(),
            vuong_z: None,
            tied_with_first: false,
        });
    }
    let mut order: Vec<usize> = (0..ranked.len()).collect();
    order.sort_by(|&a, &b| ranked[a].fe_chi2.total_cmp(&ranked[b].fe_chi2));
    let z_crit = two_sided_z(s.alpha);
    let best = order[0];
    let mut out: Vec<FeRanked> = Vec::with_capacity(ranked.len());
    for &i in &order {
        let mut r = ranked[i].clone();
        if i != best {
            r.vuong_z = vuong_z(zs[best], zs[i]);
            r.tied_with_first = r.vuong_z.is_none_or(|z| z < z_crit);
        }
        out.push(r);
    }
    let linear_first = picked
        .iter()
        .map(|c| c.linear_rank)
        .min()
        .unwrap_or_default();
    let agrees = out[0].linear_rank == linear_first;
    let verdict = verdict(&out, agrees, mesh, z_crit);
    Ok(FeRanking {
        mesh: mesh.to_string(),
        n_cells,
        alpha: s.alpha,
        candidates: out,
        agrees,
        verdict,
    })
}

fn verdict(out: &[FeRanked], agrees: bool, mesh: &str, z_crit: f64) -> String {
    let be = |r: &FeRanked| {
        r.fe_mean_be_mm
            .map_or(String::new(), |b| format!(", mean tip BE {b:.2} mm"))
    };
    let first = &out[0];
    let mut s = format!(
        "FE-confirmed ranking of the top {} candidates (each refitted with the material, run on \
         the FE model ({mesh} mesh) at its refitted value and refitted around the FE): {} first \
         at {:.4} {} (FE χ² {:.1}{})",
        out.len(),
        first.effect,
        first.value,
        first.unit,
        first.fe_chi2,
        be(first)
    );
    for r in &out[1..] {
        s.push_str(&format!(
            "; {} at {:.4} {} (χ² {:.1}{}{})",
            r.effect,
            r.value,
            r.unit,
            r.fe_chi2,
            be(r),
            r.vuong_z
                .map_or(String::new(), |z| format!(", likelihood-ratio z = {z:.2}"))
        ));
    }
    s.push('.');
    let tied: Vec<&str> = out
        .iter()
        .filter(|r| r.tied_with_first)
        .map(|r| r.effect.as_str())
        .collect();
    if tied.is_empty() {
        s.push_str(&format!(
            " {} fits the recordings significantly better than the others (z > {z_crit:.2}).",
            first.effect
        ));
    } else {
        s.push_str(&format!(
            " The FE fits cannot tell {} from {} (z < {z_crit:.2}): they stay tied.",
            first.effect,
            tied.join(", ")
        ));
    }
    if agrees {
        s.push_str(" The FE ranking puts first the candidate the linearised ranking put first.");
    } else {
        let lin = out
            .iter()
            .min_by_key(|r| r.linear_rank)
            .map_or("", |r| r.effect.as_str());
        s.push_str(&format!(
            " The FE ranking reverses the linearised one, which put {lin} first: the \
             linearisation misjudges these candidates here, and {} is the FE's choice.",
            first.effect
        ));
    }
    let unconfirmed: Vec<&str> = out
        .iter()
        .filter(|r| !r.confirmed)
        .map(|r| r.effect.as_str())
        .collect();
    if !unconfirmed.is_empty() {
        s.push_str(&format!(
            " Not confirmed within the tolerance after their FE rounds: {} (their χ² is the \
             FE's at the last refit, not at its optimum).",
            unconfirmed.join(", ")
        ));
    }
    s
}
