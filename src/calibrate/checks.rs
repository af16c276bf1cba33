//! Data checks: recordings inconsistent with themselves or with the rest.
//!
//! - **Support-to-tip distance.** A bending row's angle and tip displacements imply the
//!   distance from the support point to the undeformed tip,
//!   `L = Uz + (−Uy) / tan α` (the deformed tip lies at `(L − Uz, Uy)` and
//!   `tan α = −Uy / (L − Uz)`). All rows of one `N` come from the same printed length, so a
//!   row whose `L` departs from the median of its `N` by more than
//!   `max(1 mm, 5 × 1.4826 × MAD)` is flagged.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_inconsistent_row_is_flagged_and_only_it() {
        let rec = Recordings::shipped().unwrap();
        let flags = check(&rec);
        assert_eq!(flags.len(), 1, "{flags:#?}");
        let f = &flags[0];
        assert_eq!(
            (
                f.config.n_bellows,
                f.config.wall_thickness_mm,
                f.config.pressure_bar
            ),
            (11, 1.6, 1.0)
        );
        assert!(f.message.contains("95.7 mm"), "{}", f.message);
        assert!(f.source.ends_with("line 11"), "{}", f.source);
    }

    #[test]
    fn a_decreasing_force_is_flagged() {
        let mut rec = Recordings::shipped().unwrap();
        rec.force[2].force_n = 1.0; // N = 9, T = 1.6, 3 bar below its 2 bar value
        let flags = check(&rec);
        assert!(flags
            .iter()
            .any(|f| f.recording == Recording::Force && f.message.contains("decreases")));
    }
}
