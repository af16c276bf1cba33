//! `surrogate twin`: recordings of the FE model with concealed effects, in the experiments'
//! format ([`surrogate::calibrate::twin`]).
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use surrogate::calibrate::twin::{write_twin, TwinSettings};
use surrogate::calibrate::Recordings;
use surrogate::fe::effects::Effects;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::preset::Geometry;

use crate::args::TwinArgs;

/// The default FE cache: `twin_fe_ramps/` beside the output directory.
pub fn default_cache(out: &Path) -> PathBuf {
    let parent = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    parent.join("twin_fe_ramps")
}

/// The commit of the source tree the program was built from, as it is now
/// (`git describe --always --dirty --abbrev=40`), if it is a git checkout.
fn source_commit() -> Option<String> {
    let out = std::process::Command::new("git")
        .args(["describe", "--always", "--dirty", "--abbrev=40"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    (out.status.success() && !text.trim().is_empty()).then(|| text.trim().to_string())
}

/// Runs the subcommand.
pub fn run(a: TwinArgs) -> Result<()> {
    let effects = Effects::parse(a.effect.iter().map(String::as_str))?;
    let material = Material::from_spec(&a.material, DEFAULT_BULK_RATIO)?;
    let mesh = a.refinement.options(&a.mesh)?;
    let (noise_dir, _) =
        crate::files::given_or_announced("noise-from", a.noise_from.as_deref(), "training_data");
    let noise_from = Recordings::read_dir(&noise_dir)
        .with_context(|| format!("reading the noise source {}", noise_dir.display()))?;
    let cache = a.cache.clone().unwrap_or_else(|| default_cache(&a.out));
    let mut settings = TwinSettings {
        key: a.key.clone(),
        commit: source_commit(),
        ..TwinSettings::new(material, &a.material, mesh, effects, a.seed, &cache)
    };
    settings.sweep.geometry = Geometry::from_name(&a.geometry)?;
    eprintln!(
        "twin of {} recorded configurations, FE ramps cached in {} (a rerun resumes; another \
         seed runs no FE)",
        noise_from.bending.len(),
        settings.ramp_dir().display()
    );
    let outcome = write_twin(&settings, &noise_from, &a.out, |k, n| {
        eprintln!("FE ramp {k} of {n} done")
    })?;
    eprintln!(
        "{} FE ramps run, {} read from the cache",
        outcome.ramps_run, outcome.ramps_cached
    );
    for m in &outcome.missing {
        eprintln!("no recording of {m}");
    }
    let files: Vec<String> = outcome
        .files
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    let key = a.key.as_ref().map_or("no key file".to_string(), |k| {
        format!("key {}", k.display())
    });
    eprintln!(
        "wrote {} ({} bending, {} force, {} marker rows); {key}",
        files.join(", "),
        outcome.rows[0],
        outcome.rows[1],
        outcome.rows[2]
    );
    Ok(())
}
