//! The figures of `surrogate maps`: per output, a heat map over N (across) and T (up) for each
//! pressure, one colour scale shared by the panels with its bar, labelled contours of each
//! panel's own range, walls that leave no cavity in grey, the trained N marked. Each figure is
//! drawn into memory and written atomically.
use std::path::{Path, PathBuf};

use anyhow::Result;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use surrogate::design::DesignMap;

use crate::files::write_file;

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Width of a pressure's panel, of the colour bar, and the figure's height (px).
const PANEL_W: u32 = 420;
const BAR_W: u32 = 120;
const HEIGHT: u32 = 620;
/// A wall that leaves no cavity.
const UNBUILDABLE: RGBColor = RGBColor(200, 200, 200);
/// Contours per panel, about.
const CONTOURS: f64 = 6.0;

/// Writes one SVG per output of `m` into `dir` (`angle_deg.svg`, …); returns the paths.
///
/// # Errors
/// A drawing or file error.
pub fn write_svgs(m: &DesignMap, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for o in 0..m.outputs.len() {
        let mut svg = String::new();
        {
            let size = (PANEL_W * m.pressures.len() as u32 + BAR_W, HEIGHT);
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            root.fill(&WHITE)?;
            figure(m, o, &root)?;
            root.present()?;
        }
        let p = dir.join(format!("{}.svg", m.outputs[o].name()));
        write_file(&p, svg.as_bytes())?;
        out.push(p);
    }
    Ok(out)
}

/// Output `o`'s figure: a title, a panel per pressure, the colour bar.
fn figure(m: &DesignMap, o: usize, root: &Area<'_>) -> Result<()> {
    let q = m.outputs[o].quantity();
    let gaps = m.n_values.windows(2).any(|w| w[1] != w[0] + 1);
    let (title, body) = root.split_vertically(56);
    title.draw(&Text::new(
        format!(
            "{} ({}) over N and T; grey: no cavity left (geometry '{}'); ▲ trained N{}",
            q.meaning,
            q.unit,
            m.geometry,
            if gaps {
                "; white: N the model does not predict"
            } else {
                ""
            }
        ),
        (10, 8),
        ("sans-serif", 16),
    ))?;
    let [mu1, a1, mu2, a2] = m.material.as_array();
    title.draw(&Text::new(
        format!(
            "material: μ₁ {mu1:.4} MPa, α₁ {a1:.3}, μ₂ {mu2:.3} MPa, α₂ {a2:.3}; one colour scale \
             for all panels, contours labelled per panel"
        ),
        (10, 32),
        ("sans-serif", 13),
    ))?;
    let (panels, bar) = body.split_horizontally(PANEL_W * m.pressures.len() as u32);
    let range = finite_range((0..m.pressures.len()).flat_map(|p| values(m, o, p)));
    for (p, area) in panels
        .split_evenly((1, m.pressures.len()))
        .iter()
        .enumerate()
    {
        panel(m, o, p, area, range)?;
    }
    colour_bar(&bar, range, q.unit)
}

/// Every value of output `o` at pressure `p`.
fn values(m: &DesignMap, o: usize, p: usize) -> impl Iterator<Item = f64> + '_ {
    (0..m.n_values.len()).flat_map(move |n| (0..m.t_mm.len()).map(move |t| m.value(o, p, n, t)))
}

/// The smallest and largest finite value (a unit range around a single value or none).
fn finite_range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if !lo.is_finite() {
        (0.0, 1.0)
    } else if hi - lo < 1e-12 * (1.0 + lo.abs()) {
        (lo - 0.5, hi + 0.5)
    } else {
        (lo, hi)
    }
}

/// The edges of the cells of the wall grid: midpoints, and half a spacing beyond each end.
fn cell_edges(t: &[f64]) -> Vec<f64> {
    if t.len() == 1 {
        return vec![t[0] - 0.05, t[0] + 0.05];
    }
    let mut e = vec![t[0] - 0.5 * (t[1] - t[0])];
    e.extend(t.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(t[t.len() - 1] + 0.5 * (t[t.len() - 1] - t[t.len() - 2]));
    e
}

/// A sequential colour map (viridis' stops), `x` in `[0, 1]`.
fn viridis(x: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 5] = [
        (68, 1, 84),
        (59, 82, 139),
        (33, 145, 140),
        (94, 201, 98),
        (253, 231, 37),
    ];
    let s = x.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let f = s - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// About [`CONTOURS`] round values inside `(lo, hi)`, and their decimals.
fn contour_levels((lo, hi): (f64, f64)) -> (Vec<f64>, usize) {
    let raw = (hi - lo) / CONTOURS;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|k| k * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut decimals = 0;
    while decimals < 6 && ((step * 10f64.powi(decimals as i32)).fract()).abs() > 1e-6 {
        decimals += 1;
    }
    let scale = 10f64.powi(decimals as i32);
    let first = (lo / step).floor() as i64 + 1;
    let levels = (first..)
        .map(|k| (k as f64 * step * scale).round() / scale)
        .take_while(|v| *v < hi)
        .collect();
    (levels, decimals)
}

/// Where column `n` of output `o` at pressure `p` first crosses `level`, by linear
/// interpolation between neighbouring buildable walls.
fn crossing(m: &DesignMap, o: usize, p: usize, n: usize, level: f64) -> Option<f64> {
    (0..m.t_mm.len().saturating_sub(1)).find_map(|t| {
        let (a, b) = (m.value(o, p, n, t), m.value(o, p, n, t + 1));
        let crosses = a.is_finite() && b.is_finite() && a != b && (a - level) * (b - level) <= 0.0;
        crosses.then(|| m.t_mm[t] + (level - a) / (b - a) * (m.t_mm[t + 1] - m.t_mm[t]))
    })
}

/// One pressure's heat map.
fn panel(m: &DesignMap, o: usize, p: usize, area: &Area<'_>, range: (f64, f64)) -> Result<()> {
    let edges = cell_edges(&m.t_mm);
    let (n0, n1) = (
        m.n_values[0] as f64,
        m.n_values[m.n_values.len() - 1] as f64,
    );
    let mut ch = ChartBuilder::on(area)
        .caption(format!("P = {} bar", m.pressures[p]), ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(n0 - 0.5..n1 + 0.5, edges[0]..edges[edges.len() - 1])?;
    let integer = |x: &f64| {
        if (x - x.round()).abs() < 1e-6 {
            format!("{x:.0}")
        } else {
            String::new()
        }
    };
    ch.configure_mesh()
        .disable_mesh()
        .x_labels((n1 - n0) as usize + 1)
        .x_label_formatter(&integer)
        .x_desc("N (bellows)")
        .y_desc("T (mm)")
        .draw()?;
    let (lo, hi) = range;
    for (n_i, &n) in m.n_values.iter().enumerate() {
        let x = n as f64;
        ch.draw_series((0..m.t_mm.len()).map(|t| {
            let v = m.value(o, p, n_i, t);
            let fill = if v.is_finite() {
                viridis((v - lo) / (hi - lo))
            } else {
                UNBUILDABLE
            };
            Rectangle::new(
                [(x - 0.5, edges[t]), (x + 0.5, edges[t + 1])],
                fill.filled(),
            )
        }))?;
    }
    let (levels, decimals) = contour_levels(finite_range(values(m, o, p)));
    for level in levels {
        let ink = if (level - lo) / (hi - lo) < 0.6 {
            WHITE
        } else {
            BLACK
        };
        contour(&mut ch, m, (o, p), (level, decimals), ink)?;
    }
    let top = edges[edges.len() - 1] - 0.015 * (edges[edges.len() - 1] - edges[0]);
    ch.draw_series(
        m.trained_n
            .iter()
            .map(|&n| TriangleMarker::new((n as f64, top), 6, BLACK.filled())),
    )?;
    Ok(())
}

/// The contour of `level`: a step across each column where the column crosses it, joined at
/// the border of neighbouring N (N is discrete), labelled once per joined run.
fn contour(
    ch: &mut Chart<'_, '_>,
    m: &DesignMap,
    (o, p): (usize, usize),
    (level, decimals): (f64, usize),
    ink: RGBColor,
) -> Result<()> {
    let points: Vec<(f64, f64)> = (0..m.n_values.len())
        .filter_map(|n| crossing(m, o, p, n, level).map(|t| (m.n_values[n] as f64, t)))
        .collect();
    let mut runs: Vec<&[(f64, f64)]> = Vec::new();
    let mut start = 0;
    for k in 1..=points.len() {
        if k == points.len() || points[k].0 != points[k - 1].0 + 1.0 {
            runs.push(&points[start..k]);
            start = k;
        }
    }
    for run in runs.into_iter().filter(|r| !r.is_empty()) {
        let mut line: Vec<(f64, f64)> = Vec::with_capacity(2 * run.len());
        for &(n, t) in run {
            line.extend([(n - 0.5, t), (n + 0.5, t)]);
        }
        ch.draw_series(LineSeries::new(line, ink.stroke_width(2)))?;
        let (n, t) = run[run.len() / 2];
        ch.draw_series(std::iter::once(
            EmptyElement::at((n - 0.45, t))
                + Text::new(
                    format!("{level:.decimals$}"),
                    (0, -15),
                    ("sans-serif", 13).into_font().color(&ink),
                ),
        ))?;
    }
    Ok(())
}

/// The colour scale shared by the panels.
fn colour_bar(area: &Area<'_>, (lo, hi): (f64, f64), unit: &str) -> Result<()> {
    let mut ch = ChartBuilder::on(area)
        .caption(unit, ("sans-serif", 14))
        .margin_top(30)
        .margin_bottom(48)
        .margin_right(10)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, lo..hi)?;
    ch.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(8)
        .label_style(("sans-serif", 13))
        .draw()?;
    const STEPS: usize = 100;
    ch.draw_series((0..STEPS).map(|k| {
        let (a, b) = (k as f64 / STEPS as f64, (k + 1) as f64 / STEPS as f64);
        let y = |f: f64| lo + f * (hi - lo);
        Rectangle::new([(0.0, y(a)), (1.0, y(b))], viridis(0.5 * (a + b)).filled())
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contour_levels_are_round_and_inside() {
        for (range, step) in [
            ((0.0, 60.0), 10.0),
            ((0.31, 1.87), 0.5),
            ((12.0, 13.0), 0.2),
        ] {
            let (levels, decimals) = contour_levels(range);
            assert!(
                levels.len() >= 3 && levels.len() <= 8,
                "{range:?}: {levels:?}"
            );
            assert!(levels.iter().all(|l| *l > range.0 && *l < range.1));
            assert!(
                (levels[1] - levels[0] - step).abs() < 1e-9,
                "{range:?}: {levels:?}"
            );
            let shown = format!("{:.decimals$}", levels[0]);
            assert_eq!(shown.parse::<f64>().unwrap(), levels[0], "{shown}");
        }
    }

    #[test]
    fn cells_cover_the_grid_and_colours_run_dark_to_light() {
        assert_eq!(cell_edges(&[1.0, 2.0, 3.0]), vec![0.5, 1.5, 2.5, 3.5]);
        let (a, b) = (viridis(0.0), viridis(1.0));
        assert!((a.0 as u32 + a.1 as u32 + a.2 as u32) < (b.0 as u32 + b.1 as u32 + b.2 as u32));
    }
}
