//! Which rows a fit uses: configurations, exclusions and the selection.

use serde::{Deserialize, Serialize};

use crate::calibrate::CalibrateError;

/// A configuration `(N, T, P)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// Number of bellows.
    pub n_bellows: u32,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// Pressure (bar).
    pub pressure_bar: f64,
}

impl Config {
    /// The configuration of a recorded row.
    pub fn of(n_bellows: usize, wall_thickness_mm: f64, pressure_bar: f64) -> Self {
        Config {
            n_bellows: n_bellows as u32,
            wall_thickness_mm,
            pressure_bar,
        }
    }

    /// Same configuration (to 1e-9).
    pub fn same(&self, o: &Config) -> bool {
        self.n_bellows == o.n_bellows
            && (self.wall_thickness_mm - o.wall_thickness_mm).abs() < 1e-9
            && (self.pressure_bar - o.pressure_bar).abs() < 1e-9
    }

    /// `N=11 T=1.6 P=1`.
    pub fn label(&self) -> String {
        format!(
            "N={} T={} P={}",
            self.n_bellows, self.wall_thickness_mm, self.pressure_bar
        )
    }
}

/// Which recording an exclusion applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Recording {
    /// Bending row (tip, angle, markers).
    Bending,
    /// Blocked-force row.
    Force,
    /// Both.
    Both,
}

/// An excluded configuration, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Exclusion {
    /// The configuration.
    pub config: Config,
    /// The recording(s) excluded.
    pub recording: Recording,
    /// Why (given by the user, or by a data check).
    pub reason: String,
}

impl Exclusion {
    /// Parses `N,T,P` (both recordings), `bending:N,T,P` or `force:N,T,P`.
    ///
    /// # Errors
    /// Malformed text, naming what was expected.
    pub fn parse(text: &str) -> Result<Self, CalibrateError> {
        let expected =
            "N,T,P (both recordings), bending:N,T,P or force:N,T,P, e.g. bending:11,1.6,1";
        let (recording, rest) = match text.split_once(':') {
            Some(("bending", r)) => (Recording::Bending, r),
            Some(("force", r)) => (Recording::Force, r),
            Some(_) => return Err(CalibrateError::input("--exclude", text, expected)),
            None => (Recording::Both, text),
        };
        let v: Vec<f64> = rest
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| CalibrateError::input("--exclude", text, expected))?;
        if v.len() != 3 || v.iter().any(|x| !x.is_finite()) || v[0].fract() != 0.0 || v[0] < 1.0 {
            return Err(CalibrateError::input("--exclude", text, expected));
        }
        Ok(Exclusion {
            config: Config {
                n_bellows: v[0] as u32,
                wall_thickness_mm: v[1],
                pressure_bar: v[2],
            },
            recording,
            reason: "excluded by the user".into(),
        })
    }

    /// Whether it leaves out the row of recording `r` at `c`.
    pub fn applies(&self, c: &Config, r: Recording) -> bool {
        self.config.same(c) && (self.recording == Recording::Both || self.recording == r)
    }
}

/// Which configurations to use.
#[derive(Clone, Debug, Default)]
pub struct Selection {
    /// Only these `N` (empty: all).
    pub n_bellows: Vec<u32>,
    /// Only these `T` (empty: all).
    pub wall_thickness_mm: Vec<f64>,
    /// Only these `P` (empty: all).
    pub pressures_bar: Vec<f64>,
    /// Excluded rows.
    pub exclude: Vec<Exclusion>,
}

impl Selection {
    pub(super) fn keeps(&self, c: &Config) -> bool {
        (self.n_bellows.is_empty() || self.n_bellows.contains(&c.n_bellows))
            && (self.wall_thickness_mm.is_empty()
                || self
                    .wall_thickness_mm
                    .iter()
                    .any(|t| (t - c.wall_thickness_mm).abs() < 1e-9))
            && (self.pressures_bar.is_empty()
                || self
                    .pressures_bar
                    .iter()
                    .any(|p| (p - c.pressure_bar).abs() < 1e-9))
    }
}
