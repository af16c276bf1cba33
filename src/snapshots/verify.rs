//! Re-simulation check of a snapshot file: pick cases at random (seeded), run them again (in
//! parallel, on the FE campaign runner with nothing stored) and compare every stored output.
//!
//! For each chosen case, the stored rows must carry the plan's inputs, the same `converged`
//! flags as the new run, and outputs within the tolerance:
//! `max_{rows, outputs} |stored − fresh| ≤ tol` (`NaN` equals `NaN`; `NaN` against a number is
//! an infinite difference). The outputs are the 22 quantities `tip_uz_mm … m9_uy_mm`.

use std::collections::BTreeMap;
use std::path::Path;

use rand::seq::index::sample;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::plan::{Plan, PlannedCase};
use super::run::CaseRunner;
use super::store::{case_csv, case_name, CaseOutcome};
use super::SnapshotError;
use crate::fe::runner::{Batch, Independent, NoStore, Obtained};
use crate::schema::SNAPSHOT_COLUMN_NAMES;

/// Index of the first output column (`tip_uz_mm`).
const FIRST_OUTPUT: usize = 9;
/// Index of `converged`.
const CONVERGED: usize = 8;

/// The check of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseCheck {
    /// The case id.
    pub id: usize,
    /// Largest absolute difference over its rows and outputs.
    pub max_abs_diff: f64,
    /// Whether the `converged` flags agree row by row.
    pub same_convergence: bool,
}

/// Rows of a snapshot CSV grouped by `case_id`: the required cells of each row.
fn read_rows(path: &Path) -> Result<BTreeMap<String, Vec<Vec<String>>>, SnapshotError> {
    let bad = |line: usize, message: String| SnapshotError::CaseFile {
        path: path.display().to_string(),
        line,
        message,
    };
    let mut rdr = csv::Reader::from_path(path).map_err(|e| bad(1, e.to_string()))?;
    let header = rdr.headers().map_err(|e| bad(1, e.to_string()))?;
    if header
        .iter()
        .take(SNAPSHOT_COLUMN_NAMES.len())
        .ne(SNAPSHOT_COLUMN_NAMES)
    {
        return Err(bad(
            1,
            "header does not start with the snapshot columns".into(),
        ));
    }
    let mut out: BTreeMap<String, Vec<Vec<String>>> = BTreeMap::new();
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| bad(i + 2, e.to_string()))?;
        let cells: Vec<String> = rec
            .iter()
            .take(SNAPSHOT_COLUMN_NAMES.len())
            .map(str::to_owned)
            .collect();
        out.entry(cells[0].clone()).or_default().push(cells);
    }
    Ok(out)
}

/// `|a − b|` with `NaN = NaN`.
fn diff(a: f64, b: f64) -> f64 {
    match (a.is_nan(), b.is_nan()) {
        (true, true) => 0.0,
        (false, false) => (a - b).abs(),
        _ => f64::INFINITY,
    }
}

/// The rows of a case CSV written by [`case_csv`].
fn own_rows(bytes: &[u8]) -> Result<Vec<csv::StringRecord>, String> {
    csv::Reader::from_reader(bytes)
        .records()
        .collect::<Result<_, _>>()
        .map_err(|e| format!("re-reading the rows written for the case: {e}"))
}

/// Compares the stored rows of a case with rows written for it: row count, inputs and
/// pressure (`inputs_only`), or convergence flags and outputs.
fn compare(
    stored: &[Vec<String>],
    written: &[csv::StringRecord],
    check: &mut CaseCheck,
    inputs_only: bool,
) -> Result<(), String> {
    if written.len() != stored.len() {
        return Err(format!(
            "{} rows stored, {} expected",
            stored.len(),
            written.len()
        ));
    }
    for (s, f) in stored.iter().zip(written) {
        if inputs_only {
            if (0..CONVERGED).any(|c| s[c] != f[c]) {
                let plan: Vec<&str> = f.iter().take(CONVERGED).collect();
                let stored = &s[..CONVERGED];
                return Err(format!(
                    "stored inputs {stored:?} differ from the plan's {plan:?}"
                ));
            }
            continue;
        }
        check.same_convergence &= s[CONVERGED] == f[CONVERGED];
        for c in FIRST_OUTPUT..SNAPSHOT_COLUMN_NAMES.len() {
            let a = s[c].parse::<f64>().unwrap_or(f64::NAN);
            let b = f[c].parse::<f64>().unwrap_or(f64::NAN);
            check.max_abs_diff = check.max_abs_diff.max(diff(a, b));
        }
    }
    Ok(())
}

/// Re-runs `n_cases` cases of the snapshot file `data` chosen at random with `seed` (all if
/// fewer), with `runner`, and compares them with the stored rows.
///
/// # Errors
/// A file that cannot be read, a case id not in the plan, stored inputs that differ from the
/// plan's ([`SnapshotError::CaseFile`]); checked before anything runs.
pub fn resimulate(
    data: &Path,
    plan: &Plan,
    n_cases: usize,
    seed: u64,
    runner: &dyn CaseRunner,
) -> Result<Vec<CaseCheck>, SnapshotError> {
    let rows = read_rows(data)?;
    let bad = |name: &str, message: String| SnapshotError::CaseFile {
        path: data.display().to_string(),
        line: 0,
        message: format!("{name}: {message}"),
    };
    let by_name: BTreeMap<String, _> = plan.cases.iter().map(|c| (case_name(c.id), c)).collect();
    let names: Vec<&String> = rows.keys().collect();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut chosen = Vec::new();
    for i in sample(&mut rng, names.len(), n_cases.min(names.len())) {
        let name = names[i];
        let case = *by_name
            .get(name)
            .ok_or_else(|| bad(name, "not a case of the plan".into()))?;
        let mut check = CaseCheck {
            id: case.id,
            max_abs_diff: 0.0,
            same_convergence: true,
        };
        let planned = own_rows(&case_csv(case, &plan.settings, &CaseOutcome::default()))
            .map_err(|m| bad(name, m))?;
        compare(&rows[name], &planned, &mut check, true).map_err(|m| bad(name, m))?;
        chosen.push((name, case, check));
    }
    chosen.sort_by_key(|(_, case, _)| case.id);
    let cases: Vec<&PlannedCase> = chosen.iter().map(|(_, case, _)| *case).collect();
    let store = NoStore::new();
    let Ok(batch) = Batch::look_up(&cases, &store);
    let solver = Independent(|case: &&PlannedCase| runner.run(case, &plan.settings));
    let Ok(reports) = batch.run(&[], &solver, |_, _| {});
    chosen
        .into_iter()
        .zip(reports)
        .map(|((name, case, mut check), report)| {
            let outcome = match report.obtained {
                Obtained::Run(o) | Obtained::Cache(o) | Obtained::Failed { ramp: o, .. } => o,
            };
            let fresh =
                own_rows(&case_csv(case, &plan.settings, &outcome)).map_err(|m| bad(name, m))?;
            compare(&rows[name], &fresh, &mut check, false).map_err(|m| bad(name, m))?;
            Ok(check)
        })
        .collect()
}
