//! What every SVG figure of the tool shares: axis ranges that hold their data, and a palette
//! of strong, distinguishable colours.
use plotters::style::RGBColor;

/// Ten qualitative colours, saturated enough for thin lines and small points on white.
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

/// The colour number `k` of [`PALETTE`] (cycling).
pub fn colour(k: usize) -> RGBColor {
    PALETTE[k % PALETTE.len()]
}

/// An axis range that holds every finite value of `data` with 5 % of the span as margin on
/// each side (a single value or an empty set gets a unit-wide range around it or around 0).
pub fn axis_range(data: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = data
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (-0.5, 0.5);
    }
    let span = hi - lo;
    let pad = if span > 1e-12 * (1.0 + lo.abs().max(hi.abs())) {
        0.05 * span
    } else {
        0.5 * (1.0 + lo.abs()) * 1e-3 + 0.5
    };
    (lo - pad, hi + pad)
}

/// [`axis_range`] of the data together with the extra values that must be shown (zero, a
/// reference line).
pub fn axis_range_with(data: impl IntoIterator<Item = f64>, also: &[f64]) -> (f64, f64) {
    axis_range(data.into_iter().chain(also.iter().copied()))
}

/// A range symmetric about zero that holds every finite value of `data` (errors, residuals).
pub fn symmetric_range(data: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let m = data
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let m = if m > 0.0 { 1.1 * m } else { 1.0 };
    (-m, m)
}

/// Whether every finite value of `data` lies in `range`.
#[cfg(test)]
pub fn holds(range: (f64, f64), data: impl IntoIterator<Item = f64>) -> bool {
    data.into_iter()
        .filter(|v| v.is_finite())
        .all(|v| v >= range.0 && v <= range.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_hold_their_data_with_a_margin() {
        let cases: [&[f64]; 6] = [
            &[1.0, 2.0, 3.0],
            &[-80.0, 95.0, 12.0],
            &[4.2],
            &[],
            &[f64::NAN, -1.0, f64::INFINITY, 7.0],
            &[1e-9, 2e-9],
        ];
        for d in cases {
            let r = axis_range(d.iter().copied());
            assert!(r.0 < r.1 && holds(r, d.iter().copied()), "{d:?} -> {r:?}");
            let finite: Vec<f64> = d.iter().copied().filter(|v| v.is_finite()).collect();
            if finite.len() > 1 {
                let (lo, hi) = (
                    finite.iter().copied().fold(f64::INFINITY, f64::min),
                    finite.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                );
                // the data do not touch the border
                assert!(r.0 < lo && r.1 > hi, "{d:?} -> {r:?}");
            }
            let s = symmetric_range(d.iter().copied());
            assert!(holds(s, d.iter().copied()) && s.0 == -s.1);
        }
        let r = axis_range_with([2.0, 3.0], &[0.0]);
        assert!(holds(r, [0.0, 2.0, 3.0]));
    }
}
