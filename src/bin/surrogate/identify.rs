//! `surrogate identify`: the material and the unstated dimensions, jointly, on the FE model
//! ([`surrogate::calibrate::joint`]).
use std::path::Path;

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::calibrate::checks::check;
use surrogate::calibrate::joint::{
    identify, JointPoint, JointSettings, MeshCorrection, ModelSigma, Unknown,
};
use surrogate::calibrate::objective::Exclusion;
use surrogate::calibrate::Recordings;
use surrogate::fe::effects::Effects;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;

use crate::args::IdentifyArgs;

/// Runs the subcommand.
pub fn run(a: IdentifyArgs) -> Result<()> {
    let unknowns = a
        .unknowns
        .split(',')
        .map(|n| Unknown::from_name(n.trim()))
        .collect::<Result<Vec<_>, _>>()
        .context("--unknowns")?;
    anyhow::ensure!(
        a.max_step > 0.0 && a.max_step <= 1.0,
        "--max-step {}: expected a fraction of each unknown's range in (0, 1]",
        a.max_step
    );
    anyhow::ensure!(
        a.lambda.is_finite() && a.lambda > 0.0,
        "--lambda {}: expected a positive damping",
        a.lambda
    );
    anyhow::ensure!(
        a.max_sweeps >= 1,
        "--max-sweeps 0: expected at least 1 FE sweep"
    );
    let model_sigma = ModelSigma {
        tip_mm: a.model_sigma_tip,
        force_n: a.model_sigma_force,
    };
    model_sigma
        .validate()
        .context("--model-sigma-tip / --model-sigma-force")?;
    let material = Material::from_spec(&a.material, 1000.0).context("--material")?;
    let Some(ogden) = material.ogden_set() else {
        bail!(
            "--material {}: expected a second-order Ogden set (a name or mu1,alpha1,mu2,alpha2)",
            a.material
        );
    };
    let mut start = JointPoint {
        ogden,
        geometry: Geometry::from_name(&a.geometry).context("--geometry")?,
        effects: Effects::default(),
    };
    for item in &a.set {
        let Some((name, value)) = item.split_once('=') else {
            bail!("--set {item}: expected NAME=VALUE");
        };
        let v: f64 = value
            .trim()
            .parse()
            .with_context(|| format!("--set {item}: {value:?} is not a number"))?;
        let u = Unknown::from_name(name.trim()).with_context(|| format!("--set {item}"))?;
        start.set(u, v).with_context(|| format!("--set {item}"))?;
    }
    if !start.geometry.is_as_modelled() {
        start.geometry.name = "start".into();
    }
    start.geometry.validate().context("the starting geometry")?;
    let rec = match &a.recordings {
        Some(dir) => Recordings::read_dir(dir)?,
        None => {
            eprintln!(
                "recordings: the shipped experiments (training_data/bending_experiments.csv, \
                 training_data/blocked_force_experiments.csv); --recordings DIR for others"
            );
            Recordings::shipped()?
        }
    };
    let exclude = exclusions(&a, &rec)?;
    let correction = match &a.mesh_correction {
        Some(pair) => Some(mesh_correction(pair)?),
        None => None,
    };
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let cache = a.out.join("fe_ramps");
    eprintln!(
        "FE ramps cached in {} (a rerun with the same settings resumes)",
        cache.display()
    );
    let settings = JointSettings {
        unknowns,
        start,
        mesh: MeshOptions::level(level),
        max_sweeps: a.max_sweeps,
        lambda0: a.lambda,
        max_step: a.max_step,
        model_sigma,
        cache: Some(cache),
        warm_start: !a.cold,
        exclude,
        correction,
    };
    let bar = ProgressBar::new(0);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} sweep {msg} [{bar:30}] {pos}/{len} FE ramps, {elapsed_precise}",
    )?);
    let report = identify(&settings, &rec, |sweep, done, total| {
        bar.set_length(total as u64);
        bar.set_message(sweep.to_string());
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    report.write(&a.out)?;
    let mut g = report.optimum.geometry.clone();
    g.name = "identified".into();
    surrogate::io::write_atomic(
        &a.out.join("geometry.json"),
        serde_json::to_string_pretty(&g)?.as_bytes(),
    )?;
    println!("{}", report.summary());
    println!(
        "wrote {}/report.json, summary.md, geometry.json",
        a.out.display()
    );
    Ok(())
}

/// The rows left out of the fit: `--exclude`, and with `--exclude-flagged` every row the data
/// checks flag (each flag printed).
fn exclusions(a: &IdentifyArgs, rec: &Recordings) -> Result<Vec<Exclusion>> {
    let mut exclude = a
        .exclude
        .iter()
        .map(|e| Exclusion::parse(e))
        .collect::<Result<Vec<_>, _>>()?;
    for f in check(rec) {
        eprintln!(
            "data check: {} ({:?}): {}",
            f.config.label(),
            f.recording,
            f.message
        );
        if a.exclude_flagged && !exclude.iter().any(|e| e.config.same(&f.config)) {
            exclude.push(f.exclusion());
        }
    }
    Ok(exclude)
}

/// `--mesh-correction FINE.csv,COARSE.csv`.
fn mesh_correction(pair: &str) -> Result<MeshCorrection> {
    let Some((fine, coarse)) = pair.split_once(',') else {
        bail!("--mesh-correction {pair}: expected FINE.csv,COARSE.csv (two `surrogate validate` tables at the same point)");
    };
    let c = MeshCorrection::read(Path::new(fine.trim()), Path::new(coarse.trim()))
        .context("--mesh-correction")?;
    eprintln!(
        "mesh correction: {} − {} ({} configurations, mean {:.2} mm on the tip, {:.3} N on the force)",
        c.fine,
        c.coarse,
        c.entries.len(),
        c.mean_tip_mm(),
        c.mean_abs_force_n()
    );
    Ok(c)
}
