//! Units and signs of recordings: the columns a recording may carry in other units, and the
//! scale and sign checks every recording passes on reading.
//!
//! A recording is read in its format's units (mm, deg, N, bar; [`crate::schema`]), or from
//! a column that carries another unit ([`crate::schema::RECORDING_UNIT_COLUMNS`]:
//! `pressure_kpa`, `force_mn`, `tip_uz_cm`, `angle_rad`, …), converted on reading. The values
//! are then checked against what an actuator of this family gives. `L_f` = 92 mm is the free
//! length; rows at `P = 0` carry no response and are checked for their pressure only.
//!
//! | check | rule | a failing value most likely is |
//! |---|---|---|
//! | pressure | `0 ≤ P ≤ 10 bar` | kPa above 60, psi below; a negative one: the sign |
//! | wall thickness | `T ≥ 0.5 mm` | cm |
//! | tip Uy, angle | `Uy ≤ max(1 mm, 3 σ_tip)`, `α ≥ −max(1°, 3 σ_α)` (the actuator bends down: `Uy = Δy < 0`) | the other sign |
//! | tip Uz | the tip no farther from the support than `1.05 L_f + 3 σ_tip` | the other sign of Uz (`Uz = −Δz`) |
//! | tip and angle | the support-to-tip distance they imply, `L = Uz − Uy / tan α`, reaches 60–130 mm (92 ± 4 mm in the shipped experiments) for some angle within `α ± 3 σ_α` | tips in cm (`L` ten times too small), the angle in radians |
//! | blocked force | `F ≥ −max(0.05 N, 3 σ_F)`, `F ≤ 20 N`, `σ_F ≤ 2 N` | the other sign; mN |
//! | response per bar | median over the rows of `α / P` ≤ 100 °/bar, of `F / P` ≤ 2.5 N/bar | the pressure in MPa, when every pressure is ≤ 0.5 |
//! | markers | `Uy ≤ max(1 mm, 3 σ)`, marker `k` no farther from the support than `1.05 k L_f / 9 + max(1 mm, 3 σ)` | the other sign |
//!
//! `σ_α`, `σ_F` and the markers' `σ` are the rows' recorded standard deviations, and
//! `σ_tip = r σ_α` (radians) with `r` the chord from the support to the tip, as in the
//! calibration's noise model ([`super::objective`]): a sign or a distance is questioned only
//! beyond the row's own scatter, so that noisy recordings near zero pass.
//!
//! The bounds per bar lie above anything the shipped surrogate gives over its whole training
//! domain (at most 96 °/bar and 1.7 N/bar, at 0.25 bar and the softest materials) and below
//! what the shipped experiments give with their pressures read as MPa (at least 109 °/bar and
//! 3.0 N/bar). A row too small to tell (`α < 2°` and `|Uy| < 2 mm`) is not checked for the
//! tip-and-angle distance.
//!
//! A file with a failing value is an error ([`super::experiments::ExperimentError::Implausible`])
//! that lists, for each column, every failing row at once, the unit it most likely has and the
//! column name that would carry that unit.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::schema;

/// The free length of the actuators of the shipped experiments: the distance from the support
/// to the undeformed tip (mm).
pub const FREE_LENGTH_MM: f64 = 92.0;

/// Largest gauge pressure a recording may hold (bar).
pub const PRESSURE_MAX_BAR: f64 = 10.0;
/// Smallest wall thickness (mm).
pub const WALL_THICKNESS_MIN_MM: f64 = 0.5;
/// Tolerance of the sign checks on tip Uy and marker Uy (mm).
pub const UY_SIGN_TOL_MM: f64 = 1.0;
/// Tolerance of the sign check on the angle (deg).
pub const ANGLE_SIGN_TOL_DEG: f64 = 1.0;
/// The tip lies no farther from the support than this multiple of the free length.
pub const CHORD_MAX: f64 = 1.05;
/// Range of the support-to-tip distance implied by tip and angle (mm).
pub const IMPLIED_LENGTH_MM: [f64; 2] = [60.0, 130.0];
/// Largest blocked force (N).
pub const FORCE_MAX_N: f64 = 20.0;
/// Largest standard deviation of a blocked force (N).
pub const FORCE_STD_MAX_N: f64 = 2.0;
/// Most negative blocked force accepted as noise about zero (N).
pub const FORCE_SIGN_TOL_N: f64 = 0.05;
/// Largest median angle per bar over a file's rows (deg/bar).
pub const ANGLE_PER_BAR_MAX: f64 = 100.0;
/// Largest median blocked force per bar over a file's rows (N/bar).
pub const FORCE_PER_BAR_MAX: f64 = 2.5;
/// A file whose pressures all lie at or below this (bar) and respond too much per bar is
/// taken to be in MPa.
pub const MPA_PRESSURE_MAX: f64 = 0.5;

/// A column whose values look like another unit, or the other sign.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Suspicion {
    /// The column(s), as written in the file.
    pub columns: Vec<String>,
    /// The unit they most likely have (`kPa`), or `the other sign`.
    pub likely: String,
    /// The rule they fail, with its numbers.
    pub why: String,
    /// Every failing row: its line (header = 1) and its values as read.
    pub rows: Vec<(usize, String)>,
    /// What to do.
    pub fix: String,
}

impl fmt::Display for Suspicion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rows: Vec<String> = self
            .rows
            .iter()
            .map(|(l, v)| format!("line {l} ({v})"))
            .collect();
        let several = self.columns.len() > 1;
        let verb = match (self.likely == SIGN, several) {
            (true, false) => "has",
            (true, true) => "have",
            (false, false) => "looks like",
            (false, true) => "look like",
        };
        write!(
            f,
            "column{} {} {verb} {} ({}) in {} row{}: {}; {}",
            if several { "s" } else { "" },
            self.columns.join(" and "),
            self.likely,
            self.why,
            self.rows.len(),
            if self.rows.len() == 1 { "" } else { "s" },
            rows.join(", "),
            self.fix
        )
    }
}

/// The file's name of each column of its format: the column itself, or the column in another
/// unit it was read from.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// `(format's column, column as written)` where the two differ.
    pub renamed: Vec<(String, String)>,
}

impl Written {
    /// The name in the file of the format's column `canonical`.
    pub fn name(&self, canonical: &str) -> String {
        self.renamed
            .iter()
            .find(|(c, _)| c == canonical)
            .map_or(canonical.to_string(), |(_, w)| {
                format!("{w} (read as {canonical})")
            })
    }

    /// The column that would carry `unit` for the format's column `canonical`
    /// (`pressure_bar`, `kPa` → `pressure_kpa`), if the readers accept one.
    fn alternative(canonical: &str, unit: &str) -> Option<&'static str> {
        schema::RECORDING_UNIT_COLUMNS
            .iter()
            .find(|u| u.canonical.name == canonical && u.column.unit == unit)
            .map(|u| u.column.name)
    }
}

/// Collects failing rows per (columns, likely) and words them at the end.
struct Findings<'a> {
    written: &'a Written,
    out: Vec<Suspicion>,
}

impl<'a> Findings<'a> {
    fn new(written: &'a Written) -> Self {
        Findings {
            written,
            out: Vec::new(),
        }
    }

    /// Adds a failing row to the suspicion on `canonical` columns with `likely`.
    fn add(&mut self, canonical: &[&str], likely: &str, why: &str, line: usize, value: String) {
        let columns: Vec<String> = canonical.iter().map(|c| self.written.name(c)).collect();
        let i = match self
            .out
            .iter()
            .position(|s| s.columns == columns && s.likely == likely)
        {
            Some(i) => i,
            None => {
                self.out.push(Suspicion {
                    columns,
                    likely: likely.to_string(),
                    why: why.to_string(),
                    rows: Vec::new(),
                    fix: fix(canonical, likely),
                });
                self.out.len() - 1
            }
        };
        self.out[i].rows.push((line, value));
    }
}

/// What to do about a suspicion.
fn fix(canonical: &[&str], likely: &str) -> String {
    if likely == SIGN {
        return format!(
            "change the sign of {} (the conventions: docs/MODEL.md, src/schema.rs)",
            canonical.join(" and ")
        );
    }
    let unit = likely.split_whitespace().next().unwrap_or(likely);
    let alternatives: Vec<&str> = canonical
        .iter()
        .filter_map(|c| Written::alternative(c, unit))
        .collect();
    if alternatives.is_empty() {
        format!(
            "convert {} to the format's units (src/schema.rs)",
            canonical.join(" and ")
        )
    } else {
        format!(
            "convert to the format's units, or name the column{} {} so that it is converted \
             on reading",
            if alternatives.len() == 1 { "" } else { "s" },
            alternatives.join(" and ")
        )
    }
}

// public for the tests in tests/calibrate/
#[doc(hidden)]
pub const SIGN: &str = "the other sign";

fn pressure_check(f: &mut Findings<'_>, r: &Row) {
    let (line, p, t) = (r.line, r.pressure_bar, r.wall_thickness_mm);
    let p_name = schema::PRESSURE.name;
    if p < 0.0 {
        f.add(
            &[p_name],
            SIGN,
            "a gauge pressure is ≥ 0",
            line,
            p.to_string(),
        );
    } else if p > PRESSURE_MAX_BAR {
        let (unit, why) = if p > 60.0 {
            (
                "kPa",
                "above the 10 bar an actuator of this kind holds; 100 kPa = 1 bar",
            )
        } else {
            (
                "psi",
                "above the 10 bar an actuator of this kind holds; 14.5 psi = 1 bar",
            )
        };
        f.add(&[p_name], unit, why, line, p.to_string());
    }
    if t < WALL_THICKNESS_MIN_MM {
        f.add(
            &[schema::WALL_THICKNESS.name],
            "cm",
            "thinner than the 0.5 mm a printed wall has; 1 cm = 10 mm",
            line,
            t.to_string(),
        );
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The response-per-bar check: `(line, pressure, response)` of the rows with `P > 0`.
fn per_bar(f: &mut Findings<'_>, rows: &[(usize, f64, f64)], response: &str, unit: &str, max: f64) {
    let ratios: Vec<f64> = rows.iter().map(|&(_, p, y)| y / p).collect();
    let m = median(ratios);
    if m.is_nan() || m <= max {
        return;
    }
    let p_all_small = rows.iter().all(|&(_, p, _)| p <= MPA_PRESSURE_MAX);
    if p_all_small {
        let why = format!(
            "{response} grows {m:.0} {unit}/bar in the median over the rows, more than the at \
             most {max} {unit}/bar of any actuator of this family, and every pressure is ≤ \
             {MPA_PRESSURE_MAX}; 0.1 MPa = 1 bar"
        );
        for &(line, p, _) in rows {
            f.add(&[schema::PRESSURE.name], "MPa", &why, line, p.to_string());
        }
    } else {
        let why = format!(
            "{response} grows {m:.0} {unit}/bar in the median over the rows, more than the at \
             most {max} {unit}/bar of any actuator of this family"
        );
        for &(line, p, y) in rows {
            if y / p > max {
                f.add(
                    &[schema::PRESSURE.name, response],
                    "another unit of pressure or response",
                    &why,
                    line,
                    format!("{p} bar, {y}"),
                );
            }
        }
    }
}

/// The support-to-tip distance implied by a tip (mm) and an angle (deg).
fn implied_length(uz: f64, uy: f64, angle_deg: f64) -> f64 {
    uz - uy / angle_deg.to_radians().tan()
}

/// Whether `l` is a support-to-tip distance of this family.
fn plausible_length(l: f64) -> bool {
    (IMPLIED_LENGTH_MM[0]..=IMPLIED_LENGTH_MM[1]).contains(&l)
}

/// One row of a recording, in the format's units, for the checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// Its line in the file (header = 1).
    pub line: usize,
    /// Pressure (bar).
    pub pressure_bar: f64,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// What it records.
    pub recorded: Recorded,
}

/// What a row records, in the format's units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Recorded {
    /// Tip Uz, Uy (mm) and the bending angle (deg).
    Bending {
        /// Tip Uz.
        tip_uz_mm: f64,
        /// Tip Uy.
        tip_uy_mm: f64,
        /// Angle.
        angle_deg: f64,
        /// Its standard deviation.
        angle_std_deg: f64,
    },
    /// Blocked force and its standard deviation (N).
    Force {
        /// Force.
        force_n: f64,
        /// Its standard deviation.
        force_std_n: f64,
    },
    /// Marker `k` (1..9): Uz, Uy (mm).
    Marker {
        /// Marker number.
        marker: usize,
        /// Uz.
        uz_mm: f64,
        /// Uy.
        uy_mm: f64,
        /// Standard deviation of each component.
        std_mm: f64,
    },
}

/// The scale and sign checks of a recording's rows (the module docs' table): each suspicious
/// column with every failing row; empty when all pass.
pub fn check(rows: &[Row], written: &Written) -> Vec<Suspicion> {
    let mut f = Findings::new(written);
    for r in rows {
        pressure_check(&mut f, r);
    }
    let mut angle_per_bar = Vec::new();
    let mut force_per_bar = Vec::new();
    for r in rows {
        match r.recorded {
            Recorded::Bending {
                tip_uz_mm,
                tip_uy_mm,
                angle_deg,
                angle_std_deg,
            } => {
                let tip = [tip_uz_mm, tip_uy_mm];
                if bending(&mut f, r, tip, angle_deg, angle_std_deg) {
                    angle_per_bar.push((r.line, r.pressure_bar, angle_deg));
                }
            }
            Recorded::Force {
                force_n,
                force_std_n,
            } => {
                if force(&mut f, r, force_n, force_std_n) {
                    force_per_bar.push((r.line, r.pressure_bar, force_n));
                }
            }
            Recorded::Marker {
                marker,
                uz_mm,
                uy_mm,
                std_mm,
            } => self::marker(&mut f, r, marker, [uz_mm, uy_mm], std_mm),
        }
    }
    per_bar(
        &mut f,
        &angle_per_bar,
        schema::ANGLE.name,
        "deg",
        ANGLE_PER_BAR_MAX,
    );
    per_bar(
        &mut f,
        &force_per_bar,
        schema::FORCE.name,
        "N",
        FORCE_PER_BAR_MAX,
    );
    f.out
}

/// A bending row's sign and tip-and-angle checks; whether its angle counts in the per-bar
/// check (under pressure, signs and degrees as expected).
fn bending(f: &mut Findings<'_>, r: &Row, [uz, uy]: [f64; 2], a: f64, sa: f64) -> bool {
    if r.pressure_bar <= 0.0 {
        return false;
    }
    let chord = (FREE_LENGTH_MM - uz).hypot(uy);
    let s_tip = 3.0 * chord * sa.to_radians();
    let (uz_n, uy_n, a_n) = (schema::TIP_UZ.name, schema::TIP_UY.name, schema::ANGLE.name);
    let line = r.line;
    let mut signs_ok = true;
    if uy > UY_SIGN_TOL_MM.max(s_tip) {
        signs_ok = false;
        let why = "the actuator bends down: Uy = Δy < 0 under pressure, beyond its scatter";
        f.add(&[uy_n], SIGN, why, line, uy.to_string());
    }
    if a < -ANGLE_SIGN_TOL_DEG.max(3.0 * sa) {
        signs_ok = false;
        let why = "the bending angle is > 0 under pressure, beyond its scatter";
        f.add(&[a_n], SIGN, why, line, a.to_string());
    }
    if uz < 0.0 && chord > CHORD_MAX * FREE_LENGTH_MM + s_tip {
        signs_ok = false;
        let why = format!(
            "the tip would lie farther from the support than the free length \
             ({FREE_LENGTH_MM} mm); Uz = −Δz is > 0 when the tip moves back"
        );
        f.add(&[uz_n], SIGN, &why, line, uz.to_string());
    }
    if !signs_ok || (a < 2.0 && uy.abs() < 2.0) {
        return false;
    }
    // the distance over the angle's scatter (`L` falls as `α` grows, below 90°)
    let (lo, hi) = (
        implied_length(uz, uy, (a + 3.0 * sa).min(89.9)),
        implied_length(uz, uy, (a - 3.0 * sa).max(0.1)),
    );
    if a > 90.0 || (lo <= IMPLIED_LENGTH_MM[1] && hi >= IMPLIED_LENGTH_MM[0]) {
        return true;
    }
    tip_and_angle(f, line, uz, uy, a)
}

/// Which units make a row's tip and angle imply a support-to-tip distance of this family;
/// whether its angle is in degrees.
fn tip_and_angle(f: &mut Findings<'_>, line: usize, uz: f64, uy: f64, a: f64) -> bool {
    let (uz_n, uy_n, a_n) = (schema::TIP_UZ.name, schema::TIP_UY.name, schema::ANGLE.name);
    let value = format!("Uz {uz}, Uy {uy}, angle {a}");
    let l = implied_length(uz, uy, a);
    let why_cm = format!(
        "with the angle they imply a support-to-tip distance of {l:.1} mm, not \
         {}–{} mm; 1 cm = 10 mm",
        IMPLIED_LENGTH_MM[0], IMPLIED_LENGTH_MM[1]
    );
    if plausible_length(implied_length(10.0 * uz, 10.0 * uy, a)) {
        f.add(&[uz_n, uy_n], "cm", &why_cm, line, value);
        true
    } else if plausible_length(implied_length(uz, uy, a.to_degrees())) {
        let why = format!(
            "read in degrees, it makes the tip imply a support-to-tip distance of {l:.0} mm, \
             not {}–{} mm; in radians it fits",
            IMPLIED_LENGTH_MM[0], IMPLIED_LENGTH_MM[1]
        );
        f.add(&[a_n], "rad", &why, line, value);
        false
    } else if plausible_length(implied_length(10.0 * uz, 10.0 * uy, a.to_degrees())) {
        f.add(&[uz_n, uy_n], "cm", &why_cm, line, value.clone());
        let why = "with the tip in cm, it fits in radians";
        f.add(&[a_n], "rad", why, line, value);
        false
    } else {
        // no unit explains it; the data checks compare it with the other rows
        true
    }
}

/// A blocked-force row's scale and sign checks; whether it counts in the per-bar check.
fn force(f: &mut Findings<'_>, r: &Row, force_n: f64, force_std_n: f64) -> bool {
    let sign_tol = FORCE_SIGN_TOL_N.max(3.0 * force_std_n);
    let (f_n, s_n) = (schema::FORCE.name, schema::FORCE_STD.name);
    let line = r.line;
    if force_std_n > FORCE_STD_MAX_N {
        let why = "larger than the 2 N a blocked force scatters; 1000 mN = 1 N";
        f.add(&[s_n], "mN", why, line, force_std_n.to_string());
    }
    if force_n > FORCE_MAX_N {
        let why = "larger than the 20 N an actuator of this kind pushes; 1000 mN = 1 N";
        f.add(&[f_n], "mN", why, line, force_n.to_string());
        false
    } else if force_n < -sign_tol {
        let why = "the blocked force pushes on the plate: > 0, beyond its scatter";
        f.add(&[f_n], SIGN, why, line, force_n.to_string());
        false
    } else {
        r.pressure_bar > 0.0
    }
}

/// A marker row's sign checks.
fn marker(f: &mut Findings<'_>, r: &Row, k: usize, [uz, uy]: [f64; 2], std: f64) {
    if r.pressure_bar <= 0.0 {
        return;
    }
    let tol = UY_SIGN_TOL_MM.max(3.0 * std);
    if uy > tol {
        let why = "the actuator bends down: Uy = Δy < 0 under pressure, beyond its scatter";
        let name = schema::MARKER_RECORDED_UY.name;
        f.add(&[name], SIGN, why, r.line, uy.to_string());
    }
    let z = FREE_LENGTH_MM * k as f64 / 9.0;
    if uz < 0.0 && (z - uz).hypot(uy) > CHORD_MAX * z + tol {
        let why = "the marker would lie farther from the support than its place on the \
                   actuator; Uz = −Δz is > 0 when it moves back";
        let name = schema::MARKER_RECORDED_UZ.name;
        f.add(&[name], SIGN, why, r.line, uz.to_string());
    }
}
