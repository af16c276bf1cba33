//! The calibration's figures: tips in the bending plane, forces, residuals over N/T/P, the
//! correlation matrix and the profiles.
use std::path::{Path, PathBuf};

use anyhow::Result;
use plotters::prelude::*;
use surrogate::calibrate::objective::Output;
use surrogate::calibrate::refine::Refinement;
use surrogate::calibrate::verify::{FeCheckRow, FeVerification};
use surrogate::calibrate::Calibration;

use crate::figure::{axis_range, colour};

fn levels(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut l: Vec<f64> = v.collect();
    l.sort_by(f64::total_cmp);
    l.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    l
}

fn color_of(levels: &[f64], v: f64) -> RGBColor {
    let i = levels
        .iter()
        .position(|l| (l - v).abs() < 1e-9)
        .unwrap_or(0);
    colour(i)
}

/// Writes every figure into `dir`; returns the paths.
///
/// # Errors
/// A drawing or file error.
pub fn write_plots(
    cal: &Calibration,
    fe: Option<&FeVerification>,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    let p = dir.join("tips.svg");
    tips(cal, fe, &p)?;
    out.push(p);
    if cal.configurations.iter().any(|r| r.force_exp_n.is_finite()) {
        let p = dir.join("forces.svg");
        forces(cal, fe, &p)?;
        out.push(p);
    }
    let p = dir.join("residuals.svg");
    residuals(cal, &p)?;
    out.push(p);
    let p = dir.join("correlation.svg");
    correlation(cal, &p)?;
    out.push(p);
    let p = dir.join("profiles.svg");
    profiles(cal, &p)?;
    out.push(p);
    Ok(out)
}

const LF: f64 = 92.0;

/// The caption's promise of FE markers: made only when the FE ran and gave at least one
/// finite value of the plotted output.
fn fe_legend(fe: Option<&FeVerification>, value: impl Fn(&FeCheckRow) -> f64) -> &'static str {
    let ran = fe.is_some_and(|v| v.rows.iter().any(|r| value(r).is_finite()));
    if ran {
        ", FE at the optimum (□)"
    } else {
        ""
    }
}

fn tips(cal: &Calibration, fe: Option<&FeVerification>, path: &Path) -> Result<()> {
    let rows = &cal.configurations;
    let ts = levels(rows.iter().map(|r| r.wall_thickness_mm));
    let mut zs: Vec<f64> = Vec::new();
    let mut ys: Vec<f64> = Vec::new();
    for r in rows {
        zs.extend([LF - r.uz_exp_mm, LF - r.uz_lit_mm, LF - r.uz_cal_mm]);
        ys.extend([r.uy_exp_mm, r.uy_lit_mm, r.uy_cal_mm]);
    }
    if let Some(v) = fe {
        for r in &v.rows {
            zs.push(LF - r.fe.uz_sim_mm);
            ys.push(r.fe.uy_sim_mm);
        }
    }
    let (x0, x1) = axis_range(zs);
    let (y0, y1) = axis_range(ys);
    let root = SVGBackend::new(path, (900, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut ch = ChartBuilder::on(&root)
        .caption(
            format!(
                "Tip positions, all configurations: measured (×), literature set (○), calibrated (●){}",
                fe_legend(fe, |r| r.fe.uz_sim_mm)
            ),
            ("sans-serif", 16),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    ch.configure_mesh()
        .x_desc("deformed tip z (mm)")
        .y_desc("deformed tip y = Uy (mm)")
        .draw()?;
    for &t in &ts {
        let c = color_of(&ts, t);
        let sel: Vec<_> = rows
            .iter()
            .filter(|r| (r.wall_thickness_mm - t).abs() < 1e-9)
            .collect();
        ch.draw_series(
            sel.iter()
                .map(|r| Cross::new((LF - r.uz_exp_mm, r.uy_exp_mm), 6, c.stroke_width(2))),
        )?
        .label(format!("T = {t} mm"))
        .legend(move |(x, y)| Cross::new((x + 8, y), 5, c.stroke_width(2)));
        ch.draw_series(
            sel.iter()
                .map(|r| Circle::new((LF - r.uz_lit_mm, r.uy_lit_mm), 4, c.stroke_width(1))),
        )?;
        ch.draw_series(
            sel.iter()
                .map(|r| Circle::new((LF - r.uz_cal_mm, r.uy_cal_mm), 4, c.filled())),
        )?;
        // measured → calibrated
        for r in &sel {
            ch.draw_series(LineSeries::new(
                [
                    (LF - r.uz_exp_mm, r.uy_exp_mm),
                    (LF - r.uz_cal_mm, r.uy_cal_mm),
                ],
                c.mix(0.5).stroke_width(1),
            ))?;
        }
        if let Some(v) = fe {
            ch.draw_series(
                v.rows
                    .iter()
                    .filter(|r| (r.config.wall_thickness_mm - t).abs() < 1e-9)
                    .filter(|r| r.fe.uz_sim_mm.is_finite())
                    .map(|r| {
                        let (x, y) = (LF - r.fe.uz_sim_mm, r.fe.uy_sim_mm);
                        Rectangle::new([(x - 0.6, y - 0.6), (x + 0.6, y + 0.6)], c.stroke_width(1))
                    }),
            )?;
        }
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn forces(cal: &Calibration, fe: Option<&FeVerification>, path: &Path) -> Result<()> {
    let rows: Vec<_> = cal
        .configurations
        .iter()
        .filter(|r| r.force_exp_n.is_finite())
        .collect();
    let ts = levels(rows.iter().map(|r| r.wall_thickness_mm));
    let mut all: Vec<f64> = rows
        .iter()
        .flat_map(|r| [r.force_exp_n, r.force_lit_n, r.force_cal_n])
        .collect();
    if let Some(v) = fe {
        all.extend(v.rows.iter().map(|r| r.fe.force_sim_n));
    }
    let (a0, a1) = axis_range(all);
    let root = SVGBackend::new(path, (800, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut ch = ChartBuilder::on(&root)
        .caption(
            format!(
                "Blocked force: literature set (○), calibrated (●){} against measured",
                fe_legend(fe, |r| r.fe.force_sim_n)
            ),
            ("sans-serif", 16),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(a0..a1, a0..a1)?;
    ch.configure_mesh()
        .x_desc("measured blocked force (N)")
        .y_desc("predicted blocked force (N)")
        .draw()?;
    ch.draw_series(LineSeries::new([(a0, a0), (a1, a1)], BLACK.stroke_width(1)))?
        .label("predicted = measured")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    for &t in &ts {
        let c = color_of(&ts, t);
        let sel: Vec<_> = rows
            .iter()
            .filter(|r| (r.wall_thickness_mm - t).abs() < 1e-9)
            .collect();
        ch.draw_series(
            sel.iter()
                .map(|r| Circle::new((r.force_exp_n, r.force_lit_n), 4, c.stroke_width(1))),
        )?;
        ch.draw_series(
            sel.iter()
                .map(|r| Circle::new((r.force_exp_n, r.force_cal_n), 4, c.filled())),
        )?
        .label(format!("T = {t} mm"))
        .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
        if let Some(v) = fe {
            ch.draw_series(
                v.rows
                    .iter()
                    .filter(|r| (r.config.wall_thickness_mm - t).abs() < 1e-9)
                    .filter(|r| r.fe.force_sim_n.is_finite())
                    .map(|r| {
                        let (x, y) = (r.fe.force_exp_n, r.fe.force_sim_n);
                        let h = 0.01 * (a1 - a0);
                        Rectangle::new([(x - h, y - h), (x + h, y + h)], c.stroke_width(1))
                    }),
            )?;
        }
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// Standardised residuals at the optimum: one panel per output, x = T (offset by N), colour = P.
fn residuals(cal: &Calibration, path: &Path) -> Result<()> {
    let mut outputs: Vec<Output> = cal.residuals.iter().map(|r| r.output).collect();
    outputs.sort();
    outputs.dedup();
    outputs.truncate(6);
    let ps = levels(cal.residuals.iter().map(|r| r.config.pressure_bar));
    let ns = levels(cal.residuals.iter().map(|r| f64::from(r.config.n_bellows)));
    let ts = levels(cal.residuals.iter().map(|r| r.config.wall_thickness_mm));
    let root = SVGBackend::new(path, (1000, 300 * outputs.len().max(1) as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((outputs.len().max(1), 1));
    let (x0, x1) = axis_range(ts.iter().flat_map(|t| [t - 0.15, t + 0.15]));
    for (o, area) in outputs.iter().zip(panels.iter()) {
        let sel: Vec<_> = cal.residuals.iter().filter(|r| r.output == *o).collect();
        let (y0, y1) = axis_range(sel.iter().map(|r| r.standardised).chain([-2.0, 2.0]));
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!(
                    "{}: (predicted − recorded)/σ at the optimum; x offset by N ({})",
                    o.name(),
                    ns.iter()
                        .map(|n| n.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                ("sans-serif", 14),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(50)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        ch.configure_mesh()
            .x_desc("wall thickness T (mm)")
            .y_desc("standardised residual (1)")
            .draw()?;
        for z in [-2.0, 0.0, 2.0] {
            ch.draw_series(LineSeries::new([(x0, z), (x1, z)], BLACK.mix(0.4)))?;
        }
        for &p in &ps {
            let c = color_of(&ps, p);
            ch.draw_series(
                sel.iter()
                    .filter(|r| (r.config.pressure_bar - p).abs() < 1e-9)
                    .map(|r| {
                        let k = ns
                            .iter()
                            .position(|&n| n == f64::from(r.config.n_bellows))
                            .unwrap_or(0) as f64;
                        let dx = 0.1 * (k - (ns.len() as f64 - 1.0) / 2.0);
                        Circle::new(
                            (r.config.wall_thickness_mm + dx, r.standardised),
                            4,
                            c.filled(),
                        )
                    }),
            )?
            .label(format!("P = {p} bar"))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE)
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

fn correlation(cal: &Calibration, path: &Path) -> Result<()> {
    let id = &cal.identifiability;
    let n = id.names.len();
    let root = SVGBackend::new(path, (640, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut ch = ChartBuilder::on(&root)
        .caption(
            "Correlation of the estimates (blue −1 … red +1)",
            ("sans-serif", 16),
        )
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(100)
        .build_cartesian_2d(0.0..n as f64, 0.0..n as f64)?;
    let names = id.names.clone();
    let names_y = id.names.clone();
    ch.configure_mesh()
        .disable_mesh()
        .x_labels(n)
        .y_labels(n)
        .x_label_formatter(&move |v| names.get(v.floor() as usize).cloned().unwrap_or_default())
        .y_label_formatter(&move |v| {
            names_y
                .get(n - 1 - (v.floor() as usize).min(n - 1))
                .cloned()
                .unwrap_or_default()
        })
        .draw()?;
    for i in 0..n {
        for j in 0..n {
            let r = id.correlation[i][j];
            let c = if r.is_finite() {
                let a = r.abs().min(1.0);
                if r >= 0.0 {
                    RGBColor(255, (255.0 * (1.0 - a)) as u8, (255.0 * (1.0 - a)) as u8)
                } else {
                    RGBColor((255.0 * (1.0 - a)) as u8, (255.0 * (1.0 - a)) as u8, 255)
                }
            } else {
                RGBColor(200, 200, 200)
            };
            let (x, y) = (j as f64, (n - 1 - i) as f64);
            ch.draw_series(std::iter::once(Rectangle::new(
                [(x, y), (x + 1.0, y + 1.0)],
                c.filled(),
            )))?;
            let label = if r.is_finite() {
                format!("{r:+.2}")
            } else {
                "n/a".into()
            };
            ch.draw_series(std::iter::once(Text::new(
                label,
                (x + 0.35, y + 0.55),
                ("sans-serif", 16),
            )))?;
        }
    }
    root.present()?;
    Ok(())
}

fn profiles(cal: &Calibration, path: &Path) -> Result<()> {
    let id = &cal.identifiability;
    let root = SVGBackend::new(path, (1000, 800)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((2, 2));
    for (p, area) in id.profiles.iter().zip(panels.iter()) {
        let (x0, x1) = axis_range(p.values.iter().copied().chain(p.range));
        let (_, y1) = axis_range(p.delta_chi2.iter().copied().chain([p.threshold * 1.5]));
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!("profile of {} ({})", p.name, p.determinacy.describe()),
                ("sans-serif", 13),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(x0..x1, 0.0..y1)?;
        ch.configure_mesh()
            .x_desc(p.name.as_str())
            .y_desc("Δχ² (profile)")
            .draw()?;
        ch.draw_series(LineSeries::new(
            p.values
                .iter()
                .zip(&p.delta_chi2)
                .map(|(&x, &y)| (x, y.max(0.0))),
            colour(0).stroke_width(2),
        ))?
        .label("profile Δχ²")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour(0)));
        ch.draw_series(LineSeries::new(
            [(x0, p.threshold), (x1, p.threshold)],
            colour(1).stroke_width(1),
        ))?
        .label("95 % threshold")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour(1)));
        ch.draw_series(std::iter::once(Circle::new(
            (p.optimum, 0.0),
            5,
            BLACK.filled(),
        )))?;
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE)
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// The refinement's rounds: `(FE − surrogate)/σ` of tip Uz, tip Uy and force per configuration,
/// one colour per round, with the ±2σ band that decides a disagreement.
pub fn refinement(r: &Refinement, path: &Path) -> Result<()> {
    let mut sets: Vec<(String, &FeVerification)> = r
        .rounds
        .iter()
        .map(|x| {
            (
                format!("round {} ({} training cases)", x.round, x.model_cases),
                &x.verification,
            )
        })
        .collect();
    if let Some(c) = &r.final_check {
        sets.push((
            format!("retrained ({} cases), same set", r.last_model_cases),
            c,
        ));
    }
    let z = |v: &FeVerification| -> Vec<[f64; 3]> {
        v.rows
            .iter()
            .map(|row| {
                let fe = [row.fe.uz_sim_mm, row.fe.uy_sim_mm, row.fe.force_sim_n];
                let su = [row.uz_sur_mm, row.uy_sur_mm, row.force_sur_n];
                std::array::from_fn(|k| (fe[k] - su[k]) / row.sur_std[k])
            })
            .collect()
    };
    let all: Vec<f64> = sets
        .iter()
        .flat_map(|(_, v)| z(v).into_iter().flatten())
        .filter(|x| x.is_finite())
        .chain([-2.5, 2.5])
        .collect();
    let (y0, y1) = axis_range(all);
    let n = sets.first().map_or(1, |(_, v)| v.rows.len()).max(1);
    let root = SVGBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((3, 1));
    let names = ["tip Uz", "tip Uy", "blocked force"];
    for (k, area) in panels.iter().enumerate() {
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!(
                    "{}: (FE − surrogate) / surrogate σ at each round's calibrated set",
                    names[k]
                ),
                ("sans-serif", 15),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(50)
            .build_cartesian_2d(-0.5..(n as f64 - 0.5), y0..y1)?;
        ch.configure_mesh()
            .x_desc("configuration (N, then T, then P)")
            .y_desc("(FE − surrogate) / σ")
            .draw()?;
        for b in [-2.0, 2.0] {
            ch.draw_series(LineSeries::new(
                [(-0.5, b), (n as f64 - 0.5, b)],
                BLACK.stroke_width(1),
            ))?;
        }
        for (i, (label, v)) in sets.iter().enumerate() {
            let c = colour(i);
            let pts: Vec<(f64, f64)> = z(v)
                .iter()
                .enumerate()
                .map(|(j, q)| (j as f64 + 0.1 * i as f64, q[k]))
                .filter(|p| p.1.is_finite())
                .collect();
            let s = ch.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
            if k == 0 {
                let l = label.clone();
                s.label(l)
                    .legend(move |(x, y)| Circle::new((x + 8, y), 3, c.filled()));
            }
        }
        if k == 0 {
            ch.configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE)
                .border_style(BLACK)
                .draw()?;
        }
    }
    root.present()?;
    Ok(())
}
