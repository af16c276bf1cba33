//! `surrogate maps`: the outputs over the design space (N across, T up) at a few pressures, as
//! SVG heat maps with contours, and the grid as CSV (`surrogate::design::map`).
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use surrogate::design::{map, DesignError, Output};
use surrogate::rom::batch::material_params;

use crate::design::DesignRanges;

/// `surrogate maps`.
#[derive(Debug, Args)]
pub struct MapsArgs {
    /// Material: a name (ogden_002, ogden_005), `mu1,alpha1,mu2,alpha2` or a calibration
    /// report `DIR/report.json` (its calibrated set). Required: the maps depend on it.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::files::material_spec)]
    pub material: String,
    /// Model file (default: the shipped models/actuator.json of the repository the program
    /// was built from, from any working directory).
    #[arg(long, default_value_os_t = crate::files::repository_file(crate::files::DEFAULT_MODEL))]
    pub model: PathBuf,
    /// Output directory: one SVG per output (`angle_deg.svg`, …), a panel per pressure, and
    /// `maps.csv`.
    #[arg(long)]
    pub out: PathBuf,
    /// The outputs, comma-separated: angle, force, tip_uz, tip_uy.
    #[arg(long, default_value = "angle,force")]
    pub outputs: String,
    /// The pressures of the panels, bar, comma-separated.
    #[arg(long, default_value = "1,2,3")]
    pub pressures: String,
    /// `--n` and `--t`.
    #[command(flatten)]
    pub ranges: DesignRanges,
    /// Wall thicknesses on the grid, evenly spaced over --t (≥ 2).
    #[arg(long, default_value_t = 41)]
    pub t_points: usize,
}

pub fn run(a: MapsArgs) -> Result<()> {
    crate::files::announce_default("model", &a.model, crate::files::DEFAULT_MODEL);
    let model = crate::files::load_model(&a.model)?;
    let material = material_params(&a.material).context("--material")?;
    let outputs = a
        .outputs
        .split(',')
        .map(|s| s.parse::<Output>().map_err(anyhow::Error::msg))
        .collect::<Result<Vec<_>>>()
        .with_context(|| format!("--outputs {}", a.outputs))?;
    let pressures = a
        .pressures
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| {
            format!(
                "--pressures {}: expected numbers in bar, comma-separated",
                a.pressures
            )
        })?;
    let bounds = a.ranges.bounds(&model)?;
    let (n_lo, n_hi) = bounds.n;
    anyhow::ensure!(
        n_lo <= n_hi,
        "--n {n_lo}..{n_hi}: expected MIN..MAX with MIN ≤ MAX"
    );
    let n_values: Vec<u32> = model
        .n_allowed
        .iter()
        .copied()
        .filter(|n| (n_lo..=n_hi).contains(n))
        .collect();
    anyhow::ensure!(
        !n_values.is_empty(),
        "--n {n_lo}..{n_hi}: expected a range holding an N the model predicts {:?}",
        model.n_allowed
    );
    let (t_lo, t_hi) = bounds.t_mm;
    anyhow::ensure!(
        a.t_points >= 2 && t_lo < t_hi,
        "--t {t_lo}..{t_hi} with --t-points {}: expected MIN < MAX and at least 2 points",
        a.t_points
    );
    let t_grid: Vec<f64> = (0..a.t_points)
        .map(|k| t_lo + (t_hi - t_lo) * k as f64 / (a.t_points - 1) as f64)
        .collect();
    let m = map(&model, material, &outputs, &pressures, &n_values, &t_grid).map_err(named)?;
    let mut csv = Vec::new();
    m.write_csv(&mut csv)?;
    let path = a.out.join("maps.csv");
    crate::files::write_file(&path, &csv)?;
    let mut written = crate::maps_plots::write_svgs(&m, &a.out)?;
    written.push(path);
    for p in &written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

/// A library error with the flag it comes from.
fn named(e: DesignError) -> anyhow::Error {
    let DesignError::Invalid {
        field,
        value,
        expected,
    } = &e
    else {
        return e.into();
    };
    let flag = match field.split('[').next().unwrap_or("") {
        "pressures" => "--pressures",
        "t_grid" => "--t",
        "n_values" => "--n",
        "outputs" => "--outputs",
        _ => "--material",
    };
    anyhow::anyhow!("{flag}: {field} = {value}: expected {expected}")
}
