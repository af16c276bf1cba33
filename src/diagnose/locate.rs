//! Locate: where the calibrated model misses the recordings, read top to bottom as stages:
//! residual table → shares → misfit, structure and group tests → Holm → findings → what is
//! missing (the statistics: the [module docs](super)).

use serde::{Deserialize, Serialize};

use super::cells::{residual_table, Cell, Family};
use super::coverage::{missing, Missing};
use super::findings::{findings, Evidence, Finding};
use super::groups::{group_means, holm, misfits, shares, GroupMean, Misfit, Shares};
use super::structure::{explain_by_significant, fit, Structure};
use super::DiagnoseError;
use crate::calibrate::{Calibration, Recordings};
use crate::rom::Surrogate;

/// Settings of [`locate`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocateSettings {
    /// Family-wise significance level of all the report's tests together (Holm).
    pub alpha: f64,
}

impl Default for LocateSettings {
    fn default() -> Self {
        LocateSettings { alpha: 0.05 }
    }
}

impl LocateSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// `alpha` outside `(0, 0.5]`.
    pub fn validate(&self) -> Result<(), DiagnoseError> {
        if !(self.alpha > 0.0 && self.alpha <= 0.5) {
            return Err(DiagnoseError::input(
                "alpha",
                self.alpha,
                "a significance level in (0, 0.5]",
            ));
        }
        Ok(())
    }
}

/// Where the residual of a calibration is, and what it looks like.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Localisation {
    /// Family-wise significance level.
    pub alpha: f64,
    /// Number of tests the level is shared over (Holm).
    pub tests: usize,
    /// `Σ z²` over every cell.
    pub chi2: f64,
    /// The residual table: output × design × pressure (× marker).
    pub cells: Vec<Cell>,
    /// χ² shares by output, design, N, T, P and marker.
    pub shares: Shares,
    /// Each output's misfit against the recorded scatter.
    pub misfits: Vec<Misfit>,
    /// Each output's structure over N, T, P (and along the actuator).
    pub structures: Vec<Structure>,
    /// Each output's mean and signs per group (T, N, P, design, marker).
    pub groups: Vec<GroupMean>,
    /// Whether marker recordings let the residual be located along the actuator.
    pub along_actuator: bool,
    /// The findings in words, most general first.
    pub findings: Vec<Finding>,
    /// What the recordings do not have.
    pub missing: Vec<Missing>,
}

impl Localisation {
    /// The structure of an output, if it was fitted.
    pub fn structure(&self, f: Family) -> Option<&Structure> {
        self.structures.iter().find(|s| s.family == f)
    }

    /// The cells of an output.
    pub fn cells_of(&self, f: Family) -> impl Iterator<Item = &Cell> {
        self.cells.iter().filter(move |c| c.family == f)
    }

    /// Whether nothing this stage tests is significant: every output within the recorded
    /// scatter, no term over N, T, P, no group mean. A name the Name stage then gives is a
    /// hypothesis, not a finding (the residual it explains may be the recordings' noise).
    pub fn consistent_with_scatter(&self) -> bool {
        !self.misfits.iter().any(|m| m.significant)
            && !self
                .structures
                .iter()
                .any(|s| s.terms.iter().any(|t| t.significant))
            && !self.groups.iter().any(|g| g.significant)
    }
}

/// Locates the residual of `cal` on the recordings `rec` it was fitted to (the outputs its
/// objective left out are predicted through `model` at the calibrated set).
///
/// # Errors
/// Bad settings, a calibration without residuals, or a surrogate query that fails.
pub fn locate(
    cal: &Calibration,
    model: &Surrogate,
    rec: &Recordings,
    s: &LocateSettings,
) -> Result<Localisation, DiagnoseError> {
    s.validate()?;
    let table = residual_table(cal, model, rec)?;
    let cells = &table.cells;
    let shares = shares(cells, table.chi2);
    let mut misfits = misfits(cells);
    let of = |f: Family| -> Vec<&Cell> { cells.iter().filter(|c| c.family == f).collect() };
    let mut structures: Vec<Structure> =
        Family::ALL.iter().filter_map(|&f| fit(f, &of(f))).collect();
    let mut groups = group_means(cells);
    let tests = adjust(&mut misfits, &mut structures, &mut groups, s.alpha);
    for st in &mut structures {
        explain_by_significant(st, &of(st.family));
    }
    let findings = findings(&Evidence {
        misfits: &misfits,
        structures: &structures,
        groups: &groups,
        shares: &shares,
        tests,
        alpha: s.alpha,
    });
    let missing = missing(rec, cal, &table.outside_domain);
    Ok(Localisation {
        alpha: s.alpha,
        tests,
        chi2: table.chi2,
        along_actuator: cells.iter().any(|c| c.marker.is_some()),
        cells: table.cells,
        shares,
        misfits,
        structures,
        groups,
        findings,
        missing,
    })
}

/// Holm's procedure over every test of the report; returns the number of tests.
fn adjust(
    misfits: &mut [Misfit],
    structures: &mut [Structure],
    groups: &mut [GroupMean],
    alpha: f64,
) -> usize {
    let mut p: Vec<f64> = misfits.iter().map(|m| m.p_value).collect();
    for s in structures.iter() {
        p.extend(s.terms.iter().map(|t| t.p_value));
    }
    p.extend(groups.iter().map(|g| g.p_value));
    let sig = holm(&p, alpha);
    let mut k = 0;
    for m in misfits.iter_mut() {
        m.significant = sig[k];
        k += 1;
    }
    for s in structures.iter_mut() {
        for t in &mut s.terms {
            t.significant = sig[k];
            k += 1;
        }
    }
    for g in groups.iter_mut() {
        g.significant = sig[k];
        k += 1;
    }
    p.len()
}
