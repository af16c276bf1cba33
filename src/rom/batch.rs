//! Batch queries and the prediction output schema, for `surrogate predict` and for programs.
//! The columns, their units and meanings: [`crate::schema`] (formats `query`, `prediction`).
//!
//! A query CSV has the columns `n_bellows, wall_thickness_mm, pressure_bar` and either
//! `material` (a name, `mu1,alpha1,mu2,alpha2` in quotes, or a calibration report
//! `DIR/report.json`: [`super::material_spec`]) or the four
//! `mu1_mpa, alpha1, mu2_mpa, alpha2`, in any order. Any other column (an ID, a note) is
//! passed through to the output unchanged. `n_bellows` accepts `9` and `9.0`. A missing
//! column, an empty or non-finite cell, an unknown material or an `N` the model was not trained
//! on is an error naming the line and the column.
//!
//! Every row is checked against the training domain ([`Surrogate::domain_violations`]): by
//! default a batch with rows outside is refused with one message (how many rows, the first
//! few); allowed, each output row says which inputs were outside and whether they were
//! clamped (`in_domain`, `outside_domain`).
//!
//! A prediction is written in the same form as a step of `surrogate simulate`
//! ([`PredictionRecord`]): `pressure_bar, tip_uz_mm, tip_uy_mm, angle_deg, force_n` and
//! `markers` as `[{"uz_mm", "uy_mm"}, …]` ([`Marker`]).
//!
//! Two errors come with it, each labelled: the surrogate's standard deviation (asked for,
//! `std`: the surrogate against the FE model) and, when the model file carries one, the
//! model-form error ([`super::model_form`]: the calibrated model against the recordings),
//! always.

use std::io::{Read, Write};

use serde::Serialize;

use super::model_form::ModelFormEstimate;
use super::surrogate::Surrogate;
use super::{RomError, QUANTITY_NAMES};
use crate::case::{BatchDomainReport, BoundSnap, DomainViolation, OgdenSet, Query};
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::simulate::Marker;
use crate::schema;

/// The Ogden set of a material spec (a literature name, four numbers
/// `mu1,alpha1,mu2,alpha2`, or a calibration report file `DIR/report.json`:
/// [`super::material_spec`]), parsed and checked by [`Material::from_spec`].
///
/// # Errors
/// Unknown name, malformed numbers, an unreadable report, an inadmissible set, or a
/// non-Ogden law (the surrogate is parametrised by the Ogden constants).
pub fn material_params(spec: &str) -> Result<OgdenSet, RomError> {
    let expanded = super::material_spec::expand(spec)?;
    let material = Material::from_spec(expanded.trim(), DEFAULT_BULK_RATIO)
        .map_err(|e| RomError::invalid(MATERIAL, spec, &e.expected()))?;
    material.ogden_set().ok_or_else(|| {
        RomError::invalid(
            MATERIAL,
            spec,
            "an Ogden material: the surrogate is parametrised by Ogden (μ₁, α₁, μ₂, α₂)",
        )
    })
}

/// One validated query row with its line number and its passed-through cells.
#[derive(Debug, Clone)]
pub struct QueryRow {
    /// 1-based line in the file.
    pub line: usize,
    /// The query.
    pub query: Query,
    /// The cells of [`QueryTable::extra_columns`], as given.
    pub extra: Vec<String>,
}

/// A validated query CSV.
#[derive(Debug, Clone, Default)]
pub struct QueryTable {
    /// Columns that are not inputs (IDs, notes, the `material` spec), passed through.
    pub extra_columns: Vec<String>,
    /// The rows.
    pub rows: Vec<QueryRow>,
}

const BASE: [&str; 3] = schema::names(&schema::QUERY_COLUMNS);
const OGDEN: [&str; 4] = schema::names(&schema::OGDEN_COLUMNS);
/// The input columns of the output CSV.
const INPUT_COLUMNS: [&str; 7] = schema::names(&schema::PREDICTION_INPUT_COLUMNS);
const MATERIAL: &str = schema::MATERIAL.name;

/// Whether a column name is one the output CSV writes itself (so it cannot be passed through).
fn is_output_column(name: &str) -> bool {
    INPUT_COLUMNS.contains(&name)
        || QUANTITY_NAMES.contains(&name)
        || QUANTITY_NAMES.iter().any(|q| {
            name == format!("{q}{}", schema::STD_SUFFIX)
                || name == format!("{q}{}", schema::MODEL_FORM_SUFFIX)
        })
        || name == schema::IN_DOMAIN.name
        || name == schema::OUTSIDE_DOMAIN.name
}

/// Reads and validates a query CSV against a model.
///
/// # Errors
/// Missing columns, a passed-through column that the output would overwrite, bad cells,
/// unknown materials, untrained `N`, each naming line and column.
pub fn read_queries<R: Read>(
    reader: R,
    source: &str,
    model: &Surrogate,
) -> Result<QueryTable, RomError> {
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(reader);
    let csv_err = |e: csv::Error| RomError::Csv {
        source_name: source.into(),
        message: e.to_string(),
    };
    let header: Vec<String> = rdr
        .headers()
        .map_err(csv_err)?
        .iter()
        .map(str::to_string)
        .collect();
    let header_err = |message: String| RomError::Header {
        source_name: source.into(),
        message,
    };
    let has_material = header.iter().any(|h| h == MATERIAL);
    let mut wanted: Vec<&str> = BASE.to_vec();
    if has_material {
        wanted.push(MATERIAL);
    } else {
        wanted.extend(OGDEN);
    }
    let hint = if has_material {
        ""
    } else {
        " (or a `material` column instead of the four Ogden columns)"
    };
    let mut col = Vec::new();
    for w in &wanted {
        col.push(header.iter().position(|h| h == w).ok_or_else(|| {
            header_err(format!(
                "missing column `{w}`: expected {}{hint}",
                wanted.join(", ")
            ))
        })?);
    }
    // every other column is passed through; `material` is kept as well (the spec as given)
    let mut extra_idx = Vec::new();
    for (i, h) in header.iter().enumerate() {
        if h == MATERIAL || !wanted.contains(&h.as_str()) {
            if h != MATERIAL && is_output_column(h) {
                return Err(header_err(format!(
                    "column `{h}` would be overwritten by the prediction: rename it to pass it through"
                )));
            }
            if header[..i].contains(h) {
                return Err(header_err(format!("column `{h}` appears twice")));
            }
            extra_idx.push(i);
        }
    }
    let mut rows = Vec::new();
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(csv_err)?;
        let line = rec.position().map(|p| p.line() as usize).unwrap_or(i + 2);
        if rec.len() > header.len() {
            return Err(RomError::Cell {
                source_name: source.into(),
                line,
                column: format!("#{}", header.len() + 1),
                value: rec.get(header.len()).unwrap_or("").to_string(),
                expected: format!("no cell beyond the {} header columns", header.len()),
            });
        }
        let query = parse_query(&rec, &col, &wanted, has_material, source, line, model)?;
        let extra = extra_idx
            .iter()
            .map(|&c| rec.get(c).unwrap_or("").to_string())
            .collect();
        rows.push(QueryRow { line, query, extra });
    }
    Ok(QueryTable {
        extra_columns: extra_idx.iter().map(|&c| header[c].clone()).collect(),
        rows,
    })
}

fn parse_query(
    rec: &csv::StringRecord,
    col: &[usize],
    wanted: &[&str],
    has_material: bool,
    source: &str,
    line: usize,
    model: &Surrogate,
) -> Result<Query, RomError> {
    let text = |c: usize| rec.get(col[c]).unwrap_or("");
    let cell_err = |c: usize, expected: &str| RomError::Cell {
        source_name: source.into(),
        line,
        column: wanted[c].to_string(),
        value: text(c).to_string(),
        expected: expected.to_string(),
    };
    let num = |c: usize| -> Result<f64, RomError> {
        match text(c).parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(cell_err(c, "a finite number")),
        }
    };
    let n = match super::data::parse_count(text(0)) {
        Some(n) if model.n_allowed.contains(&n) => n,
        Some(_) => {
            return Err(cell_err(
                0,
                &format!(
                    "a number of bellows the model predicts {:?} ({})",
                    model.n_allowed,
                    super::surrogate::N_NOT_EXTRAPOLATED
                ),
            ))
        }
        None => return Err(cell_err(0, "a positive integer (9 or 9.0)")),
    };
    let m = if has_material {
        material_params(text(3)).map_err(|e| cell_err(3, &e.to_string()))?
    } else {
        OgdenSet::from_array([num(3)?, num(4)?, num(5)?, num(6)?])
    };
    let query = Query::new(n, num(1)?, num(2)?, m);
    model
        .check_query(&query)
        .map_err(|e| cell_err(3, &e.to_string()))?;
    Ok(query)
}

/// The 22 outputs in the JSON schema shared with `surrogate simulate`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputRecord {
    /// Tip `Uz = −Δz`, mm.
    pub tip_uz_mm: f64,
    /// Tip `Uy = Δy`, mm.
    pub tip_uy_mm: f64,
    /// Bending angle, degrees.
    pub angle_deg: f64,
    /// Blocked force, N.
    pub force_n: f64,
    /// Markers 1..9.
    pub markers: Vec<Marker>,
}

impl OutputRecord {
    /// From the 22 values in [`QUANTITY_NAMES`] order.
    pub fn from_values(v: &[f64; 22]) -> Self {
        OutputRecord {
            tip_uz_mm: v[super::Q_TIP_UZ],
            tip_uy_mm: v[super::Q_TIP_UY],
            angle_deg: v[super::Q_ANGLE],
            force_n: v[super::Q_FORCE],
            markers: (0..9)
                .map(|k| Marker::from([v[2 * k], v[2 * k + 1]]))
                .collect(),
        }
    }
}

/// An input outside the training domain, as written in a prediction record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutsideInput {
    /// Input name.
    pub input: String,
    /// Value given.
    pub value: f64,
    /// Training range.
    pub min: f64,
    /// Training range.
    pub max: f64,
    /// Whether the prediction holds the value at the nearer end instead of extrapolating.
    pub clamped: bool,
    /// The value the prediction is evaluated at.
    pub used: f64,
}

impl From<&DomainViolation> for OutsideInput {
    fn from(v: &DomainViolation) -> Self {
        OutsideInput {
            input: v.name.clone(),
            value: v.value,
            min: v.min,
            max: v.max,
            clamped: v.clamped,
            used: v.used(),
        }
    }
}

/// The model-form error of a prediction as JSON ([`super::model_form`]), labelled.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelFormRecord {
    /// What it is: [`super::model_form::LABEL`].
    pub what: &'static str,
    /// The calibration report it was learned from.
    pub calibration: String,
    /// Tip Uz, mm (`null`: not recorded in the calibration).
    pub tip_uz_mm: Option<f64>,
    /// Tip Uy, mm.
    pub tip_uy_mm: Option<f64>,
    /// Bending angle, degrees.
    pub angle_deg: Option<f64>,
    /// Blocked force, N.
    pub force_n: Option<f64>,
}

impl ModelFormRecord {
    /// The record of `model`'s model-form error at `q`'s pressure; `None` when it has none.
    pub fn of(model: &Surrogate, q: &Query) -> Option<Self> {
        let m = model.model_form()?;
        let e = m.at(q.p_bar);
        Some(ModelFormRecord {
            what: super::model_form::LABEL,
            calibration: m.calibration.report.clone(),
            tip_uz_mm: e.tip_uz_mm(),
            tip_uy_mm: e.tip_uy_mm(),
            angle_deg: e.angle_deg(),
            force_n: e.force_n(),
        })
    }
}

/// One prediction as JSON: the pressure as given, the outputs (the form of a `simulate` step),
/// their standard deviations if asked for, the model-form error when the model carries one,
/// and the domain flags.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictionRecord {
    /// Pressure as given, bar.
    pub pressure_bar: f64,
    /// The outputs.
    #[serde(flatten)]
    pub outputs: OutputRecord,
    /// Standard deviations of the outputs: the surrogate against the FE model only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std: Option<OutputRecord>,
    /// What `std` is ([`super::model_form::STD_LABEL`]), when present.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_is: Option<&'static str>,
    /// The model-form error at this pressure ([`PredictionRecord::with_model_form`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_form_error: Option<ModelFormRecord>,
    /// Whether every input lies in the training domain.
    pub in_domain: bool,
    /// The inputs outside it (empty when in the domain).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub outside_domain: Vec<OutsideInput>,
}

impl PredictionRecord {
    /// The record of a prediction of `q` (`std` when computed) with its domain violations.
    pub fn new(
        q: &Query,
        values: &[f64; 22],
        std: Option<&[f64; 22]>,
        outside: &[DomainViolation],
    ) -> Self {
        PredictionRecord {
            pressure_bar: q.p_bar,
            outputs: OutputRecord::from_values(values),
            std: std.map(OutputRecord::from_values),
            std_is: std.map(|_| super::model_form::STD_LABEL),
            model_form_error: None,
            in_domain: outside.is_empty(),
            outside_domain: outside.iter().map(OutsideInput::from).collect(),
        }
    }

    /// The record with `model`'s model-form error at its pressure (none when the model
    /// carries none).
    pub fn with_model_form(mut self, model: &Surrogate, q: &Query) -> Self {
        self.model_form_error = ModelFormRecord::of(model, q);
        self
    }
}

/// One predicted row of a batch.
#[derive(Debug, Clone)]
pub struct PredictedRow {
    /// The query row.
    pub row: QueryRow,
    /// The 22 outputs.
    pub values: [f64; 22],
    /// Their standard deviations, when asked for.
    pub std: Option<[f64; 22]>,
    /// The inputs outside the training domain.
    pub outside: Vec<DomainViolation>,
    /// The inputs beyond an end of the domain within the tolerance, predicted at the end
    /// ([`Surrogate::snap_to_domain`]; the row's query holds the moved values).
    pub snapped: Vec<BoundSnap>,
    /// The model-form error at the row's pressure, when the model carries one.
    pub model_form: Option<ModelFormEstimate>,
}

/// A predicted batch.
#[derive(Debug, Clone, Default)]
pub struct PredictedTable {
    /// Passed-through columns.
    pub extra_columns: Vec<String>,
    /// The rows.
    pub rows: Vec<PredictedRow>,
    /// The domain summary of the batch.
    pub domain: BatchDomainReport,
    /// The outputs (indices among the 22) the model's model-form error covers: a
    /// [`schema::MODEL_FORM_SUFFIX`] column each.
    pub model_form_outputs: Vec<usize>,
}

/// Predicts every row of a query table. The domain is checked for every row first: with rows
/// outside and `allow_extrapolation` false, nothing is predicted and the error carries one
/// summary of the batch (count and the first rows). An input beyond an end of the domain by
/// at most the tolerance ([`crate::case::BOUND_TOLERANCE`]) is moved onto it and predicted
/// there ([`PredictedRow::snapped`]).
///
/// # Errors
/// [`RomError::OutsideDomain`]; an invalid query.
pub fn predict_table(
    model: &Surrogate,
    table: QueryTable,
    with_std: bool,
    allow_extrapolation: bool,
) -> Result<PredictedTable, RomError> {
    let domain = model.domain();
    let mut report = BatchDomainReport::default();
    let outside: Vec<Vec<DomainViolation>> = table
        .rows
        .iter()
        .map(|r| {
            let v = domain.violations(&r.query);
            report.record(|| format!("line {}", r.line), &v);
            v
        })
        .collect();
    if report.outside > 0 && !allow_extrapolation {
        return Err(RomError::OutsideDomain(report.to_string()));
    }
    let mut pred = model.new_prediction();
    let mut rows = Vec::with_capacity(table.rows.len());
    for (mut row, outside) in table.rows.into_iter().zip(outside) {
        let (query, snapped) = domain.snap(&row.query);
        row.query = query;
        if with_std {
            model.predict_with_std_into(&row.query, &mut pred)?;
        } else {
            model.predict_into(&row.query, &mut pred)?;
        }
        let model_form = model.model_form_error(&row.query);
        rows.push(PredictedRow {
            row,
            values: pred.values,
            std: with_std.then_some(pred.std),
            outside,
            snapped,
            model_form,
        });
    }
    let model_form_outputs = model.model_form().map_or_else(Vec::new, |m| {
        (0..QUANTITY_NAMES.len())
            .filter(|&q| m.error(q, 0.0).is_some())
            .collect()
    });
    Ok(PredictedTable {
        extra_columns: table.extra_columns,
        rows,
        domain: report,
        model_form_outputs,
    })
}

/// Writes a predicted batch as CSV: the passed-through columns, the inputs, the 22 outputs,
/// their standard deviations when computed (`_std`: the surrogate against the FE model), the
/// model-form error of each output it covers (`_model_form`), `in_domain` and
/// `outside_domain` (the inputs outside, `;`-separated, each `name=value (clamped to x)` or
/// `name=value (extrapolated)`).
///
/// # Errors
/// Write failures.
pub fn write_predictions<W: Write>(out: W, table: &PredictedTable) -> Result<(), RomError> {
    let err = |e: csv::Error| RomError::Csv {
        source_name: "<output>".into(),
        message: e.to_string(),
    };
    let with_std = table.rows.first().is_some_and(|r| r.std.is_some());
    let mut w = csv::Writer::from_writer(out);
    let mut header: Vec<String> = table.extra_columns.clone();
    header.extend(INPUT_COLUMNS.iter().map(|s| s.to_string()));
    header.extend(QUANTITY_NAMES.iter().map(|s| s.to_string()));
    if with_std {
        header.extend(
            QUANTITY_NAMES
                .iter()
                .map(|s| format!("{s}{}", schema::STD_SUFFIX)),
        );
    }
    header.extend(
        table
            .model_form_outputs
            .iter()
            .map(|&q| format!("{}{}", QUANTITY_NAMES[q], schema::MODEL_FORM_SUFFIX)),
    );
    header.push(schema::IN_DOMAIN.name.into());
    header.push(schema::OUTSIDE_DOMAIN.name.into());
    w.write_record(&header).map_err(err)?;
    for r in &table.rows {
        let q = &r.row.query;
        let mut cells: Vec<String> = r.row.extra.clone();
        cells.push(q.n.to_string());
        cells.extend(
            [
                q.t_mm,
                q.p_bar,
                q.material.mu1_mpa,
                q.material.alpha1,
                q.material.mu2_mpa,
                q.material.alpha2,
            ]
            .iter()
            .map(|v| v.to_string()),
        );
        cells.extend(r.values.iter().map(|v| v.to_string()));
        if let Some(std) = &r.std {
            cells.extend(std.iter().map(|v| v.to_string()));
        }
        cells.extend(table.model_form_outputs.iter().map(|&q| {
            r.model_form
                .and_then(|m| m.values[q])
                .map_or_else(String::new, |v| v.to_string())
        }));
        cells.push(r.outside.is_empty().to_string());
        let outside: Vec<String> = r.outside.iter().map(DomainViolation::short).collect();
        cells.push(outside.join("; "));
        w.write_record(&cells).map_err(err)?;
    }
    w.flush().map_err(|source| RomError::Io {
        path: "<output>".into(),
        source,
    })
}
