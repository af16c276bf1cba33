//! Data checks: recordings inconsistent with themselves or with the rest.
//!
//! - **Support-to-tip distance.** A bending row's angle and tip displacements imply the
//!   distance from the support point to the undeformed tip,
//!   `L = Uz + (−Uy) / tan α` (the deformed tip lies at `(L − Uz, Uy)` and
//!   `tan α = −Uy / (L − Uz)`). All rows of one `N` come from the same printed length, so a
//!   row whose `L` departs from the median of its `N` by more than
//!   `max(1 mm, 5 × 1.4826 × MAD)` is flagged.
//! - **Chord against angle.** The tip lies at the distance `c = −Uy / sin α` from the support
//!   (the chord). For an actuator of length `L` bent into an arc whose chord makes the angle
//!   `α` with the horizontal, `c = L sin α / α`; real shapes are close to arcs, so the ratio
//!   `c α / (L sin α)` (`L` the median support-to-tip distance of the row's `N`) stays near 1
//!   over a set of recordings (0.97 … 1.05 on the shipped ones but two). A row whose ratio
//!   departs from the median of all rows by more than `max(0.05, 5 × 1.4826 × MAD)` is
//!   flagged: its tip is farther from (or nearer to) the support than any bending shape with
//!   its angle puts it, so its angle and its tip cannot both be right. The flag gives the
//!   floor of any model's tip error there ([`arc_floor_mm`]): how near any shape within the
//!   other rows' band of ratios, at any angle, comes to the recorded tip.
//! - **Monotonic ramps.** For one design, tip Uz, −Uy, the angle and the blocked force grow
//!   with pressure; a decrease between two recorded pressures is flagged.
//!
//! Flags are advice: nothing is excluded unless the user says so (`--exclude`, or
//! `--exclude-flagged`, which excludes them explicitly and lists them in the report).

use serde::{Deserialize, Serialize};

use super::objective::{Config, Exclusion, Recording, Recordings};

/// A flagged recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DataFlag {
    /// The configuration.
    pub config: Config,
    /// The recording it concerns.
    pub recording: Recording,
    /// `file, line N`.
    pub source: String,
    /// What is inconsistent, in words with numbers.
    pub message: String,
}

impl DataFlag {
    /// The explicit exclusion of the flagged row.
    pub fn exclusion(&self) -> Exclusion {
        Exclusion {
            config: self.config,
            recording: self.recording,
            reason: format!("flagged by the data checks: {}", self.message),
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The support-to-tip distance implied by a bending row (mm); `NaN` when the angle is not
/// positive.
pub fn implied_length(uz_mm: f64, uy_mm: f64, angle_deg: f64) -> f64 {
    if angle_deg <= 0.0 {
        return f64::NAN;
    }
    uz_mm - uy_mm / angle_deg.to_radians().tan()
}

/// The chord of a bending row over the chord of an arc of length `length_mm` with the same
/// angle, `c α / (L sin α)` with `c = −Uy / sin α`; `NaN` when the angle is not positive.
pub fn arc_ratio(uy_mm: f64, angle_deg: f64, length_mm: f64) -> f64 {
    if angle_deg <= 0.0 {
        return f64::NAN;
    }
    let a = angle_deg.to_radians();
    let chord = -uy_mm / a.sin();
    chord * a / (length_mm * a.sin())
}

/// The closest any arc-like bending shape comes to a recorded tip (mm): over every chord
/// angle `α` and every ratio `q ∈ [q_lo, q_hi]` of the chord to an arc's, the distance from
/// `(Uz, Uy)` to the tip `(L − q c(α) cos α, −q c(α) sin α)`, `c(α) = L sin α / α`. No model
/// whose shape stays in the band of the other rows can miss this tip by less: a floor on its
/// tip error there.
pub fn arc_floor_mm(uz_mm: f64, uy_mm: f64, length_mm: f64, q_lo: f64, q_hi: f64) -> f64 {
    // distance from the tip to the segment of tips at chord angle `a`
    let at = |a: f64| {
        let c = if a.abs() < 1e-12 {
            length_mm
        } else {
            length_mm * a.sin() / a
        };
        let (dz, dy) = (-a.cos(), -a.sin());
        // project the recorded tip onto the ray from the support
        let (pz, py) = (uz_mm - length_mm, uy_mm);
        let s = (pz * dz + py * dy).clamp(q_lo * c, q_hi * c);
        (pz - s * dz).hypot(py - s * dy)
    };
    let n = 2000;
    let h = std::f64::consts::FRAC_PI_2 / n as f64;
    let (mut best_a, mut best) = (0.0, f64::INFINITY);
    for i in 0..=n {
        let a = i as f64 * h;
        let d = at(a);
        if d < best {
            (best_a, best) = (a, d);
        }
    }
    // golden-section refinement around the best grid point
    let (mut lo, mut hi) = ((best_a - h).max(0.0), best_a + h);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if at(x1) < at(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    best.min(at(0.5 * (lo + hi)))
}

/// The median support-to-tip distance of the bending rows of each `N`.
fn lengths_by_n(rec: &Recordings) -> Vec<(usize, f64)> {
    let mut ns: Vec<usize> = rec.bending.iter().map(|r| r.n_bellows).collect();
    ns.sort_unstable();
    ns.dedup();
    ns.into_iter()
        .filter_map(|n| {
            let mut ls: Vec<f64> = rec
                .bending
                .iter()
                .filter(|r| r.n_bellows == n)
                .map(|r| implied_length(r.tip_uz_mm, r.tip_uy_mm, r.angle_deg))
                .filter(|l| l.is_finite())
                .collect();
            (!ls.is_empty()).then(|| (n, median(&mut ls)))
        })
        .collect()
}

/// Rows whose chord does not fit their angle (see the module documentation).
fn chord_flags(rec: &Recordings, flags: &mut Vec<DataFlag>) {
    let lengths = lengths_by_n(rec);
    let rows: Vec<(usize, f64)> = rec
        .bending
        .iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let l = lengths.iter().find(|(n, _)| *n == r.n_bellows)?.1;
            let q = arc_ratio(r.tip_uy_mm, r.angle_deg, l);
            q.is_finite().then_some((i, q))
        })
        .collect();
    if rows.len() < 5 {
        return;
    }
    let mut qs: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let med = median(&mut qs);
    let mut dev: Vec<f64> = rows.iter().map(|r| (r.1 - med).abs()).collect();
    let tol = (5.0 * 1.4826 * median(&mut dev)).max(0.05);
    let outlier = |q: f64| (q - med).abs() > tol;
    let (lo, hi) = rows
        .iter()
        .filter(|r| !outlier(r.1))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r.1), hi.max(r.1))
        });
    for &(i, q) in rows.iter().filter(|r| outlier(r.1)) {
        let r = &rec.bending[i];
        let a = r.angle_deg.to_radians();
        let l = lengths
            .iter()
            .find(|(n, _)| *n == r.n_bellows)
            .map_or(f64::NAN, |x| x.1);
        let (pct, side) = match q >= 1.0 {
            true => (100.0 * (q - 1.0), "farther"),
            false => (100.0 * (1.0 - q), "nearer"),
        };
        flags.push(DataFlag {
            config: Config::of(r.n_bellows, r.wall_thickness_mm, r.pressure_bar),
            recording: Recording::Bending,
            source: format!("{}, line {}", rec.bending_source, i + 2),
            message: format!(
                "the tip lies {:.1} mm from the support at an angle of {}°, {pct:.0} % {side} \
                 than an arc of the actuator's {l:.1} mm puts it ({:.1} mm); the other rows' \
                 ratios to their arcs lie in {lo:.2} … {hi:.2} (median {med:.3}, tolerance \
                 ±{tol:.3}): the angle and the tip cannot both be right; no shape within \
                 that band comes nearer to this tip than {:.1} mm, a floor on any such \
                 model's tip error here",
                -r.tip_uy_mm / a.sin(),
                r.angle_deg,
                l * a.sin() / a,
                arc_floor_mm(r.tip_uz_mm, r.tip_uy_mm, l, lo, hi),
            ),
        });
    }
}

/// Runs every check.
pub fn check(rec: &Recordings) -> Vec<DataFlag> {
    let mut flags = Vec::new();
    let config = Config::of;
    // support-to-tip distance per N
    let mut ns: Vec<usize> = rec.bending.iter().map(|r| r.n_bellows).collect();
    ns.sort_unstable();
    ns.dedup();
    for n in ns {
        let rows: Vec<(usize, f64)> = rec
            .bending
            .iter()
            .enumerate()
            .filter(|(_, r)| r.n_bellows == n)
            .map(|(i, r)| (i, implied_length(r.tip_uz_mm, r.tip_uy_mm, r.angle_deg)))
            .filter(|(_, l)| l.is_finite())
            .collect();
        if rows.len() < 3 {
            continue;
        }
        let mut ls: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let med = median(&mut ls);
        let mut dev: Vec<f64> = rows.iter().map(|r| (r.1 - med).abs()).collect();
        let mad = median(&mut dev);
        let tol = (5.0 * 1.4826 * mad).max(1.0);
        for &(i, l) in &rows {
            if (l - med).abs() > tol {
                let r = &rec.bending[i];
                flags.push(DataFlag {
                    config: config(r.n_bellows, r.wall_thickness_mm, r.pressure_bar),
                    recording: Recording::Bending,
                    source: format!("{}, line {}", rec.bending_source, i + 2),
                    message: format!(
                        "angle and tip imply a support-to-tip distance of {l:.1} mm; the other \
                         rows with N = {n} give {med:.1} mm (tolerance ±{tol:.1} mm)"
                    ),
                });
            }
        }
    }
    chord_flags(rec, &mut flags);
    // monotonic ramps
    let mut designs: Vec<(usize, f64)> = rec
        .bending
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm))
        .chain(rec.force.iter().map(|r| (r.n_bellows, r.wall_thickness_mm)))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    for (n, t) in designs {
        let mut b: Vec<(usize, &super::experiments::BendingRecord)> = rec
            .bending
            .iter()
            .enumerate()
            .filter(|(_, r)| r.n_bellows == n && r.wall_thickness_mm == t)
            .collect();
        b.sort_by(|x, y| x.1.pressure_bar.total_cmp(&y.1.pressure_bar));
        for w in b.windows(2) {
            let (lo, (i, hi)) = (w[0].1, w[1]);
            for (name, a, c) in [
                ("tip Uz", lo.tip_uz_mm, hi.tip_uz_mm),
                ("tip −Uy", -lo.tip_uy_mm, -hi.tip_uy_mm),
                ("angle", lo.angle_deg, hi.angle_deg),
            ] {
                if c < a {
                    flags.push(DataFlag {
                        config: config(n, t, hi.pressure_bar),
                        recording: Recording::Bending,
                        source: format!("{}, line {}", rec.bending_source, i + 2),
                        message: format!(
                            "{name} decreases from {a} at {} bar to {c} at {} bar",
                            lo.pressure_bar, hi.pressure_bar
                        ),
                    });
                }
            }
        }
        let mut f: Vec<(usize, &super::experiments::ForceRecord)> = rec
            .force
            .iter()
            .enumerate()
            .filter(|(_, r)| r.n_bellows == n && r.wall_thickness_mm == t)
            .collect();
        f.sort_by(|x, y| x.1.pressure_bar.total_cmp(&y.1.pressure_bar));
        for w in f.windows(2) {
            let (lo, (i, hi)) = (w[0].1, w[1]);
            if hi.force_n < lo.force_n {
                flags.push(DataFlag {
                    config: config(n, t, hi.pressure_bar),
                    recording: Recording::Force,
                    source: format!("{}, line {}", rec.force_source, i + 2),
                    message: format!(
                        "blocked force decreases from {} N at {} bar to {} N at {} bar",
                        lo.force_n, lo.pressure_bar, hi.force_n, hi.pressure_bar
                    ),
                });
            }
        }
    }
    flags
}
