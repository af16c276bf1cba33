//! The diagnosis' figures: the residual map (design × pressure per output), the residual over
//! T per output with its significant structure, and the residual along the actuator where
//! markers were recorded. Each is drawn into memory and written atomically.
use std::path::{Path, PathBuf};

use anyhow::Result;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use surrogate::diagnose::cells::{Cell, Family};
use surrogate::diagnose::structure::Term;
use surrogate::diagnose::Localisation;

use crate::figure::{axis_range, colour, symmetric_range};
use crate::files::write_file;

fn levels(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut l: Vec<f64> = v.collect();
    l.sort_by(f64::total_cmp);
    l.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    l
}

fn index_of(levels: &[f64], v: f64) -> usize {
    levels
        .iter()
        .position(|l| (l - v).abs() < 1e-9)
        .unwrap_or(0)
}

/// The scalar outputs present, in report order.
fn scalar_families(l: &Localisation) -> Vec<Family> {
    [Family::TipUz, Family::TipUy, Family::Angle, Family::Force]
        .into_iter()
        .filter(|&f| l.cells_of(f).next().is_some())
        .collect()
}

/// Writes every figure into `dir`; returns the paths.
///
/// # Errors
/// A drawing or file error.
pub fn write_plots(l: &Localisation, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    let fams = scalar_families(l);
    let n = fams.len().max(1) as u32;
    let figures: [(&str, (u32, u32), DrawFn); 3] = [
        ("residual_map.svg", (330 * n + 120, 560), residual_map),
        ("residual_trends.svg", (1000, 300 * n), residual_trends),
        ("along_actuator.svg", (1000, 640), along_actuator),
    ];
    for (name, size, draw) in figures {
        if name == "along_actuator.svg" && !l.along_actuator {
            continue;
        }
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            root.fill(&WHITE)?;
            draw(l, &root)?;
            root.present()?;
        }
        let p = dir.join(name);
        write_file(&p, svg.as_bytes())?;
        out.push(p);
    }
    Ok(out)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type DrawFn = for<'a, 'b> fn(&'a Localisation, &'a Area<'b>) -> Result<()>;

/// Blue (z < 0) – white – red (z > 0), saturated at `|z| = m`.
fn diverging(z: f64, m: f64) -> RGBColor {
    let a = (z.abs() / m).clamp(0.0, 1.0);
    let fade = (255.0 * (1.0 - a)) as u8;
    if z >= 0.0 {
        RGBColor(255, fade, fade)
    } else {
        RGBColor(fade, fade, 255)
    }
}

/// One panel per output: designs down, pressures across, each cell coloured by z (its own
/// scale per output) with its value written in.
fn residual_map(l: &Localisation, root: &Area<'_>) -> Result<()> {
    let fams = scalar_families(l);
    let (title, body) = root.split_vertically(40);
    title.draw(&Text::new(
        "Residual map: z = (predicted − recorded)/σ per design and pressure (red: predicted above recorded)",
        (10, 12),
        ("sans-serif", 16),
    ))?;
    let mut designs: Vec<(u32, f64)> = l
        .cells
        .iter()
        .map(|c| (c.n_bellows, c.wall_thickness_mm))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    let ps = levels(l.cells.iter().map(|c| c.pressure_bar));
    let (labels, panels) = body.split_horizontally(120);
    let nd = designs.len();
    // the rows of the panels: below a caption of about 30 px, nd rows over nd + 0.5 units
    let h = panels.dim_in_pixel().1 as f64 - 40.0;
    let row_h = h / (nd as f64 + 0.5);
    for (k, d) in designs.iter().enumerate() {
        labels.draw(&Text::new(
            format!("N = {}, T = {} mm", d.0, d.1),
            (8, 30 + (row_h * (k as f64 + 0.45)) as i32),
            ("sans-serif", 13),
        ))?;
    }
    let areas = panels.split_evenly((1, fams.len().max(1)));
    for (f, area) in fams.iter().zip(areas.iter()) {
        map_panel(l, *f, area, &designs, &ps)?;
    }
    Ok(())
}

/// One output's panel of the residual map.
fn map_panel(
    l: &Localisation,
    f: Family,
    area: &Area<'_>,
    designs: &[(u32, f64)],
    ps: &[f64],
) -> Result<()> {
    let nd = designs.len();
    let cells: Vec<&Cell> = l.cells_of(f).collect();
    let (_, m) = symmetric_range(cells.iter().map(|c| c.standardised));
    let fitted = cells.iter().any(|c| c.fitted);
    let mut ch = ChartBuilder::on(area)
        .caption(
            format!(
                "{}{} (colour ±{:.1})",
                f.label(),
                if fitted { "" } else { ", not fitted" },
                m
            ),
            ("sans-serif", 14),
        )
        .margin(5)
        .build_cartesian_2d(0.0..ps.len() as f64, -0.5..nd as f64)?;
    for (i, p) in ps.iter().enumerate() {
        ch.draw_series(std::iter::once(Text::new(
            format!("P = {p} bar"),
            (i as f64 + 0.22, -0.2),
            ("sans-serif", 13),
        )))?;
    }
    for c in &cells {
        let i = index_of(ps, c.pressure_bar) as f64;
        let j = designs
            .iter()
            .position(|d| d.0 == c.n_bellows && (d.1 - c.wall_thickness_mm).abs() < 1e-9)
            .unwrap_or(0);
        let y = (nd - 1 - j) as f64;
        ch.draw_series(std::iter::once(Rectangle::new(
            [(i + 0.03, y + 0.03), (i + 0.97, y + 0.97)],
            diverging(c.standardised, m).filled(),
        )))?;
        ch.draw_series(std::iter::once(Text::new(
            format!("{:+.1}", c.standardised),
            (i + 0.3, y + 0.6),
            ("sans-serif", 13),
        )))?;
    }
    Ok(())
}

/// The levels of the factors over the table, and the x range of the trend panels.
struct Levels {
    ts: Vec<f64>,
    ns: Vec<f64>,
    ps: Vec<f64>,
    x: (f64, f64),
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// One panel per output: z against T (offset by N), colour per N, shape per P, and the
/// significant structure along T (the others at their centre).
fn residual_trends(l: &Localisation, root: &Area<'_>) -> Result<()> {
    let fams = scalar_families(l);
    let panels = root.split_evenly((fams.len().max(1), 1));
    let ts = levels(l.cells.iter().map(|c| c.wall_thickness_mm));
    // room on the right for the legend
    let (x0, x1) = axis_range(ts.iter().flat_map(|t| [t - 0.15, t + 0.15]));
    let lv = Levels {
        ns: levels(l.cells.iter().map(|c| f64::from(c.n_bellows))),
        ps: levels(l.cells.iter().map(|c| c.pressure_bar)),
        ts,
        x: (x0, x1 + 0.45 * (x1 - x0)),
    };
    for (f, area) in fams.iter().zip(panels.iter()) {
        trend_panel(l, *f, area, &lv)?;
    }
    Ok(())
}

/// One output's panel of the trends.
fn trend_panel(l: &Localisation, f: Family, area: &Area<'_>, lv: &Levels) -> Result<()> {
    let (x0, x1) = lv.x;
    let cells: Vec<&Cell> = l.cells_of(f).collect();
    let st = l.structure(f);
    let (a, b) = (lv.ts[0] - 0.15, lv.ts[lv.ts.len() - 1] + 0.15);
    let line: Vec<(f64, f64)> = match st.filter(|s| s.explained_by_significant > 0.0) {
        Some(s) => (0..=20)
            .map(|i| {
                let t = a + (b - a) * f64::from(i) / 20.0;
                (t, s.along(Term::T, t, true))
            })
            .collect(),
        None => Vec::new(),
    };
    let (y0, y1) = axis_range(
        cells
            .iter()
            .map(|c| c.standardised)
            .chain(line.iter().map(|p| p.1))
            .chain([-2.0, 2.0]),
    );
    let explained = st.map_or(0.0, |s| 100.0 * s.explained_by_significant);
    let fitted = if cells.iter().any(|c| c.fitted) {
        ""
    } else {
        " (not fitted)"
    };
    let mut ch = ChartBuilder::on(area)
        .caption(
            format!(
                "{}{fitted}: significant structure explains {explained:.0} % of its χ²",
                f.label()
            ),
            ("sans-serif", 14),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    ch.configure_mesh()
        .x_desc("wall thickness T (mm), points offset by N")
        .y_desc("z = (predicted − recorded)/σ (1)")
        .draw()?;
    for z in [-2.0, 0.0, 2.0] {
        ch.draw_series(LineSeries::new([(x0, z), (x1, z)], BLACK.mix(0.3)))?;
    }
    if !line.is_empty() {
        ch.draw_series(LineSeries::new(line, BLACK.stroke_width(2)))?
            .label("significant structure (N, P at their mean)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    }
    trend_points(&mut ch, &cells, lv)?;
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// The cells of a trend panel (colour per N, shape per P) and the legend of the shapes.
fn trend_points<'a, 'b: 'a>(ch: &mut Chart<'a, 'b>, cells: &[&Cell], lv: &Levels) -> Result<()> {
    for (kn, &n) in lv.ns.iter().enumerate() {
        let style = colour(kn).filled();
        let dx = 0.08 * (kn as f64 - (lv.ns.len() as f64 - 1.0) / 2.0);
        for (kp, &p) in lv.ps.iter().enumerate() {
            let at: Vec<(f64, f64)> = cells
                .iter()
                .filter(|x| f64::from(x.n_bellows) == n && (x.pressure_bar - p).abs() < 1e-9)
                .map(|x| (x.wall_thickness_mm + dx, x.standardised))
                .collect();
            let anno = match kp % 4 {
                0 => ch.draw_series(at.into_iter().map(|q| Circle::new(q, 4, style)))?,
                1 => ch.draw_series(at.into_iter().map(|q| TriangleMarker::new(q, 5, style)))?,
                2 => ch
                    .draw_series(at.into_iter().map(|q| {
                        EmptyElement::at(q) + Rectangle::new([(-4, -4), (4, 4)], style)
                    }))?,
                _ => ch.draw_series(at.into_iter().map(|q| Cross::new(q, 5, style)))?,
            };
            if kp == 0 {
                anno.label(format!("N = {n}"))
                    .legend(move |(x, y)| Circle::new((x + 8, y), 4, style));
            }
        }
    }
    for (kp, &p) in lv.ps.iter().enumerate() {
        let entry = ch.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?;
        entry.label(format!("P = {p} bar"));
        let style = BLACK.filled();
        match kp % 4 {
            0 => entry.legend(move |(x, y)| Circle::new((x + 8, y), 4, style)),
            1 => entry.legend(move |(x, y)| TriangleMarker::new((x + 8, y), 5, style)),
            2 => entry.legend(move |(x, y)| {
                EmptyElement::at((x + 8, y)) + Rectangle::new([(-4, -4), (4, 4)], style)
            }),
            _ => entry.legend(move |(x, y)| Cross::new((x + 8, y), 5, style)),
        };
    }
    Ok(())
}

/// One panel per marker component: z of every cell against the marker number, colour per
/// pressure, and the mean per marker.
fn along_actuator(l: &Localisation, root: &Area<'_>) -> Result<()> {
    let panels = root.split_evenly((2, 1));
    let ps = levels(l.cells.iter().map(|c| c.pressure_bar));
    for (f, area) in [Family::MarkerUz, Family::MarkerUy]
        .iter()
        .zip(panels.iter())
    {
        let cells: Vec<&Cell> = l.cells_of(*f).collect();
        let (y0, y1) = axis_range(cells.iter().map(|c| c.standardised).chain([-2.0, 2.0]));
        let mut ch = ChartBuilder::on(area)
            .caption(
                format!(
                    "{}: z along the actuator (marker k at k·Lf/9 from the support; 9 is the tip)",
                    f.label()
                ),
                ("sans-serif", 14),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(0.5..11.0, y0..y1)?;
        ch.configure_mesh()
            .x_labels(11)
            .x_label_formatter(&|v| {
                if (1.0..=9.0).contains(v) {
                    format!("{v:.0}")
                } else {
                    String::new()
                }
            })
            .x_desc("marker k (1)")
            .y_desc("z = (predicted − recorded)/σ (1)")
            .draw()?;
        ch.draw_series(LineSeries::new([(0.5, 0.0), (11.0, 0.0)], BLACK.mix(0.3)))?;
        for (kp, &p) in ps.iter().enumerate() {
            let c = colour(kp);
            let dx = 0.12 * (kp as f64 - (ps.len() as f64 - 1.0) / 2.0);
            ch.draw_series(
                cells
                    .iter()
                    .filter(|x| (x.pressure_bar - p).abs() < 1e-9)
                    .filter_map(|x| {
                        x.marker.map(|k| {
                            Circle::new((f64::from(k) + dx, x.standardised), 3, c.filled())
                        })
                    }),
            )?
            .label(format!("P = {p} bar"))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
        }
        let means: Vec<(f64, f64)> = (1..=9u8)
            .filter_map(|k| {
                let v: Vec<f64> = cells
                    .iter()
                    .filter(|c| c.marker == Some(k))
                    .map(|c| c.standardised)
                    .collect();
                (!v.is_empty()).then(|| (f64::from(k), v.iter().sum::<f64>() / v.len() as f64))
            })
            .collect();
        ch.draw_series(LineSeries::new(means, BLACK.stroke_width(2)))?
            .label("mean per marker")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE)
            .border_style(BLACK)
            .draw()?;
    }
    Ok(())
}
