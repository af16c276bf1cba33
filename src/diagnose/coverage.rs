//! What the recordings do not have, against the shipped experiments' plan (9 designs × 1, 2,
//! 3 bar, bending and blocked force) and against what a diagnosis can use (markers along the
//! actuator).

use serde::{Deserialize, Serialize};

use crate::calibrate::experiments::shipped_bending;
use crate::calibrate::fit::describe_exclusions;
use crate::calibrate::{Calibration, Recordings};

/// What kind of thing is missing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MissingKind {
    /// Blocked-force recordings (none, or not at every bending configuration).
    Force,
    /// Marker recordings along the actuator (none, or not at every configuration).
    Markers,
    /// A design of the shipped plan with no recording.
    Design,
    /// Pressures of the shipped plan absent for a recorded design.
    Pressure,
    /// Rows outside the surrogate's domain (not used).
    OutsideDomain,
    /// Rows the calibration excluded (not used).
    Excluded,
}

/// One thing the diagnosis could not use.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Missing {
    /// Its kind.
    pub kind: MissingKind,
    /// What is missing.
    pub what: String,
    /// What the diagnosis therefore cannot say.
    pub consequence: String,
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

type Configuration = (usize, f64, f64);

/// The list for `rec` (calibrated as `cal`); `outside` names the rows outside the surrogate's
/// domain.
pub fn missing(rec: &Recordings, cal: &Calibration, outside: &[String]) -> Vec<Missing> {
    let bending: Vec<Configuration> = rec
        .bending
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
        .collect();
    let force: Vec<Configuration> = rec
        .force
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
        .collect();
    let markers: Vec<Configuration> = rec
        .markers
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
        .collect();
    let mut out = Vec::new();
    out.extend(partial(
        MissingKind::Force,
        &bending,
        &force,
        ("no blocked-force recordings", "blocked force"),
        (
            "the blocked force is not diagnosed, so a misfit that moves force and bending \
             differently cannot be seen",
            "the force's structure rests on the configurations recorded",
        ),
    ));
    out.extend(partial(
        MissingKind::Markers,
        &bending,
        &markers,
        ("no marker recordings along the actuator", "markers"),
        (
            "the residual cannot be located along the actuator; only the tip and the angle it \
             implies are compared",
            "the residual along the actuator rests on the configurations recorded",
        ),
    ));
    out.extend(against_plan(&bending));
    for o in outside {
        out.push(Missing {
            kind: MissingKind::OutsideDomain,
            what: o.clone(),
            consequence: "not diagnosed: the surrogate does not predict there".into(),
        });
    }
    for e in describe_exclusions(&cal.excluded) {
        out.push(Missing {
            kind: MissingKind::Excluded,
            what: format!("excluded from the calibration: {e}"),
            consequence: "not diagnosed".into(),
        });
    }
    out
}

/// A recording absent (`rows` empty) or absent at some bending configurations; `what` and
/// `consequence` word each case (none, some).
fn partial(
    kind: MissingKind,
    bending: &[Configuration],
    rows: &[Configuration],
    what: (&str, &str),
    consequence: (&str, &str),
) -> Option<Missing> {
    if rows.is_empty() {
        return Some(Missing {
            kind,
            what: what.0.into(),
            consequence: consequence.0.into(),
        });
    }
    let lacking: Vec<String> = bending
        .iter()
        .filter(|c| {
            !rows
                .iter()
                .any(|r| r.0 == c.0 && same(r.1, c.1) && same(r.2, c.2))
        })
        .map(|c| format!("N={} T={} P={}", c.0, c.1, c.2))
        .collect();
    (!lacking.is_empty()).then(|| Missing {
        kind,
        what: format!(
            "no {} at {} of {} bending configurations: {}",
            what.1,
            lacking.len(),
            bending.len(),
            lacking.join(", ")
        ),
        consequence: consequence.1.into(),
    })
}

/// Designs and pressures of the shipped plan without a bending recording.
fn against_plan(bending: &[Configuration]) -> Vec<Missing> {
    let plan: Vec<Configuration> = shipped_bending()
        .map(|rows| {
            rows.iter()
                .map(|r| (r.n_bellows, r.wall_thickness_mm, r.pressure_bar))
                .collect()
        })
        .unwrap_or_default();
    let mut designs: Vec<(usize, f64)> = plan.iter().map(|c| (c.0, c.1)).collect();
    designs.dedup_by(|a, b| a.0 == b.0 && same(a.1, b.1));
    let mut out = Vec::new();
    for (n, t) in designs {
        let planned: Vec<f64> = plan
            .iter()
            .filter(|c| c.0 == n && same(c.1, t))
            .map(|c| c.2)
            .collect();
        let absent: Vec<String> = planned
            .iter()
            .filter(|&&p| {
                !bending
                    .iter()
                    .any(|c| c.0 == n && same(c.1, t) && same(c.2, p))
            })
            .map(|p| p.to_string())
            .collect();
        if absent.len() == planned.len() {
            out.push(Missing {
                kind: MissingKind::Design,
                what: format!("design N={n} T={t}: no recording (the shipped plan has it)"),
                consequence: "the structure over N and T rests on the other designs".into(),
            });
        } else if !absent.is_empty() {
            out.push(Missing {
                kind: MissingKind::Pressure,
                what: format!(
                    "design N={n} T={t}: no recording at {} bar (the shipped plan has it)",
                    absent.join(", ")
                ),
                consequence: "the trend over P of this design rests on the other pressures".into(),
            });
        }
    }
    out
}
