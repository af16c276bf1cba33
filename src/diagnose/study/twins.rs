//! Making the twins: the plan's FE sweeps (cached) and a twin per seed, its key apart.

use std::path::{Path, PathBuf};

use super::plan::StudyPlan;
use crate::calibrate::baseline::{cached_ramps, recorded_designs, RampSource};
use crate::calibrate::twin::write_twin;
use crate::calibrate::Recordings;
use crate::diagnose::DiagnoseError;

/// Directories of a study under its output directory.
#[derive(Clone, Debug)]
pub struct StudyDirs {
    /// FE ramps of every group.
    pub cache: PathBuf,
    /// The twins' recordings (one directory each).
    pub twins: PathBuf,
    /// The keys.
    pub keys: PathBuf,
    /// The diagnoses.
    pub diagnoses: PathBuf,
}

impl StudyDirs {
    /// The directories under `out`.
    pub fn under(out: &Path) -> Self {
        StudyDirs {
            cache: out.join("fe_cache"),
            twins: out.join("twins"),
            keys: out.join("keys"),
            diagnoses: out.join("diagnoses"),
        }
    }
}

/// The FE ramps of `plan`'s groups that are not in the cache of `dirs`, by group (`id`,
/// ramps missing), groups with all their ramps cached left out: what [`make_twins`] would
/// run. Reads the cache only.
///
/// # Errors
/// A group whose effects or material do not parse, an invalid design.
pub fn ramps_to_run(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
) -> Result<Vec<(String, usize)>, DiagnoseError> {
    let designs = recorded_designs(&noise_from.bending);
    let mut out = Vec::new();
    for g in &plan.groups {
        let s = g.settings(plan, 0, &dirs.cache)?;
        let missing = cached_ramps(&s.sweep, &designs, &s.ramp_dir())
            .map_err(crate::calibrate::CalibrateError::from)?
            .iter()
            .filter(|r| r.source == RampSource::Missing)
            .count();
        if missing > 0 {
            out.push((g.id.clone(), missing));
        }
    }
    Ok(out)
}

/// Makes every twin of `plan` (FE runs cached and resumable; a group's seeds share them),
/// each with its noise seed [`StudyPlan::noise_seed`] and the seed's origin in its key;
/// `progress` gets a line per twin.
///
/// # Errors
/// A plan of another noise-seed derivation ([`StudyPlan::check_noise_seeds`]); a twin error
/// (a design out of range, an unwritable cache).
pub fn make_twins(
    plan: &StudyPlan,
    noise_from: &Recordings,
    dirs: &StudyDirs,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<(), DiagnoseError> {
    plan.check_noise_seeds()?;
    let all = plan.twins();
    for (k, (g, replicate, name)) in all.iter().enumerate() {
        let group = &plan.groups[*g];
        let seed = plan.noise_seed(&group.id, *replicate);
        let mut s = group.settings(plan, seed, &dirs.cache)?;
        s.seed_origin = Some(plan.seed_origin(&group.id, *replicate));
        s.key = Some(dirs.keys.join(format!("{name}.json")));
        let out = dirs.twins.join(name);
        let o = write_twin(&s, noise_from, &out, |done, total| {
            progress(&format!("{name}: FE ramp {done} of {total}"))
        })
        .map_err(|e| DiagnoseError::input(&format!("twin {name}"), "", &e.to_string()))?;
        progress(&format!(
            "twin {} of {}: {name} ({} FE ramps run, {} cached)",
            k + 1,
            all.len(),
            o.ramps_run,
            o.ramps_cached
        ));
    }
    Ok(())
}
