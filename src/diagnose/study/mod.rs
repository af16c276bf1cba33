//! The blind study of the diagnoser: twins with concealed effects (and null twins without),
//! each diagnosed without its key, then scored against the keys.
//!
//! ```text
//!   StudyPlan (groups: effects + material; seeds; the twins' mesh)
//!     │  per group: one FE sweep (cached), a twin per seed      ──► twins/<id>_s<seed>/
//!     │                                    the keys, apart      ──► keys/<id>_s<seed>.json
//!     ▼
//!   diagnose each twin directory (calibrate, locate, name, refit the named effect),
//!   seeing only its recordings                                  ──► diagnoses/<id>_s<seed>.json
//!     ▼
//!   score against the keys: confusion matrix, rank of the concealed effect, recovered
//!   sizes, false alarms, held-out tip error                     ──► results.json, results.md
//! ```
//!
//! **The standard plan** ([`StudyPlan::standard`]): six effects of the library at two sizes
//! each, each group with its own material drawn uniformly in the ±10 % box around Ogden 002
//! (the reference study's box), and six null groups (no effect) with materials drawn by a
//! Latin hypercube over the central 80 % of the surrogate's training domain; three noise
//! seeds per group; the twins on elements of 5 mm (one through a wall), which is not the
//! discretisation of the coarse mesh (6 mm) that the diagnosing surrogate and the
//! sensitivities come from.
//!
//! **Noise** ([`StudyPlan::noise_seed`]): a twin's noise seed is a function of its identity
//! in the whole plan, `s = m(m(h ⊕ |id|) ⊕ replicate)`, `m` the SplitMix64 finaliser and `h`
//! the draw seed and the bytes of the group's id folded through it, so every twin draws its own noise and a run given only some groups
//! (`--groups`, to split the FE between processes) draws exactly what one run of the whole
//! plan draws. The derivation is versioned ([`NOISE_SEEDS`], in the plan and every key).
//!
//! **Scoring** ([`score_twin`]): a twin's effect *moves the tip* by `max |(ΔUz, ΔUy)| / σ_tip`
//! over its configurations, the difference between its noise-free FE tip and the
//! diagnosing surrogate's prediction at the twin's true material (what the effect adds, up
//! to the two discretisations and the surrogate's own error, which the null twins measure).
//! The targets count the twins whose effect moves the tip by more than 2 σ.

mod closed_loop;
mod diagnosis;
mod markdown;
mod plan;
mod results;
mod score;
mod twins;

pub use closed_loop::{
    close_loop, AddedMeasurement, Chooser, LoopResults, LoopSettings, TwinLoop, LOOP_FORMAT,
    LOOP_KINDS,
};
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub use closed_loop::{add_record, draw, last_value};
pub use diagnosis::{
    diagnose_recordings, diagnose_twin, null_approximation_error, twin_recordings, Diagnoser,
};
pub use markdown::{loop_markdown, study_markdown};
pub use plan::{StudyPlan, TwinGroup, NOISE_SEEDS, PLAN_FORMAT, STANDARD_EFFECTS, VERSION};
pub use results::{run_diagnoses, summarise, StudyResults, StudySummary, RESULTS_FORMAT};
pub use score::{score_twin, truth_tips, TrueTip, TwinScore};
pub use twins::{make_twins, ramps_to_run, StudyDirs};
