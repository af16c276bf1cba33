//! The study's results: every twin scored, the targets counted, and the run that makes them.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::diagnosis::{diagnose_twin, Diagnoser};
use super::plan::{StudyPlan, VERSION};
use super::score::{score_twin, truth_tips, TrueTip, TwinScore};
use super::twins::StudyDirs;
use crate::calibrate::twin::TwinKey;
use crate::calibrate::Recordings;
use crate::diagnose::approx_error::ApproximationError;
use crate::diagnose::DiagnoseError;

/// The `format` field of the study's results.
pub const RESULTS_FORMAT: &str = "surrogate.twin-study-results";

/// The study's scores and their summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyResults {
    /// [`RESULTS_FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// Every twin diagnosed.
    pub twins: Vec<TwinScore>,
    /// Twins of the plan not diagnosed yet (their FE is not in the cache).
    pub pending: Vec<String>,
    /// Whether the diagnoses used the twins' marker recordings.
    pub markers: bool,
    /// The reference surrogate of the mesh error projected out (none: not projected).
    #[serde(default)]
    pub mesh_reference: Option<String>,
    /// The approximation error the diagnoses used: its reference and samples (none: not
    /// used).
    #[serde(default)]
    pub approximation_error: Option<String>,
    /// The summary.
    pub summary: StudySummary,
}

/// The study's numbers against its targets.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudySummary {
    /// Effect twins whose effect moves the tip by more than 2 σ.
    pub visible: usize,
    /// … of which the concealed effect is ranked first.
    pub visible_first: usize,
    /// … ranked first or reported indistinguishable from the first.
    pub visible_first_or_indistinguishable: usize,
    /// … named (the verdict's effect is the concealed one).
    pub visible_named: usize,
    /// Over the visible twins: the mean number of other candidates the recordings cannot
    /// tell from the first, and the mean number ranked.
    #[serde(default)]
    pub visible_mean_tied: (f64, f64),
    /// Every effect twin: ranked first.
    pub effect_twins: usize,
    /// Every effect twin: ranked first (count).
    pub effect_first: usize,
    /// Null twins.
    pub nulls: usize,
    /// Null twins where an effect was named (false alarms).
    pub false_alarms: usize,
    /// Twins (effect, null) where the model's own mesh error explained the residual best.
    #[serde(default)]
    pub model_error_best: (usize, usize),
    /// Correctly named twins whose refitted value is within 25 % of the truth or whose
    /// interval covers it, of the correctly named.
    pub sizes_recovered: (usize, usize),
    /// Correctly named twins whose held-out tip BE after the refit is within 1.2 × the
    /// noise level, of the correctly named with a held-out BE.
    pub held_out_within: (usize, usize),
    /// Confusion matrix: rows the concealed effect (`none`), columns the named one
    /// (`nothing`; `nothing (model's mesh)` when the model's own mesh error explained the
    /// residual best), counts.
    pub confusion: Vec<(String, String, usize)>,
}

/// The summary of `twins`.
pub fn summarise(twins: &[TwinScore]) -> StudySummary {
    let effect: Vec<&TwinScore> = twins.iter().filter(|t| t.truth.is_some()).collect();
    let visible: Vec<&&TwinScore> = effect.iter().filter(|t| t.tip_move_sigma > 2.0).collect();
    let first = |t: &TwinScore| t.rank == Some(1);
    let named_right = |t: &TwinScore| t.named.is_some() && t.named == t.truth;
    let nulls: Vec<&TwinScore> = twins.iter().filter(|t| t.truth.is_none()).collect();
    let right: Vec<&&TwinScore> = effect.iter().filter(|t| named_right(t)).collect();
    let recovered = right
        .iter()
        .filter(|t| match (t.refit_value, t.true_value) {
            (Some((v, lo, hi)), Some(truth)) => {
                (v - truth).abs() <= 0.25 * truth.abs() || (lo <= truth && truth <= hi)
            }
            _ => false,
        })
        .count();
    let with_be: Vec<(f64, f64)> = right
        .iter()
        .filter_map(|t| t.held_out_be.map(|(_, after, noise)| (after, noise)))
        .collect();
    let mut confusion: Vec<(String, String, usize)> = Vec::new();
    for t in twins {
        let row = t.truth.clone().unwrap_or_else(|| "none".into());
        let col = match (&t.named, t.model_error_best) {
            (Some(n), _) => n.clone(),
            (None, true) => "nothing (model's mesh)".into(),
            (None, false) => "nothing".into(),
        };
        match confusion.iter_mut().find(|c| c.0 == row && c.1 == col) {
            Some(c) => c.2 += 1,
            None => confusion.push((row, col, 1)),
        }
    }
    StudySummary {
        visible: visible.len(),
        visible_first: visible.iter().filter(|t| first(t)).count(),
        visible_first_or_indistinguishable: visible
            .iter()
            .filter(|t| first(t) || t.indistinguishable_from_first)
            .count(),
        visible_named: visible.iter().filter(|t| named_right(t)).count(),
        visible_mean_tied: {
            let k = visible.len().max(1) as f64;
            (
                visible
                    .iter()
                    .map(|t| t.tied_with_first.0 as f64)
                    .sum::<f64>()
                    / k,
                visible
                    .iter()
                    .map(|t| t.tied_with_first.1 as f64)
                    .sum::<f64>()
                    / k,
            )
        },
        effect_twins: effect.len(),
        effect_first: effect.iter().filter(|t| first(t)).count(),
        nulls: nulls.len(),
        false_alarms: nulls.iter().filter(|t| t.named.is_some()).count(),
        model_error_best: (
            effect.iter().filter(|t| t.model_error_best).count(),
            nulls.iter().filter(|t| t.model_error_best).count(),
        ),
        sizes_recovered: (recovered, right.len()),
        held_out_within: (
            with_be.iter().filter(|(a, n)| *a <= 1.2 * n).count(),
            with_be.len(),
        ),
        confusion,
    }
}

/// Diagnoses every twin whose FE is complete and scores it; the others are listed as
/// pending. `progress` gets a line per twin.
///
/// # Errors
/// A plan of another noise-seed derivation ([`StudyPlan::check_noise_seeds`]); a key whose
/// seed is not the plan's for its twin (a twin made by an older derivation or another
/// plan: remake the twins); a diagnosis error, an unreadable key.
pub fn run_diagnoses(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
    by: &Diagnoser<'_>,
    progress: &dyn Fn(&str),
) -> Result<StudyResults, DiagnoseError> {
    plan.check_noise_seeds()?;
    let (model, markers) = (by.model, by.markers);
    let mut twins = Vec::new();
    let mut pending = Vec::new();
    for (g, replicate, name) in plan.twins() {
        let dir = dirs.twins.join(&name);
        let key_path = dirs.keys.join(format!("{name}.json"));
        if !dir.is_dir() || !key_path.exists() {
            pending.push(name);
            continue;
        }
        let own = without_own_group(by, &plan.groups[g].id)?;
        let by_here = Diagnoser {
            approximation: own.as_ref().or(by.approximation),
            ..*by
        };
        let d = diagnose_twin(&dir, &by_here)?;
        let text = d.to_json()?;
        std::fs::create_dir_all(&dirs.diagnoses).map_err(|e| {
            DiagnoseError::input("diagnoses", dirs.diagnoses.display(), &e.to_string())
        })?;
        let suffix = match (markers == plan.markers, markers) {
            (true, _) => "",
            (false, true) => "_markers",
            (false, false) => "_no_markers",
        };
        let out = dirs.diagnoses.join(format!("{name}{suffix}.json"));
        crate::io::write_atomic(&out, text.as_bytes())
            .map_err(|e| DiagnoseError::input("diagnosis", out.display(), &e.to_string()))?;
        let key = read_key(plan, g, replicate, &key_path)?;
        let tips = truth_tips(plan, &plan.groups[g], noise_from, dirs)?;
        let s = score_twin(&name, &d, &key, model, &|n, t, p| tip_at(&tips, n, t, p))?;
        progress(&format!(
            "{name}: concealed {}, named {}, first {}",
            s.truth.as_deref().unwrap_or("nothing"),
            s.named.as_deref().unwrap_or("nothing"),
            s.first.as_deref().unwrap_or("—")
        ));
        twins.push(s);
    }
    let summary = summarise(&twins);
    Ok(StudyResults {
        format: RESULTS_FORMAT.into(),
        version: VERSION,
        twins,
        pending,
        markers,
        mesh_reference: by.mesh_reference.map(|(_, n)| n.to_string()),
        approximation_error: by.approximation.map(|a| {
            let own = plan
                .groups
                .iter()
                .any(|g| a.samples.iter().any(|x| x.source == g.id));
            format!(
                "the error of `{}` against {}, {} samples ({}){}",
                a.model,
                a.reference,
                a.samples.len(),
                a.samples
                    .iter()
                    .map(|s| s.source.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                if own {
                    "; a null twin is diagnosed without the sample of its own group"
                } else {
                    "; none of the twins' own FE among them"
                }
            )
        }),
        summary,
    })
}

/// The approximation error of `by` without the sample of group `id` (a null twin is not
/// diagnosed with its own group's sample); none when `by` has none or no sample of `id`.
///
/// # Errors
/// As [`ApproximationError::without`].
pub(super) fn without_own_group(
    by: &Diagnoser<'_>,
    id: &str,
) -> Result<Option<ApproximationError>, DiagnoseError> {
    match by.approximation {
        Some(a) if a.samples.iter().any(|x| x.source == id) => Ok(Some(a.without(&[id])?)),
        _ => Ok(None),
    }
}

/// The key of twin `replicate` of group `g`, checked against the plan's noise seed.
///
/// # Errors
/// An unreadable key; a seed that is not the plan's.
pub(super) fn read_key(
    plan: &StudyPlan,
    g: usize,
    replicate: u64,
    path: &Path,
) -> Result<TwinKey, DiagnoseError> {
    let key: TwinKey = serde_json::from_str(
        &std::fs::read_to_string(path)
            .map_err(|e| DiagnoseError::input("key", path.display(), &e.to_string()))?,
    )?;
    plan.check_key(&plan.groups[g].id, replicate, &key)?;
    Ok(key)
}

/// The noise-free tip `(Uz, Uy)` of `tips` at `(n, t, p)`.
pub(super) fn tip_at(tips: &[TrueTip], n: u32, t: f64, p: f64) -> Option<(f64, f64)> {
    tips.iter()
        .find(|r| {
            r.n_bellows == n
                && (r.wall_thickness_mm - t).abs() < 1e-9
                && (r.pressure_bar - p).abs() < 1e-9
        })
        .map(|r| (r.tip_uz_mm, r.tip_uy_mm))
}
