//! `surrogate validate`: the FE model (with contact) against all experimental configurations
//! for one material; CSV table, SVG plot, summary on stdout.
use std::path::Path;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use plotters::prelude::*;
use surrogate::calibrate::baseline::{run_baseline, summarize, BaselineRow};
use surrogate::calibrate::experiments::{shipped_bending, shipped_force};
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::ContactSettings;

use crate::args::ValidateArgs;

/// Runs the subcommand.
pub fn run(a: ValidateArgs) -> Result<()> {
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
    let rows = run_baseline(
        &material,
        MeshOptions {
            level,
            element_size: a.element_size,
            wall_elements: None,
        },
        contact,
        &bending,
        &force,
        Some(&cache),
        |k, n| {
            bar.set_length(n as u64);
            bar.set_position(k as u64);
        },
    )?;
    bar.finish_and_clear();
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let tmp = a.out.with_extension("csv.tmp");
    {
        let mut w =
            csv::Writer::from_path(&tmp).with_context(|| format!("writing {}", tmp.display()))?;
        for r in &rows {
            w.serialize(r)?;
        }
        w.flush()?;
    }
    std::fs::rename(&tmp, &a.out)?;
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
        "  L9 subset ({} configurations): mean BE {:.2} mm, median BE {:.2} mm; at {} bar: mean F error {:+.3} N",
        s.l9_configurations,
        s.l9_mean_be_mm,
        s.l9_median_be_mm,
        s.top_pressure_bar,
        s.mean_force_error_top_pressure_n
    );
    println!("wrote {} and {}", a.out.display(), svg.display());
    Ok(())
}

/// Measured vs simulated tip positions (left) and blocked forces (right).
fn plot(path: &Path, rows: &[BaselineRow], material: &str) -> Result<()> {
    let root = SVGBackend::new(path, (1100, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(600);
    // axes that hold every measured and simulated tip (a curled actuator's tip comes back
    // towards the support)
    let lf = 92.0;
    let (z_lo, y_lo) = rows
        .iter()
        .flat_map(|r| [(r.uz_exp_mm, r.uy_exp_mm), (r.uz_sim_mm, r.uy_sim_mm)])
        .filter(|(uz, uy)| uz.is_finite() && uy.is_finite())
        .fold((20.0f64, -90.0f64), |(z, y), (uz, uy)| {
            (z.min(lf - uz - 5.0), y.min(uy - 5.0))
        });
    let mut c = ChartBuilder::on(&left)
        .caption(
            format!("Tip position, {material}: measured (o) vs FE (x)"),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(z_lo..100.0, y_lo..5.0)?;
    c.configure_mesh()
        .x_desc("z_tip (mm)")
        .y_desc("y_tip (mm)")
        .draw()?;
    for r in rows {
        let col = Palette99::pick((r.n_bellows * 7 + (r.wall_thickness_mm * 10.0) as usize) % 99);
        let e = (lf - r.uz_exp_mm, r.uy_exp_mm);
        let s = (lf - r.uz_sim_mm, r.uy_sim_mm);
        c.draw_series(std::iter::once(Circle::new(e, 4, col.stroke_width(2))))?;
        c.draw_series(std::iter::once(Cross::new(s, 5, col.stroke_width(2))))?;
        c.draw_series(LineSeries::new(vec![e, s], col.mix(0.5)))?;
    }
    let fmax = rows
        .iter()
        .flat_map(|r| [r.force_exp_n, r.force_sim_n])
        .filter(|v| v.is_finite())
        .fold(1.0f64, f64::max)
        * 1.1;
    let mut f = ChartBuilder::on(&right)
        .caption("Blocked force (N)", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(0.0..fmax, 0.0..fmax)?;
    f.configure_mesh().x_desc("measured").y_desc("FE").draw()?;
    f.draw_series(LineSeries::new(
        vec![(0.0, 0.0), (fmax, fmax)],
        BLACK.mix(0.4),
    ))?;
    f.draw_series(rows.iter().filter(|r| r.force_sim_n.is_finite()).map(|r| {
        Circle::new(
            (r.force_exp_n, r.force_sim_n),
            4,
            Palette99::pick((r.pressure_bar as usize) * 20).filled(),
        )
    }))?;
    root.present()?;
    Ok(())
}
