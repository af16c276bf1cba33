//! `surrogate validate`: the FE model (with contact) against all experimental configurations
//! for one material; CSV table, SVG plot, summary on stdout.
use std::path::Path;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use plotters::prelude::*;
use surrogate::calibrate::baseline::{
    cached_ramps, recorded_designs, run_baseline, summarize, BaselineRow, SweepSensitivities,
    SweepSettings,
};
use surrogate::calibrate::experiments::{shipped_bending, shipped_force};
use surrogate::fe::effects::Effects;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::sensitivity::Parameter;
use surrogate::fe::simulate::ContactSettings;

use crate::args::ValidateArgs;
use crate::figure::{axis_range_with, colour};

/// Runs the subcommand.
pub fn run(a: ValidateArgs) -> Result<()> {
    if a.plot_only {
        return plot_only(&a);
    }
    let level: MeshLevel = a.mesh.parse().map_err(anyhow::Error::msg)?;
    let material = Material::from_spec(&a.material, 1000.0)?;
    let contact = ContactSettings {
        enabled: true,
        stiffness: a.contact_stiffness,
        smoothing: a.contact_smoothing,
        closest_point: a.closest_point_contact,
    };
    contact.validate()?;
    let bending = shipped_bending()?;
    let force = shipped_force()?;
    let cache = a.cache.clone().unwrap_or_else(|| {
        let stem = a
            .out
            .file_stem()
            .map_or("baseline".into(), |s| s.to_string_lossy().into_owned());
        a.out.with_file_name(format!("{stem}_ramps"))
    });
    eprintln!(
        "FE ramps cached in {} (a rerun resumes from there)",
        cache.display()
    );
    let bar = ProgressBar::new(0);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} FE ramps [{bar:30}] {pos}/{len}, {elapsed_precise}, eta {eta}",
    )?);
    let settings = SweepSettings {
        contact,
        effects: Effects::parse(a.effect.iter().map(String::as_str))?,
        sensitivities: match &a.sensitivities {
            Some(list) => Parameter::parse_list(list).context("--sensitivities")?,
            None => Vec::new(),
        },
        geometry: surrogate::fe::preset::Geometry::from_name(&a.geometry).context("--geometry")?,
        ..SweepSettings::new(
            material,
            MeshOptions {
                level,
                element_size: a.element_size,
                wall_elements: None,
            },
        )
    };
    if !settings.effects.is_neutral() {
        eprintln!(
            "effects: {}",
            serde_json::to_string(&settings.effects).context("effects as JSON")?
        );
    }
    let rows = run_baseline(&settings, &bending, &force, Some(&cache), |k, n| {
        bar.set_length(n as u64);
        bar.set_position(k as u64);
    })?;
    bar.finish_and_clear();
    if !settings.sensitivities.is_empty() {
        // read back from the cache the sweep just filled: no FE
        let ramps = cached_ramps(&settings, &recorded_designs(&bending), &cache)?;
        let sens = SweepSensitivities::of(&settings, &ramps);
        let stem = a
            .out
            .file_stem()
            .map_or("baseline".into(), |s| s.to_string_lossy().into_owned());
        let path = a.out.with_file_name(format!("{stem}_sensitivities.json"));
        crate::files::write_file(&path, serde_json::to_string(&sens)?.as_bytes())?;
        eprintln!(
            "wrote the sensitivities of {} ramps to {}{}",
            sens.designs.len(),
            path.display(),
            if sens.missing.is_empty() {
                String::new()
            } else {
                format!(" (missing: {})", sens.missing.join("; "))
            }
        );
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in &rows {
        w.serialize(r)?;
    }
    let table = w.into_inner().context("CSV buffer")?;
    crate::files::write_file(&a.out, &table)?;
    let svg = a.out.with_extension("svg");
    plot(&svg, &rows, &a.material)?;
    let s = summarize(&rows);
    println!(
        "{}: {} configurations ({} not reached), mean BE {:.2} mm, median BE {:.2} mm, mean |F error| {:.3} N, \
         mean F error {:+.3} N",
        a.material,
        s.configurations,
        s.failed,
        s.mean_be_mm,
        s.median_be_mm,
        s.mean_abs_force_error_n,
        s.mean_force_error_n
    );
    println!(
        "  the reference study's nine ({} configurations, T and P together): mean BE {:.2} mm, median BE {:.2} mm; at {} bar: mean F error {:+.3} N",
        s.paper_nine_configurations,
        s.paper_nine_mean_be_mm,
        s.paper_nine_median_be_mm,
        s.top_pressure_bar,
        s.mean_force_error_top_pressure_n
    );
    println!("wrote {} and {}", a.out.display(), svg.display());
    Ok(())
}

/// Free length of the experimental actuators (mm): tip position `z = Lf − Uz`.
const LF: f64 = 92.0;

/// Tip positions `(z, y)` in mm, measured and simulated, of every row.
fn tips(rows: &[BaselineRow]) -> Vec<(f64, f64)> {
    rows.iter()
        .flat_map(|r| {
            [
                (LF - r.uz_exp_mm, r.uy_exp_mm),
                (LF - r.uz_sim_mm, r.uy_sim_mm),
            ]
        })
        .collect()
}

/// Axis ranges `(z, y)` of the tip panel: every tip, the support (0, 0) and the unloaded
/// tip (Lf, 0).
pub fn tip_axes(rows: &[BaselineRow]) -> ((f64, f64), (f64, f64)) {
    let t = tips(rows);
    (
        axis_range_with(t.iter().map(|p| p.0), &[0.0, LF]),
        axis_range_with(t.iter().map(|p| p.1), &[0.0]),
    )
}

/// Axis range of the force panel (both axes, with zero): every measured and simulated force.
pub fn force_axes(rows: &[BaselineRow]) -> (f64, f64) {
    axis_range_with(
        rows.iter().flat_map(|r| [r.force_exp_n, r.force_sim_n]),
        &[0.0],
    )
}

/// Measured vs simulated tip positions (left, coloured by design) and blocked forces (right,
/// coloured by pressure), with legends and units.
fn plot(path: &Path, rows: &[BaselineRow], material: &str) -> Result<()> {
    let root = SVGBackend::new(path, (1200, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(680);
    let ((z_lo, z_hi), (y_lo, y_hi)) = tip_axes(rows);
    let mut c = ChartBuilder::on(&left)
        .caption(
            format!("Tip position, {material}: measured (circles) vs FE (crosses)"),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(z_lo..z_hi, y_lo..y_hi)?;
    c.configure_mesh()
        .x_desc("tip z, from the support (mm)")
        .y_desc("tip y (mm)")
        .draw()?;
    let mut designs: Vec<(usize, f64)> = rows
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    for (k, &(n, t)) in designs.iter().enumerate() {
        let col = colour(k);
        let mine: Vec<&BaselineRow> = rows
            .iter()
            .filter(|r| r.n_bellows == n && r.wall_thickness_mm == t)
            .collect();
        for r in &mine {
            let e = (LF - r.uz_exp_mm, r.uy_exp_mm);
            let s = (LF - r.uz_sim_mm, r.uy_sim_mm);
            if s.0.is_finite() && s.1.is_finite() {
                c.draw_series(std::iter::once(Cross::new(s, 6, col.stroke_width(2))))?;
                c.draw_series(LineSeries::new(vec![e, s], col.stroke_width(1)))?;
            }
        }
        c.draw_series(
            mine.iter()
                .map(|r| Circle::new((LF - r.uz_exp_mm, r.uy_exp_mm), 5, col.stroke_width(2))),
        )?
        .label(format!("N = {n}, T = {t} mm"))
        .legend(move |(x, y)| Circle::new((x, y), 5, col.filled()));
    }
    c.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 13))
        .draw()?;
    let (f_lo, f_hi) = force_axes(rows);
    let mut f = ChartBuilder::on(&right)
        .caption("Blocked force: FE vs measured", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(f_lo..f_hi, f_lo..f_hi)?;
    f.configure_mesh()
        .x_desc("measured blocked force (N)")
        .y_desc("FE blocked force (N)")
        .draw()?;
    f.draw_series(LineSeries::new(
        vec![(f_lo, f_lo), (f_hi, f_hi)],
        BLACK.mix(0.5),
    ))?
    .label("FE = measured")
    .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK.mix(0.5)));
    let mut levels: Vec<f64> = rows.iter().map(|r| r.pressure_bar).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    for (k, &p) in levels.iter().enumerate() {
        let col = colour(k);
        f.draw_series(
            rows.iter()
                .filter(|r| r.pressure_bar == p && r.force_sim_n.is_finite())
                .map(|r| Circle::new((r.force_exp_n, r.force_sim_n), 5, col.filled())),
        )?
        .label(format!("{p} bar"))
        .legend(move |(x, y)| Circle::new((x, y), 5, col.filled()));
    }
    f.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 13))
        .draw()?;
    root.present()?;
    Ok(())
}

/// `--plot-only`: the figure of an existing baseline CSV, no FE run.
fn plot_only(a: &ValidateArgs) -> Result<()> {
    let mut r = csv::Reader::from_path(&a.out)
        .with_context(|| format!("reading {} (--plot-only)", a.out.display()))?;
    let rows: Vec<BaselineRow> = r
        .deserialize()
        .collect::<Result<_, _>>()
        .with_context(|| format!("reading {}", a.out.display()))?;
    anyhow::ensure!(!rows.is_empty(), "{}: no rows to plot", a.out.display());
    let svg = a.out.with_extension("svg");
    plot(&svg, &rows, &a.material)?;
    eprintln!(
        "wrote {} ({} configurations of {})",
        svg.display(),
        rows.len(),
        a.out.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::holds;

    fn row(n: usize, uz: f64, uy: f64, f_exp: f64, f_sim: f64) -> BaselineRow {
        BaselineRow {
            n_bellows: n,
            wall_thickness_mm: 1.6,
            pressure_bar: 3.0,
            uz_exp_mm: uz,
            uz_sim_mm: uz + 5.0,
            uy_exp_mm: uy,
            uy_sim_mm: uy - 3.0,
            angle_exp_deg: f64::NAN,
            angle_sim_deg: f64::NAN,
            be_mm: f64::NAN,
            force_exp_n: f_exp,
            force_sim_n: f_sim,
            force_error_n: f_sim - f_exp,
            error: String::new(),
        }
    }

    /// A tip curled back past the support (z < 0) and one barely bent: both inside the panel,
    /// not on its border; the forces too, with NaN (a ramp not reached) ignored.
    #[test]
    fn baseline_axes_hold_every_point() {
        let rows = vec![
            row(9, 110.0, -60.0, 4.4, 4.0),
            row(11, 1.0, -8.0, 0.2, f64::NAN),
            row(13, 40.0, -95.0, 2.9, 2.2),
        ];
        let (zr, yr) = tip_axes(&rows);
        let t = tips(&rows);
        assert!(holds(zr, t.iter().map(|p| p.0)) && holds(yr, t.iter().map(|p| p.1)));
        assert!(zr.0 < LF - 115.0 && yr.0 < -98.0, "{zr:?} {yr:?}");
        let fr = force_axes(&rows);
        assert!(holds(
            fr,
            rows.iter().flat_map(|r| [r.force_exp_n, r.force_sim_n])
        ));
    }
}
