//! Batch queries: material specs and query CSV files for `surrogate predict --csv`.
//!
//! A query CSV has the columns `n_bellows, wall_thickness_mm, pressure_bar` and either
//! `material` (a name or `mu1,alpha1,mu2,alpha2` in quotes) or the four
//! `mu1_mpa, alpha1, mu2_mpa, alpha2`, in any order. A missing or unknown column, an empty or
//! non-finite cell, an unknown material or an `N` the model was not trained on is an error
//! naming the line and the column.

use std::io::{Read, Write};

use super::surrogate::{Prediction, Query, Surrogate};
use super::{RomError, QUANTITY_NAMES};
use crate::fe::material::Material;

/// Ogden parameters `[μ₁, α₁, μ₂, α₂]` of a material spec (a literature name or four numbers
/// `mu1,alpha1,mu2,alpha2`), parsed and checked by [`Material::from_spec`].
///
/// # Errors
/// Unknown name, malformed numbers, an inadmissible set, or a non-Ogden law (the surrogate is
/// parametrised by the Ogden constants).
pub fn material_params(spec: &str) -> Result<[f64; 4], RomError> {
    let material = Material::from_spec(spec.trim(), 1000.0)
        .map_err(|e| RomError::invalid("material", spec, &e.to_string()))?;
    material.ogden_params().ok_or_else(|| {
        RomError::invalid(
            "material",
            spec,
            "an Ogden material: the surrogate is parametrised by Ogden (μ₁, α₁, μ₂, α₂)",
        )
    })
}

/// One validated query row with its line number.
#[derive(Debug, Clone)]
pub struct QueryRow {
    /// 1-based line in the file.
    pub line: usize,
    /// The query.
    pub query: Query,
}

const BASE: [&str; 3] = ["n_bellows", "wall_thickness_mm", "pressure_bar"];
const OGDEN: [&str; 4] = ["mu1_mpa", "alpha1", "mu2_mpa", "alpha2"];

/// Reads and validates a query CSV against a model.
///
/// # Errors
/// Missing/unknown columns, bad cells, unknown materials, untrained `N`, each naming line and column.
pub fn read_queries<R: Read>(
    reader: R,
    source: &str,
    model: &Surrogate,
) -> Result<Vec<QueryRow>, RomError> {
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
    let has_material = header.iter().any(|h| h == "material");
    let mut wanted: Vec<&str> = BASE.to_vec();
    if has_material {
        wanted.push("material");
    } else {
        wanted.extend(OGDEN);
    }
    for h in &header {
        if !wanted.contains(&h.as_str()) {
            return Err(header_err(format!(
                "unknown column `{h}`: expected exactly {}",
                wanted.join(", ")
            )));
        }
    }
    let mut col = Vec::new();
    let hint = if has_material {
        ""
    } else {
        " (or a `material` column instead of the four Ogden columns)"
    };
    for w in &wanted {
        col.push(header.iter().position(|h| h == w).ok_or_else(|| {
            header_err(format!(
                "missing column `{w}`: expected {}{hint}",
                wanted.join(", ")
            ))
        })?);
    }
    let mut rows = Vec::new();
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(csv_err)?;
        let line = rec.position().map(|p| p.line() as usize).unwrap_or(i + 2);
        let cell_err = |c: usize, value: &str, expected: &str| RomError::Cell {
            source_name: source.into(),
            line,
            column: wanted[c].to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        };
        let text = |c: usize| rec.get(col[c]).unwrap_or("");
        if rec.len() > header.len() {
            return Err(RomError::Cell {
                source_name: source.into(),
                line,
                column: format!("#{}", header.len() + 1),
                value: rec.get(header.len()).unwrap_or("").to_string(),
                expected: format!("no cell beyond the {} header columns", header.len()),
            });
        }
        let num = |c: usize| -> Result<f64, RomError> {
            match text(c).parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(cell_err(c, text(c), "a finite number")),
            }
        };
        let n = match text(0).parse::<u32>() {
            Ok(n) if model.n_allowed.contains(&n) => n,
            Ok(_) => {
                return Err(cell_err(
                    0,
                    text(0),
                    &format!("a trained number of bellows {:?}", model.n_allowed),
                ))
            }
            Err(_) => return Err(cell_err(0, text(0), "a positive integer")),
        };
        let m = if has_material {
            material_params(text(3)).map_err(|e| cell_err(3, text(3), &e.to_string()))?
        } else {
            [num(3)?, num(4)?, num(5)?, num(6)?]
        };
        let query = Query {
            n,
            t_mm: num(1)?,
            p_bar: num(2)?,
            mu1: m[0],
            alpha1: m[1],
            mu2: m[2],
            alpha2: m[3],
        };
        model
            .check_query(&query)
            .map_err(|e| cell_err(3, text(3), &e.to_string()))?;
        rows.push(QueryRow { line, query });
    }
    Ok(rows)
}

/// Writes predictions as CSV: inputs, the 22 outputs, their standard deviations when
/// available, and `in_domain`.
///
/// # Errors
/// Write failures.
pub fn write_predictions<W: Write>(
    out: W,
    rows: &[(QueryRow, Prediction, bool)],
    with_std: bool,
) -> Result<(), RomError> {
    let io = |source| RomError::Io {
        path: "<output>".into(),
        source,
    };
    let mut w = std::io::BufWriter::new(out);
    let mut header: Vec<String> = [
        "n_bellows",
        "wall_thickness_mm",
        "pressure_bar",
        "mu1_mpa",
        "alpha1",
        "mu2_mpa",
        "alpha2",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    header.extend(QUANTITY_NAMES.iter().map(|s| s.to_string()));
    if with_std {
        header.extend(QUANTITY_NAMES.iter().map(|s| format!("{s}_std")));
    }
    header.push("in_domain".into());
    writeln!(w, "{}", header.join(",")).map_err(io)?;
    for (row, pred, in_domain) in rows {
        let q = &row.query;
        let mut cells: Vec<String> = vec![q.n.to_string()];
        cells.extend(
            [q.t_mm, q.p_bar, q.mu1, q.alpha1, q.mu2, q.alpha2]
                .iter()
                .map(|v| v.to_string()),
        );
        cells.extend(pred.values.iter().map(|v| v.to_string()));
        if with_std {
            cells.extend(pred.std.iter().map(|v| v.to_string()));
        }
        cells.push(in_domain.to_string());
        writeln!(w, "{}", cells.join(",")).map_err(io)?;
    }
    w.flush().map_err(io)
}
