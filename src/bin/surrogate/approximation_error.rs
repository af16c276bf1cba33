//! `surrogate approximation-error`: samples of the model's own error against a reference FE
//! ([`surrogate::diagnose::approx_error`]).
use anyhow::{Context, Result};
use surrogate::calibrate::{ParamSpace, Recordings};
use surrogate::diagnose::approx_error::{sample, spread_materials, SampleSettings};

use crate::args::ApproximationErrorArgs;
use crate::files::{given_or_announced, load_model, DEFAULT_MODEL};

/// Runs the subcommand.
pub fn run(a: ApproximationErrorArgs) -> Result<()> {
    let mesh = a.refinement.options(&a.mesh)?;
    if a.materials < 2 {
        anyhow::bail!(
            "--materials {}: expected at least 2 (the covariance needs two)",
            a.materials
        );
    }
    if a.out.is_dir() {
        anyhow::bail!(
            "--out {}: a directory (expected the file to write)",
            a.out.display()
        );
    }
    let (model_path, _) = given_or_announced("model", a.model.as_deref(), DEFAULT_MODEL);
    let model = load_model(&model_path)?;
    let (recordings, _) =
        given_or_announced("recordings", a.recordings.as_deref(), "training_data");
    let rec = Recordings::read_dir(&recordings)
        .with_context(|| format!("reading the recordings in {}", recordings.display()))?;
    let materials = spread_materials(&ParamSpace::training_domain(&model)?, a.materials, a.seed)?;
    let cache = a.cache.clone().unwrap_or_else(|| {
        a.out
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."))
            .join("approximation_fe_ramps")
    });
    eprintln!(
        "{} materials × {} designs × 2 ramps on the {} mesh{}, cached in {} (a rerun resumes)",
        materials.len(),
        rec.bending
            .iter()
            .map(|r| (r.n_bellows, r.wall_thickness_mm.to_bits()))
            .collect::<std::collections::BTreeSet<_>>()
            .len(),
        mesh.level.name(),
        a.refinement
            .element_size
            .map_or(String::new(), |h| format!(" ({h} mm elements)")),
        cache.display()
    );
    let settings = SampleSettings {
        mesh,
        materials,
        cache,
        run_fe: true,
    };
    let e = sample(
        &model,
        &model_path.display().to_string(),
        &settings,
        &rec,
        &|k, done, n| {
            eprintln!(
                "material {} of {}: FE ramp {done} of {n}",
                k + 1,
                a.materials
            )
        },
    )?;
    e.write(&a.out)?;
    eprintln!(
        "wrote {} ({} samples of {} against {}); use it with `diagnose --approximation-error {}`",
        a.out.display(),
        e.samples.len(),
        e.model,
        e.reference,
        a.out.display()
    );
    Ok(())
}
