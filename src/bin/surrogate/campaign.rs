//! `surrogate campaign --bench`: the warm-start benchmark of FE campaigns
//! ([`surrogate::fe::campaign`]): a material sweep at fixed designs run cold, warm from each
//! case's nearest neighbour, and warm moved by first-order sensitivities; Newton iterations
//! per output level, factorisations, wall time and the differences from the cold answers, as
//! JSON.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::case::OgdenSet;
use surrogate::fe::campaign::{bench_material_sweep, bench_materials, WarmOrder};
use surrogate::fe::effects::Effects;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, MaterialLaw, Ogden2, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{parse_pressures, Case, ContactSettings, Mode};
use surrogate::fe::solver::SolverSettings;
use surrogate::io::write_atomic;

/// `surrogate campaign`.
#[derive(Debug, Args)]
pub struct CampaignArgs {
    /// Run the material-sweep benchmark (the only mode so far).
    #[arg(long)]
    pub bench: bool,
    /// Output JSON (written atomically).
    #[arg(long)]
    pub out: PathBuf,
    /// Number of materials (a seeded Latin hypercube around Ogden 002).
    #[arg(long, default_value_t = 10)]
    pub materials: usize,
    /// Relative span of the materials: μ0 within a factor 1 ± span (log-uniform), α₁ within
    /// ± span/2.
    #[arg(long, default_value_t = 0.2)]
    pub span: f64,
    /// Seed of the materials' Latin hypercube.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Instead of the Latin hypercube: two materials, Ogden 002 and Ogden 002 with μ0 (μ₁ and
    /// μ₂) scaled by 1 + this (a calibration's step; 0.05 for 5 %).
    #[arg(long)]
    pub mu0_step: Option<f64>,
    /// Designs as N:T pairs (default: the reference study's nine, N 9, 11, 13 × T 1.6, 2.0, 2.4).
    #[arg(long, value_delimiter = ',')]
    pub designs: Vec<String>,
    /// Mesh level.
    #[arg(long, default_value = "coarse")]
    pub mesh: String,
    /// Rig: bending or force.
    #[arg(long, default_value = "bending")]
    pub mode: String,
    /// Pressures (bar).
    #[arg(long, default_value = "0,1,2,3")]
    pub pressures: String,
    /// Ways of starting to measure; the first is the reference of the differences.
    #[arg(long, value_delimiter = ',', default_value = "cold,zeroth,first")]
    pub orders: Vec<String>,
}

fn order(s: &str) -> Result<WarmOrder> {
    Ok(match s {
        "cold" => WarmOrder::Cold,
        "zeroth" => WarmOrder::Zeroth,
        "first" => WarmOrder::First,
        _ => bail!("--orders: `{s}` is not one of cold, zeroth, first"),
    })
}

fn design(s: &str) -> Result<(usize, f64)> {
    let (n, t) = s
        .split_once(':')
        .with_context(|| format!("--designs: `{s}` is not N:T (e.g. 11:2.0)"))?;
    let n = n
        .trim()
        .parse()
        .with_context(|| format!("--designs: N `{n}` is not a whole number"))?;
    let t = t
        .trim()
        .parse()
        .with_context(|| format!("--designs: T `{t}` is not a number of mm"))?;
    DesignParams::new(n, t)
        .validate()
        .with_context(|| format!("--designs: {s}"))?;
    Ok((n, t))
}

/// Runs the command.
pub fn run(a: CampaignArgs) -> Result<()> {
    if !a.bench {
        bail!("surrogate campaign: only --bench is available (the material-sweep benchmark)");
    }
    let mesh: MeshLevel = a.mesh.parse().map_err(|e| anyhow::anyhow!("--mesh: {e}"))?;
    let mode = match a.mode.as_str() {
        "bending" => Mode::Bending,
        "force" => Mode::Force,
        m => bail!("--mode: `{m}` is not one of bending, force"),
    };
    if !(a.span.is_finite() && a.span > 0.0 && a.span < 1.0) {
        bail!("--span: {} is not a relative span in (0, 1)", a.span);
    }
    if a.materials < 2 {
        bail!("--materials: {} (at least 2 for a sweep)", a.materials);
    }
    let pressures = parse_pressures(&a.pressures)?;
    let orders = a
        .orders
        .iter()
        .map(|s| order(s))
        .collect::<Result<Vec<_>>>()?;
    let designs = if a.designs.is_empty() {
        [9, 11, 13]
            .iter()
            .flat_map(|&n| [1.6, 2.0, 2.4].map(|t| (n, t)))
            .collect()
    } else {
        a.designs
            .iter()
            .map(|s| design(s))
            .collect::<Result<Vec<_>>>()?
    };
    let centre = Material::from_spec("ogden_002", DEFAULT_BULK_RATIO)?
        .ogden_set()
        .context("ogden_002 is an Ogden set")?;
    let materials = match a.mu0_step {
        Some(step) if step.is_finite() && step > -1.0 && step != 0.0 => {
            let f = 1.0 + step;
            let c = centre.as_array();
            vec![
                centre,
                OgdenSet::from_array([c[0] * f, c[1], c[2] * f, c[3]]),
            ]
        }
        Some(step) => bail!("--mu0-step: {step} is not a relative step in (-1, 0) or (0, ∞)"),
        None => bench_materials(centre, a.materials, a.span, a.seed),
    };
    let total = materials.len() * designs.len();
    let bar = ProgressBar::new((total * orders.len()) as u64).with_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} ramps, {elapsed} ({eta} left)")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let case = |m: OgdenSet, (n, t): (usize, f64)| Case {
        design: DesignParams::new(n, t)
            .validate()
            .expect("the designs were validated"),
        material: Material::new(
            MaterialLaw::Ogden(Ogden2::try_from(m).expect("inside the box")),
            DEFAULT_BULK_RATIO,
        )
        .expect("a valid Ogden set"),
        pressures_bar: pressures.clone(),
        gravity: true,
        mesh: MeshOptions::level(mesh),
        solver: SolverSettings::default(),
        mode,
        contact: ContactSettings::default(),
        effects: Effects::neutral(),
    };
    let bench = bench_material_sweep(&materials, &designs, case, &orders, |o, _, _| {
        bar.set_message(format!("{o:?}"));
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    for r in &bench.rows {
        eprintln!(
            "{:?}: {} ramps ({} warm), {:.2} Newton iterations per output level {:?}, {} \
             factorisations, {:.1} s ({:.0} % of the first row), largest tip difference {:.1e} \
             (relative), force {:.1e} N",
            r.warm,
            r.ramps,
            r.warm_ramps,
            r.iterations_per_level,
            r.iterations_per_level_by_pressure
                .iter()
                .map(|v| (v * 10.0).round() / 10.0)
                .collect::<Vec<_>>(),
            r.factorizations,
            r.wall_s,
            100.0 * r.wall_ratio,
            r.max_tip_difference,
            r.max_force_difference_n
        );
    }
    let json = serde_json::to_string_pretty(&bench)?;
    write_atomic(&a.out, json.as_bytes())
        .with_context(|| format!("writing {}", a.out.display()))?;
    eprintln!("wrote {}", a.out.display());
    Ok(())
}
