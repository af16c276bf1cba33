//! Merging shard directories into one snapshot CSV.
//!
//! The merge reads the case files of every directory (all of the same plan), checks that every
//! plan case is there exactly once, validates each file, and writes the header followed by the
//! case files' rows in case-id order (each case's rows are in plan-pressure order). The text of
//! each case file is copied unchanged, so the result is byte-identical to merging one run of
//! the whole plan, whatever the sharding, thread count or resume history.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::plan::{Plan, PlannedCase};
use super::store::{
    case_name, check_row, header_with, read_case_file, CsvText, ShardDir, BASE_COLUMNS,
};
use super::SnapshotError;

/// What a merge wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct MergeSummary {
    /// Cases merged.
    pub cases: usize,
    /// Rows written.
    pub rows: usize,
    /// Cases with an error (some steps not reached).
    pub failed_cases: usize,
    /// Rows with `converged = false`.
    pub unconverged_rows: usize,
    /// Plan cases without a file (only with `allow_missing`).
    pub missing_cases: usize,
    /// The plan hash.
    pub plan_hash: String,
}

/// At most 10 ids, then a count.
fn id_list(ids: &[usize]) -> String {
    let shown: Vec<String> = ids.iter().take(10).map(|&i| case_name(i)).collect();
    let more = ids.len().saturating_sub(10);
    if more > 0 {
        format!("{} and {more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

/// The plan of `dirs` (all the same) and the case files found, by id; duplicate ids.
type Found = (Plan, BTreeMap<usize, PathBuf>, Vec<usize>);

/// Opens every directory, checks they hold one plan, and lists their case files.
fn collect(dirs: &[PathBuf]) -> Result<Found, SnapshotError> {
    let Some(first) = dirs.first() else {
        return Err(merge_error("no shard directory given".into()));
    };
    let (_, plan) = ShardDir::open(first)?;
    let hash = plan.hash();
    let mut found: BTreeMap<usize, PathBuf> = BTreeMap::new();
    let mut duplicates = Vec::new();
    for d in dirs {
        let (dir, p) = ShardDir::open(d)?;
        if p.hash() != hash {
            return Err(merge_error(format!(
                "{} holds plan {} but {} holds plan {hash}",
                d.display(),
                p.hash(),
                first.display()
            )));
        }
        for (id, path) in dir.case_ids()? {
            if let Some(prev) = found.insert(id, path.clone()) {
                if prev != path {
                    duplicates.push(id);
                }
            }
        }
    }
    Ok((plan, found, duplicates))
}

fn merge_error(message: String) -> SnapshotError {
    SnapshotError::Merge { message }
}

/// Every plan case exactly once, nothing else.
fn check_complete(
    plan: &Plan,
    found: &BTreeMap<usize, PathBuf>,
    duplicates: &[usize],
    allow_missing: bool,
) -> Result<usize, SnapshotError> {
    let missing: Vec<usize> = plan
        .cases
        .iter()
        .map(|c| c.id)
        .filter(|id| !found.contains_key(id))
        .collect();
    let unknown: Vec<usize> = found
        .keys()
        .copied()
        .filter(|id| !plan.cases.iter().any(|c| c.id == *id))
        .collect();
    let mut parts = Vec::new();
    if !missing.is_empty() && !allow_missing {
        parts.push(format!(
            "{} cases missing ({})",
            missing.len(),
            id_list(&missing)
        ));
    }
    if !duplicates.is_empty() {
        let (n, ids) = (duplicates.len(), id_list(duplicates));
        parts.push(format!("{n} cases in more than one directory ({ids})"));
    }
    if !unknown.is_empty() {
        let (n, ids) = (unknown.len(), id_list(&unknown));
        parts.push(format!("{n} case files not in the plan ({ids})"));
    }
    if parts.is_empty() {
        Ok(missing.len())
    } else {
        Err(merge_error(format!(
            "plan {}: {}",
            plan.hash(),
            parts.join("; ")
        )))
    }
}

/// Joins the shard directories `dirs` into one CSV at `out` (written atomically), with the
/// plan copy beside it ([`sidecar_path`]). Rows are sorted by case id, then pressure; the
/// result is byte-identical to merging a single run of the whole plan.
///
/// # Errors
/// [`SnapshotError::Merge`] if the directories hold different plans, a case is missing, or a
/// case appears more than once; case-file and I/O errors. Nothing is written on error.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<MergeSummary, SnapshotError> {
    merge_with(dirs, out, false)
}

/// [`merge`], or with `allow_missing` the finished cases only (to train on a set that is
/// still running): missing cases are counted in [`MergeSummary::missing_cases`]; duplicates
/// and files of cases not in the plan are still errors.
///
/// # Errors
/// As [`merge`], less the missing cases when they are allowed.
pub fn merge_with(
    dirs: &[PathBuf],
    out: &Path,
    allow_missing: bool,
) -> Result<MergeSummary, SnapshotError> {
    let (plan, found, duplicates) = collect(dirs)?;
    let missing_cases = check_complete(&plan, &found, &duplicates, allow_missing)?;
    let mut cases: Vec<&PlannedCase> = plan
        .cases
        .iter()
        .filter(|c| found.contains_key(&c.id))
        .collect();
    cases.sort_by_key(|c| c.id);
    let mut text = header_with(&plan.effect_columns()).into_bytes();
    text.push(b'\n');
    let mut summary = MergeSummary {
        cases: cases.len(),
        rows: 0,
        failed_cases: 0,
        unconverged_rows: 0,
        missing_cases,
        plan_hash: plan.hash(),
    };
    for case in cases {
        let file = read_case_file(&found[&case.id], case, &plan.settings)?;
        text.extend_from_slice(&file.body);
        summary.rows += plan.settings.pressures_bar.len();
        summary.failed_cases += usize::from(file.failed);
        summary.unconverged_rows += file.unconverged_rows;
    }
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| SnapshotError::io(parent, e))?;
    }
    let sidecar = sidecar_path(out);
    crate::io::write_atomic(&sidecar, plan.pretty_json().as_bytes())
        .map_err(|e| SnapshotError::io(&sidecar, e))?;
    crate::io::write_atomic(out, &text).map_err(|e| SnapshotError::io(out, e))?;
    Ok(summary)
}

/// The plan copy written beside a merged file: `<stem>.plan.json`.
pub fn sidecar_path(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "snapshots".into());
    out.with_file_name(format!("{stem}.plan.json"))
}

/// Checks that the merged file at `path` is a complete merge of the plan beside it
/// ([`sidecar_path`]): the header of the plan's columns, then every plan case exactly once in
/// case-id order, each with one row per plan pressure carrying the plan's inputs and settings
/// (what [`merge`] writes). A finished campaign is committed this way, once, without its case
/// files.
///
/// # Errors
/// [`SnapshotError::CaseFile`] naming the line and what differs; plan and I/O errors.
pub fn check_merged(path: &Path) -> Result<MergeSummary, SnapshotError> {
    let plan = Plan::read(&sidecar_path(path))?;
    let file = CsvText::read(path)?;
    let bad = |line: usize, message: String| file.error(line, message);
    if file.head() != header_with(&plan.effect_columns()).as_bytes() {
        let why = "header differs from the snapshot columns of the plan beside the file";
        return Err(bad(1, why.into()));
    }
    let mut cases: Vec<&PlannedCase> = plan.cases.iter().collect();
    cases.sort_by_key(|c| c.id);
    let n = plan.settings.pressures_bar.len();
    let mut summary = MergeSummary {
        cases: cases.len(),
        rows: 0,
        failed_cases: 0,
        unconverged_rows: 0,
        missing_cases: 0,
        plan_hash: plan.hash(),
    };
    let mut failed = vec![false; cases.len()];
    for (k, rec) in file.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| bad(line, e.to_string()))?;
        let Some(case) = cases.get(k / n) else {
            let why = format!(
                "more rows than the plan's {} cases × {n} pressures",
                cases.len()
            );
            return Err(bad(line, why));
        };
        let converged = check_row(&rec, k % n, case, &plan.settings)
            .map_err(|m| bad(line, format!("{}: {m}", case_name(case.id))))?;
        summary.unconverged_rows += usize::from(!converged);
        failed[k / n] |= !rec[BASE_COLUMNS - 1].is_empty();
        summary.rows += 1;
    }
    if summary.rows != cases.len() * n {
        let why = format!(
            "{} rows, expected every plan case once with one row per pressure ({} × {n})",
            summary.rows,
            cases.len()
        );
        return Err(bad(summary.rows + 2, why));
    }
    summary.failed_cases = failed.iter().filter(|f| **f).count();
    Ok(summary)
}
