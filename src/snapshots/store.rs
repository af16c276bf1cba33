//! The snapshot store: what a runner returns for a case ([`CaseOutcome`]), the CSV columns, and
//! the atomic per-case files of a shard directory (merged by [`mod@super::merge`]).
//!
//! ## Columns
//!
//! [`SNAPSHOT_COLUMN_NAMES`] (the surrogate trainer's contract: `case_id, n_bellows,
//! wall_thickness_mm, mu1_mpa, alpha1, mu2_mpa, alpha2, pressure_bar, converged, tip_uz_mm,
//! tip_uy_mm, angle_deg, force_n, m1_uz_mm, m1_uy_mm, …, m9_uz_mm, m9_uy_mm`), then
//! [`PROVENANCE_COLUMNS`]; their units and meanings are in [`crate::schema`] (format
//! `snapshots`). The provenance holds how the step was reached (`newton_iterations`,
//! `substeps`, `cutbacks`: empty if not), its `residual` and `min_gap_mm`, the plan's FE
//! settings (`mesh`, `element_size_mm`, `bulk_ratio`, `gravity`, `solver_rtol`),
//! [`super::code_version`] and the `error` that left a step without a result.
//!
//! A plan with effects (fixed or sampled, [`super::plan`]) adds one column per effect after
//! the provenance, in the library's order, named by [`schema::effect_column`]
//! (`effect_wall_bias_mm`), holding the case's value; a plan without effects writes exactly
//! the columns above.
//!
//! `case_id` is `case_<id, 6 digits>`. A case has one row per plan pressure, in plan order;
//! steps the solver did not reach have `converged = false` and `NaN` outputs. Floats are
//! written in Rust's shortest round-trip form (`{:?}`), so reading gives the same bits.
//! `force_n` is the plate reaction of the case's blocked-force ramp at the same pressure (see
//! [`super::fe_runner`]).
//!
//! ## Shard directory
//!
//! `plan.json`, `plan_hash` and `cases/case_<id>.csv` (see [`super`]); case files are written
//! to `cases/.case_<id>.csv.<pid>-<k>.tmp`, fsynced, renamed, and the directory fsynced
//! ([`crate::io::write_atomic`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::plan::{Plan, PlanSettings, PlannedCase};
use super::{code_version, SnapshotError};
use crate::fe::effects::Effect;
use crate::fe::runner::Outcome;
use crate::schema::{self, SNAPSHOT_COLUMN_NAMES};

/// Outputs of one converged pressure step.
#[derive(Clone, Debug, PartialEq)]
pub struct StepOutputs {
    /// Tip `Uz = −Δz` (mm).
    pub tip_uz_mm: f64,
    /// Tip `Uy = Δy` (mm).
    pub tip_uy_mm: f64,
    /// Bending angle (deg).
    pub angle_deg: f64,
    /// Blocked force (N); `NaN` when not computed.
    pub force_n: f64,
    /// Markers 1..9: `[Uz, Uy]` (mm).
    pub markers: [[f64; 2]; 9],
    /// Newton iterations to reach the step.
    pub newton_iterations: usize,
    /// Load substeps.
    pub substeps: usize,
    /// Cut-backs.
    pub cutbacks: usize,
    /// Final normalised residual.
    pub residual: f64,
    /// Smallest deformed gap between bellows (mm).
    pub min_gap_mm: f64,
    /// Whether the step converged.
    pub converged: bool,
}

/// What a runner returns for one case: the steps reached, in plan-pressure order (a prefix
/// of the ramp), and why it stopped early, if it did.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct CaseOutcome {
    /// Steps reached (at most one per plan pressure).
    pub steps: Vec<StepOutputs>,
    /// The error that stopped the ramp.
    pub error: Option<String>,
}

impl CaseOutcome {
    /// A case that produced nothing.
    pub fn failed(error: impl Into<String>) -> Self {
        Self {
            steps: Vec::new(),
            error: Some(error.into()),
        }
    }

    /// Whether the case stopped early.
    pub fn is_failed(&self) -> bool {
        self.error.is_some()
    }
}

impl Outcome for CaseOutcome {
    fn failure(&self) -> Option<&str> {
        self.error.as_deref()
    }
}

/// Provenance columns after [`SNAPSHOT_COLUMN_NAMES`] ([`schema::PROVENANCE_COLUMNS`]).
pub const PROVENANCE_COLUMNS: [&str; 12] = schema::names(&schema::PROVENANCE_COLUMNS);

/// Name of the plan-hash marker file.
pub const PLAN_HASH_FILE: &str = "plan_hash";
/// Name of the plan copy.
pub const PLAN_FILE: &str = "plan.json";
/// Name of the case-file folder.
pub const CASES_DIR: &str = "cases";

/// The header line (without newline) of a plan without effects.
pub fn header_line() -> String {
    header_with(&[])
}

/// The header line (without newline) of a plan whose effect columns are `effects`
/// ([`Plan::effect_columns`]).
pub fn header_with(effects: &[Effect]) -> String {
    let mut all: Vec<String> = SNAPSHOT_COLUMN_NAMES
        .iter()
        .chain(PROVENANCE_COLUMNS.iter())
        .map(|c| c.to_string())
        .collect();
    all.extend(
        effects
            .iter()
            .map(|e| schema::effect_column(e.name(), e.info().unit)),
    );
    all.join(",")
}

/// Number of columns without effects; the `error` column is the last of them.
pub(super) const BASE_COLUMNS: usize = SNAPSHOT_COLUMN_NAMES.len() + PROVENANCE_COLUMNS.len();

/// The effects of a case's columns and their values, in the library's order.
fn effect_cells(case: &PlannedCase, settings: &PlanSettings) -> Vec<(Effect, f64)> {
    // a validated plan never conflicts; a hand-built one shows its case's own values
    let all = case
        .effects_with(settings)
        .unwrap_or_else(|_| case.effects.clone());
    all.iter().collect()
}

pub use super::plan::case_name;

/// Shortest round-trip text of a float.
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The cells of one row: inputs, pressure, outputs (if any) and provenance.
fn row_cells(
    case: &PlannedCase,
    settings: &PlanSettings,
    pressure: f64,
    step: Option<&StepOutputs>,
    error: &str,
) -> Vec<String> {
    let mut r = vec![
        case_name(case.id),
        case.n_bellows.to_string(),
        num(case.wall_thickness_mm),
        num(case.material.mu1_mpa),
        num(case.material.alpha1),
        num(case.material.mu2_mpa),
        num(case.material.alpha2),
        num(pressure),
        step.is_some_and(|s| s.converged).to_string(),
    ];
    match step {
        Some(s) => {
            r.extend([s.tip_uz_mm, s.tip_uy_mm, s.angle_deg, s.force_n].map(num));
            r.extend(s.markers.iter().flat_map(|m| [num(m[0]), num(m[1])]));
            r.extend([
                s.newton_iterations.to_string(),
                s.substeps.to_string(),
                s.cutbacks.to_string(),
                num(s.residual),
                num(s.min_gap_mm),
            ]);
        }
        None => {
            r.extend(std::iter::repeat_n(num(f64::NAN), 4 + 18));
            r.extend(std::iter::repeat_n(String::new(), 5));
        }
    }
    r.extend([
        settings.mesh.level.name().to_owned(),
        settings.mesh.element_size.map(num).unwrap_or_default(),
        num(settings.bulk_ratio),
        settings.gravity.to_string(),
        num(settings.solver.rtol),
        code_version(),
        error.to_owned(),
    ]);
    r.extend(
        effect_cells(case, settings)
            .into_iter()
            .map(|(_, v)| num(v)),
    );
    r
}

/// Error text on one line (newlines would make the CSV awkward for line-based tools).
fn one_line(s: &str) -> String {
    s.split(['\n', '\r'])
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// The CSV text of one case (header + one row per plan pressure).
///
/// Steps beyond `outcome.steps` get `converged = false`, `NaN` outputs and the outcome's
/// error (or a note that the runner returned too few steps).
pub fn case_csv(case: &PlannedCase, settings: &PlanSettings, outcome: &CaseOutcome) -> Vec<u8> {
    let missing_error = match &outcome.error {
        Some(e) => one_line(e),
        None => format!(
            "runner returned {} of {} steps without an error",
            outcome.steps.len(),
            settings.pressures_bar.len()
        ),
    };
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    let effects: Vec<Effect> = effect_cells(case, settings)
        .into_iter()
        .map(|(e, _)| e)
        .collect();
    let mut out = header_with(&effects).into_bytes();
    out.push(b'\n');
    for (j, &p) in settings.pressures_bar.iter().enumerate() {
        let step = outcome.steps.get(j);
        let error = if step.is_some() { "" } else { &missing_error };
        let cells = row_cells(case, settings, p, step, error);
        w.write_record(&cells).expect("writing to memory"); // ok: strings into a Vec cannot fail
    }
    out.extend(w.into_inner().expect("writing to memory")); // ok: flushing a Vec cannot fail
    out
}

/// A validated case file: its data rows as written (without the header).
#[derive(Debug)]
pub struct CaseFile {
    /// The rows' bytes, ending with a newline.
    pub body: Vec<u8>,
    /// Whether any row carries an error.
    pub failed: bool,
    /// Rows with `converged = false`.
    pub unconverged_rows: usize,
    /// The first error message of the case's rows, if any.
    pub error: Option<String>,
}

/// Checks one data row (0-based `j`) of a case file; returns whether it converged.
pub(super) fn check_row(
    rec: &csv::StringRecord,
    j: usize,
    case: &PlannedCase,
    settings: &PlanSettings,
) -> Result<bool, String> {
    let Some(&p) = settings.pressures_bar.get(j) else {
        let n = settings.pressures_bar.len();
        return Err(format!("more rows than the plan's {n} pressures"));
    };
    // inputs, pressure, the plan's settings (not code_version: a resume may use a newer build)
    // and the effects
    let expected = row_cells(case, settings, p, None, "");
    if rec.len() != expected.len() {
        return Err(format!("{} cells, expected {}", rec.len(), expected.len()));
    }
    let effects: Vec<Effect> = effect_cells(case, settings)
        .into_iter()
        .map(|(e, _)| e)
        .collect();
    let header = header_with(&effects);
    let header: Vec<&str> = header.split(',').collect();
    let b = BASE_COLUMNS;
    for col in (0..8).chain(b - 7..b - 2).chain(b..expected.len()) {
        if rec[col] != expected[col] {
            let name = header.get(col).copied().unwrap_or("?");
            return Err(format!(
                "{name} = {:?}, expected {:?} (the plan's value)",
                &rec[col], expected[col]
            ));
        }
    }
    let converged = match &rec[8] {
        "true" => true,
        "false" => false,
        other => return Err(format!("converged = {other:?}, expected true or false")),
    };
    for (col, name) in SNAPSHOT_COLUMN_NAMES.iter().enumerate().skip(9) {
        if rec[col].parse::<f64>().is_err() {
            return Err(format!("{name} = {:?} is not a number", &rec[col]));
        }
    }
    Ok(converged)
}

/// A snapshot CSV read whole: its header line, the rows after it, and errors that name the file
/// and a line. Case files and merged files share this reading.
pub(super) struct CsvText {
    path: String,
    bytes: Vec<u8>,
    head_end: usize,
}

impl CsvText {
    /// Reads the file at `path`.
    ///
    /// # Errors
    /// I/O errors naming the path.
    pub(super) fn read(path: &Path) -> Result<Self, SnapshotError> {
        let bytes = std::fs::read(path).map_err(|e| SnapshotError::io(path, e))?;
        let head_end = bytes
            .iter()
            .position(|&b| b == b'\n')
            .unwrap_or(bytes.len());
        Ok(Self {
            path: path.display().to_string(),
            bytes,
            head_end,
        })
    }

    /// The header line, without its newline.
    pub(super) fn head(&self) -> &[u8] {
        &self.bytes[..self.head_end]
    }

    /// Everything after the header line.
    pub(super) fn body(&self) -> &[u8] {
        self.bytes.get(self.head_end + 1..).unwrap_or(&[])
    }

    /// The rows after the header, as CSV records.
    pub(super) fn records(&self) -> csv::StringRecordsIntoIter<&[u8]> {
        csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(self.body())
            .into_records()
    }

    /// [`SnapshotError::CaseFile`] at 1-based `line` of this file.
    pub(super) fn error(&self, line: usize, message: String) -> SnapshotError {
        SnapshotError::CaseFile {
            path: self.path.clone(),
            line,
            message,
        }
    }
}

/// Reads and validates the case file of `case` against the plan: header, one row per plan
/// pressure in order, the case's inputs and settings, booleans and numbers.
///
/// # Errors
/// [`SnapshotError::CaseFile`] naming the file, line and problem.
pub fn read_case_file(
    path: &Path,
    case: &PlannedCase,
    settings: &PlanSettings,
) -> Result<CaseFile, SnapshotError> {
    let file = CsvText::read(path)?;
    let bad = |line: usize, message: String| file.error(line, message);
    let effects: Vec<Effect> = effect_cells(case, settings)
        .into_iter()
        .map(|(e, _)| e)
        .collect();
    if file.head() != header_with(&effects).as_bytes() {
        let why = "header differs from this program's snapshot columns (written by another \
                   version?); delete the file to re-run the case";
        return Err(bad(1, why.into()));
    }
    let mut out = CaseFile {
        body: file.body().to_vec(),
        failed: false,
        unconverged_rows: 0,
        error: None,
    };
    let mut rows = 0;
    for (j, rec) in file.records().enumerate() {
        let rec = rec.map_err(|e| bad(j + 2, e.to_string()))?;
        let converged = check_row(&rec, j, case, settings).map_err(|m| bad(j + 2, m))?;
        out.unconverged_rows += usize::from(!converged);
        let error = &rec[BASE_COLUMNS - 1];
        if !error.is_empty() && out.error.is_none() {
            out.error = Some(error.to_string());
        }
        out.failed |= !error.is_empty();
        rows += 1;
    }
    let n = settings.pressures_bar.len();
    if rows != n {
        let why = format!("{rows} rows, expected one per plan pressure ({n})");
        return Err(bad(rows + 1, why));
    }
    Ok(out)
}

/// A shard directory bound to one plan.
#[derive(Debug, Clone)]
pub struct ShardDir {
    root: PathBuf,
}

impl ShardDir {
    /// Checks `root` for `plan` without writing anything: the directory if it holds this plan,
    /// `None` if it is not a snapshot directory yet (missing, or without a plan hash and case
    /// folder).
    ///
    /// # Errors
    /// [`SnapshotError::PlanMismatch`] if it holds another plan, [`SnapshotError::NotSnapshotDir`]
    /// if it has a case folder but no plan hash, I/O errors.
    pub fn existing(root: &Path, plan: &Plan) -> Result<Option<Self>, SnapshotError> {
        let dir = Self {
            root: root.to_path_buf(),
        };
        let hash = plan.hash();
        // the case folder is looked at before the hash: a shard creating the directory beside
        // this one writes the hash first, so a case folder seen here has its hash by the time
        // it is read (read the other way round, the hash could be missing and the folder,
        // created in between, present)
        let has_cases = dir.cases_dir().exists();
        match dir.recorded_hash()? {
            Some(found) if found == hash => Ok(Some(dir)),
            Some(found) => Err(SnapshotError::PlanMismatch {
                dir: root.display().to_string(),
                found,
                expected: hash,
            }),
            None if has_cases => Err(SnapshotError::NotSnapshotDir {
                dir: root.display().to_string(),
                reason: format!("it has a {CASES_DIR}/ folder but no {PLAN_HASH_FILE}"),
            }),
            None => Ok(None),
        }
    }

    /// Opens `root` for `plan`, creating it (with `plan.json` and `plan_hash`) if needed.
    ///
    /// # Errors
    /// See [`ShardDir::existing`]; I/O errors.
    pub fn create(root: &Path, plan: &Plan) -> Result<Self, SnapshotError> {
        let dir = match Self::existing(root, plan)? {
            Some(dir) => dir,
            None => {
                let dir = Self {
                    root: root.to_path_buf(),
                };
                std::fs::create_dir_all(root).map_err(|e| SnapshotError::io(root, e))?;
                let plan_file = root.join(PLAN_FILE);
                crate::io::write_atomic(&plan_file, plan.pretty_json().as_bytes())
                    .map_err(|e| SnapshotError::io(&plan_file, e))?;
                // the hash marker commits the directory to the plan; the case folder comes
                // after it (below), so that a shard starting beside this one never sees a case
                // folder without a hash (both write the same files, atomically)
                let hash_file = root.join(PLAN_HASH_FILE);
                let hash = format!("{}\n", plan.hash());
                crate::io::write_atomic(&hash_file, hash.as_bytes())
                    .map_err(|e| SnapshotError::io(&hash_file, e))?;
                dir
            }
        };
        let cases = dir.cases_dir();
        std::fs::create_dir_all(&cases).map_err(|e| SnapshotError::io(&cases, e))?;
        Ok(dir)
    }

    /// Opens an existing shard directory and its plan (for merging).
    ///
    /// # Errors
    /// [`SnapshotError::NotSnapshotDir`] without a plan hash, a plan copy that does not match
    /// the hash, or plan errors.
    pub fn open(root: &Path) -> Result<(Self, Plan), SnapshotError> {
        let dir = Self {
            root: root.to_path_buf(),
        };
        let not_dir = |reason: String| SnapshotError::NotSnapshotDir {
            dir: root.display().to_string(),
            reason,
        };
        let hash = dir
            .recorded_hash()?
            .ok_or_else(|| not_dir(format!("no {PLAN_HASH_FILE} file")))?;
        let plan = Plan::read(&root.join(PLAN_FILE))?;
        if plan.hash() != hash {
            return Err(not_dir(format!(
                "{PLAN_FILE} has hash {}, {PLAN_HASH_FILE} says {hash}",
                plan.hash()
            )));
        }
        Ok((dir, plan))
    }

    /// The directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    fn cases_dir(&self) -> PathBuf {
        self.root.join(CASES_DIR)
    }

    fn recorded_hash(&self) -> Result<Option<String>, SnapshotError> {
        let path = self.root.join(PLAN_HASH_FILE);
        match std::fs::read_to_string(&path) {
            Ok(s) => Ok(Some(s.trim().to_owned())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(SnapshotError::io(&path, e)),
        }
    }

    /// Path of the case file of case `id`.
    pub fn case_path(&self, id: usize) -> PathBuf {
        self.cases_dir().join(format!("{}.csv", case_name(id)))
    }

    /// Ids of the case files present (temporary files ignored).
    ///
    /// # Errors
    /// I/O errors; [`SnapshotError::NotSnapshotDir`] for a file in `cases/` that is neither a
    /// case file nor a temporary file.
    pub fn case_ids(&self) -> Result<BTreeMap<usize, PathBuf>, SnapshotError> {
        let dir = self.cases_dir();
        let mut ids = BTreeMap::new();
        for entry in std::fs::read_dir(&dir).map_err(|e| SnapshotError::io(&dir, e))? {
            let entry = entry.map_err(|e| SnapshotError::io(&dir, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') && name.ends_with(".tmp") {
                continue;
            }
            let id = name
                .strip_prefix("case_")
                .and_then(|s| s.strip_suffix(".csv"))
                .and_then(|s| s.parse::<usize>().ok())
                .filter(|&id| name == format!("{}.csv", case_name(id)));
            match id {
                Some(id) => {
                    ids.insert(id, entry.path());
                }
                None => {
                    return Err(SnapshotError::NotSnapshotDir {
                        dir: self.root.display().to_string(),
                        reason: format!("unexpected file {CASES_DIR}/{name}"),
                    })
                }
            }
        }
        Ok(ids)
    }

    /// Removes temporary files left by a killed writer of case `id`.
    ///
    /// # Errors
    /// I/O errors.
    pub fn remove_temporaries(&self, id: usize) -> Result<(), SnapshotError> {
        let dir = self.cases_dir();
        let prefix = format!(".{}.csv.", case_name(id));
        for entry in std::fs::read_dir(&dir).map_err(|e| SnapshotError::io(&dir, e))? {
            let entry = entry.map_err(|e| SnapshotError::io(&dir, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with(&prefix) && name.ends_with(".tmp") {
                let p = entry.path();
                std::fs::remove_file(&p).map_err(|e| SnapshotError::io(&p, e))?;
            }
        }
        Ok(())
    }

    /// Writes the case file of `case` atomically.
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_case(
        &self,
        case: &PlannedCase,
        settings: &PlanSettings,
        outcome: &CaseOutcome,
    ) -> Result<PathBuf, SnapshotError> {
        let path = self.case_path(case.id);
        crate::io::write_atomic(&path, &case_csv(case, settings, outcome))
            .map_err(|e| SnapshotError::io(&path, e))?;
        Ok(path)
    }
}
