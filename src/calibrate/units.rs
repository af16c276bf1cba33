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
//! | tip Uy, angle | `Uy ≤ 1 mm`, `α ≥ −1°` (the actuator bends down: `Uy = Δy < 0`) | the other sign |
//! | tip Uz | the tip no farther from the support than `1.05 L_f` | the other sign of Uz (`Uz = −Δz`) |
//! | tip and angle | the support-to-tip distance they imply, `L = Uz − Uy / tan α`, in 60–130 mm (92 ± 4 mm in the shipped experiments) | tips in cm (`L` ten times too small), the angle in radians |
//! | blocked force | `−0.05 ≤ F ≤ 20 N`, its standard deviation ≤ 2 N | the other sign; mN |
//! | response per bar | median over the rows of `α / P` ≤ 100 °/bar, of `F / P` ≤ 2.5 N/bar | the pressure in MPa, when every pressure is ≤ 0.5 |
//! | markers | `Uy ≤ 1 mm`, marker `k` no farther from the support than `1.05 k L_f / 9 + 1 mm` | the other sign |
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

use super::experiments::{record_error, BendingRecord, ExperimentError, ForceRecord, MarkerRecord};
use super::objective::FREE_LENGTH_MM;
use crate::schema;

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

/// Each column of the file as the format's column it stands for, with its factor.
pub(super) fn map_header(
    name: &str,
    headers: &csv::StringRecord,
    columns: &[&str],
) -> Result<(Vec<(String, f64)>, Written), ExperimentError> {
    if headers.len() == 1 {
        let h = &headers[0];
        for (sep, word) in [(';', ";"), ('\t', "tab")] {
            if h.contains(sep) {
                return Err(ExperimentError::Separator {
                    source_name: name.to_string(),
                    header: h.to_string(),
                    separator: word.to_string(),
                });
            }
        }
    }
    let mut mapped = Vec::new();
    let mut written = Written::default();
    let mut unknown = Vec::new();
    for h in headers.iter() {
        if columns.contains(&h) {
            mapped.push((h.to_string(), 1.0));
        } else if let Some(u) = schema::RECORDING_UNIT_COLUMNS
            .iter()
            .find(|u| u.column.name == h && columns.contains(&u.canonical.name))
        {
            mapped.push((u.canonical.name.to_string(), u.to_canonical));
            written
                .renamed
                .push((u.canonical.name.to_string(), h.to_string()));
        } else {
            unknown.push(h);
            mapped.push((String::new(), f64::NAN));
        }
    }
    for c in columns {
        if !mapped.iter().any(|(m, _)| m == c) {
            let hint = if unknown.is_empty() {
                String::new()
            } else {
                format!(
                    " (the header has {}, which this format does not have: renamed?)",
                    unknown.join(", ")
                )
            };
            return Err(record_error(name, 1, c, &format!("missing column{hint}")));
        }
    }
    if let Some(h) = unknown.first() {
        let alternatives: Vec<&str> = schema::RECORDING_UNIT_COLUMNS
            .iter()
            .filter(|u| columns.contains(&u.canonical.name))
            .map(|u| u.column.name)
            .collect();
        return Err(record_error(
            name,
            1,
            h,
            &format!(
                "unexpected column (a unit or quantity this file format does not have); \
                 expected exactly {}, each either as named or in another unit ({})",
                columns.join(", "),
                alternatives.join(", ")
            ),
        ));
    }
    for (i, (m, _)) in mapped.iter().enumerate() {
        if let Some(j) = mapped[..i].iter().position(|(o, _)| o == m) {
            let both = if headers[i] == headers[j] {
                "column given twice".to_string()
            } else {
                format!(
                    "column given twice, as {} and as {}",
                    &headers[j], &headers[i]
                )
            };
            return Err(record_error(name, 1, m, &both));
        }
    }
    Ok((mapped, written))
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

const SIGN: &str = "the other sign";

fn pressure_checks(f: &mut Findings<'_>, rows: &[(usize, f64, f64)]) {
    let p_name = schema::PRESSURE.name;
    for &(line, p, t) in rows {
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

/// The scale and sign checks of bending rows (line of row `i` = `i + 2`).
pub fn check_bending(rows: &[BendingRecord], written: &Written) -> Vec<Suspicion> {
    let mut f = Findings::new(written);
    let (uz_n, uy_n, a_n) = (schema::TIP_UZ.name, schema::TIP_UY.name, schema::ANGLE.name);
    let lines = || rows.iter().enumerate().map(|(i, r)| (i + 2, r));
    let pt: Vec<_> = lines()
        .map(|(l, r)| (l, r.pressure_bar, r.wall_thickness_mm))
        .collect();
    pressure_checks(&mut f, &pt);
    let mut angle_ok = Vec::new();
    for (line, r) in lines().filter(|(_, r)| r.pressure_bar > 0.0) {
        let (uz, uy, a) = (r.tip_uz_mm, r.tip_uy_mm, r.angle_deg);
        let mut signs_ok = true;
        if uy > UY_SIGN_TOL_MM {
            signs_ok = false;
            let why = "the actuator bends down: Uy = Δy < 0 under pressure";
            f.add(&[uy_n], SIGN, why, line, uy.to_string());
        }
        if a < -ANGLE_SIGN_TOL_DEG {
            signs_ok = false;
            let why = "the bending angle is > 0 under pressure";
            f.add(&[a_n], SIGN, why, line, a.to_string());
        }
        let chord = (FREE_LENGTH_MM - uz).hypot(uy);
        if uz < 0.0 && chord > CHORD_MAX * FREE_LENGTH_MM {
            signs_ok = false;
            let why = format!(
                "the tip would lie farther from the support than the free length \
                 ({FREE_LENGTH_MM} mm); Uz = −Δz is > 0 when the tip moves back"
            );
            f.add(&[uz_n], SIGN, &why, line, uz.to_string());
        }
        if !signs_ok || (a < 2.0 && uy.abs() < 2.0) {
            continue;
        }
        if !plausible_length(implied_length(uz, uy, a)) {
            tip_and_angle(&mut f, line, uz, uy, a);
        }
        if !f
            .out
            .iter()
            .any(|s| s.likely == "rad" && s.rows.iter().any(|(l, _)| *l == line))
        {
            angle_ok.push((line, r.pressure_bar, a));
        }
    }
    per_bar(&mut f, &angle_ok, a_n, "deg", ANGLE_PER_BAR_MAX);
    f.out
}

/// Which units make a row's tip and angle imply a support-to-tip distance of this family.
fn tip_and_angle(f: &mut Findings<'_>, line: usize, uz: f64, uy: f64, a: f64) {
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
    } else if plausible_length(implied_length(uz, uy, a.to_degrees())) {
        let why = format!(
            "read in degrees, it makes the tip imply a support-to-tip distance of {l:.0} mm, \
             not {}–{} mm; in radians it fits",
            IMPLIED_LENGTH_MM[0], IMPLIED_LENGTH_MM[1]
        );
        f.add(&[a_n], "rad", &why, line, value);
    } else if plausible_length(implied_length(10.0 * uz, 10.0 * uy, a.to_degrees())) {
        f.add(&[uz_n, uy_n], "cm", &why_cm, line, value.clone());
        let why = "with the tip in cm, it fits in radians";
        f.add(&[a_n], "rad", why, line, value);
    }
}

/// The scale and sign checks of blocked-force rows.
pub fn check_force(rows: &[ForceRecord], written: &Written) -> Vec<Suspicion> {
    let mut f = Findings::new(written);
    let (f_n, s_n) = (schema::FORCE.name, schema::FORCE_STD.name);
    let pt: Vec<_> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| (i + 2, r.pressure_bar, r.wall_thickness_mm))
        .collect();
    pressure_checks(&mut f, &pt);
    let mut force_ok = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        let line = i + 2;
        let mn = "larger than the 20 N an actuator of this kind pushes; 1000 mN = 1 N";
        if r.force_n > FORCE_MAX_N {
            f.add(&[f_n], "mN", mn, line, r.force_n.to_string());
        } else if r.force_n < -FORCE_SIGN_TOL_N {
            let why = "the blocked force pushes on the plate: > 0";
            f.add(&[f_n], SIGN, why, line, r.force_n.to_string());
        } else if r.pressure_bar > 0.0 {
            force_ok.push((line, r.pressure_bar, r.force_n));
        }
        if r.force_std_n > FORCE_STD_MAX_N {
            let why = "larger than the 2 N a blocked force scatters; 1000 mN = 1 N";
            f.add(&[s_n], "mN", why, line, r.force_std_n.to_string());
        }
    }
    per_bar(&mut f, &force_ok, f_n, "N", FORCE_PER_BAR_MAX);
    f.out
}

/// The scale and sign checks of marker rows.
pub fn check_markers(rows: &[MarkerRecord], written: &Written) -> Vec<Suspicion> {
    let mut f = Findings::new(written);
    let pt: Vec<_> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| (i + 2, r.pressure_bar, r.wall_thickness_mm))
        .collect();
    pressure_checks(&mut f, &pt);
    for (i, r) in rows.iter().enumerate() {
        if r.pressure_bar <= 0.0 {
            continue;
        }
        let line = i + 2;
        if r.uy_mm > UY_SIGN_TOL_MM {
            let why = "the actuator bends down: Uy = Δy < 0 under pressure";
            let name = schema::MARKER_RECORDED_UY.name;
            f.add(&[name], SIGN, why, line, r.uy_mm.to_string());
        }
        let z = FREE_LENGTH_MM * r.marker as f64 / 9.0;
        if r.uz_mm < 0.0 && (z - r.uz_mm).hypot(r.uy_mm) > CHORD_MAX * z + 1.0 {
            let why = "the marker would lie farther from the support than its place on the \
                       actuator; Uz = −Δz is > 0 when it moves back";
            let name = schema::MARKER_RECORDED_UZ.name;
            f.add(&[name], SIGN, why, line, r.uz_mm.to_string());
        }
    }
    f.out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::experiments::{shipped_bending, shipped_force};

    #[test]
    fn the_shipped_experiments_pass() {
        let w = Written::default();
        assert_eq!(check_bending(&shipped_bending().unwrap(), &w), vec![]);
        assert_eq!(check_force(&shipped_force().unwrap(), &w), vec![]);
    }

    #[test]
    fn each_unit_is_named_with_every_row() {
        let w = Written::default();
        let b = shipped_bending().unwrap();
        let scaled = |f: &dyn Fn(&mut BendingRecord)| {
            let mut v = b.clone();
            v.iter_mut().for_each(f);
            check_bending(&v, &w)
        };
        for (what, s, likely) in [
            ("kPa", scaled(&|r| r.pressure_bar *= 100.0), "kPa"),
            ("MPa", scaled(&|r| r.pressure_bar /= 10.0), "MPa"),
            (
                "cm",
                scaled(&|r| {
                    r.tip_uz_mm /= 10.0;
                    r.tip_uy_mm /= 10.0
                }),
                "cm",
            ),
            (
                "rad",
                scaled(&|r| r.angle_deg = r.angle_deg.to_radians()),
                "rad",
            ),
            ("sign", scaled(&|r| r.tip_uy_mm = -r.tip_uy_mm), SIGN),
        ] {
            assert_eq!(s.len(), 1, "{what}: {s:?}");
            assert_eq!(s[0].likely, likely, "{what}");
            assert_eq!(s[0].rows.len(), 27, "{what}: every row listed");
        }
        let f = shipped_force().unwrap();
        let mut mn = f.clone();
        mn.iter_mut().for_each(|r| {
            r.force_n *= 1000.0;
            r.force_std_n *= 1000.0
        });
        let s = check_force(&mn, &w);
        assert_eq!(s.len(), 2, "{s:?}");
        assert!(s.iter().all(|x| x.likely == "mN"));
        assert!(s[0].to_string().contains("force_mn"), "{}", s[0]);
        let mut mpa = f;
        mpa.iter_mut().for_each(|r| r.pressure_bar /= 10.0);
        let s = check_force(&mpa, &w);
        assert_eq!(s.len(), 1, "{s:?}");
        assert_eq!(s[0].likely, "MPa");
        assert!(s[0].to_string().contains("pressure_mpa"), "{}", s[0]);
    }
}
