//! `surrogate predict`: one query → JSON on stdout, or a CSV batch → CSV.
use std::fs::File;
use std::io::Write as _;

use anyhow::{bail, Context, Result};
use serde_json::{json, Value};
use surrogate::rom::batch::{material_params, read_queries, write_predictions};
use surrogate::rom::{Prediction, Query, Surrogate};

use crate::args::PredictArgs;

pub fn run(a: PredictArgs) -> Result<()> {
    let model = Surrogate::load(&a.model)?;
    if a.validation {
        eprintln!("{}", model.validation.table());
        if let Some(c) = &model.training.correction {
            eprintln!(
                "trained on a corrected set: {} high-fidelity cases ({}); discrepancy surrogate, held out (adds to the errors above):\n{}",
                c.matched_cases,
                c.high_source,
                c.validation.table()
            );
            if let Some(e) = &c.end_to_end {
                eprintln!("{}", e.table());
            }
        }
    }
    if let (Some(csv), Some(out)) = (&a.csv, &a.out) {
        return batch(&model, &a, csv, out);
    }
    if let (Some(mesh), Some(out)) = (&a.bench_fe, &a.bench_out) {
        return crate::speedup::run(&model, &a, mesh, out);
    }
    let (Some(n), Some(t), Some(p), Some(mat)) = (a.n, a.t, a.pressure, a.material.as_deref())
    else {
        if a.validation {
            return Ok(());
        }
        bail!("give --n, --t, --pressure and --material, or --csv and --out");
    };
    let m = material_params(mat)?;
    let q = Query::new(n, t, p, m);
    let warnings = domain_check(&model, &q, a.strict, "query")?;
    let mut pred = model.new_prediction();
    if a.std {
        model.predict_with_std_into(&q, &mut pred)?;
    } else {
        model.predict_into(&q, &mut pred)?;
    }
    let mut out = outputs_json(&pred.values);
    if a.std {
        out["std"] = outputs_json(&pred.std);
    }
    out["in_domain"] = json!(warnings.is_empty());
    if !warnings.is_empty() {
        out["warnings"] = json!(warnings);
    }
    writeln!(std::io::stdout(), "{}", serde_json::to_string_pretty(&out)?)?;
    Ok(())
}

fn outputs_json(v: &[f64; 22]) -> Value {
    let markers: Vec<Value> = (0..9)
        .map(|k| json!({"uz_mm": v[2 * k], "uy_mm": v[2 * k + 1]}))
        .collect();
    json!({"tip_uz_mm": v[18], "tip_uy_mm": v[19], "angle_deg": v[20], "force_n": v[21], "markers": markers})
}

/// Warnings for inputs outside the training domain (an error with `--strict`).
fn domain_check(model: &Surrogate, q: &Query, strict: bool, what: &str) -> Result<Vec<String>> {
    let v: Vec<String> = model
        .domain_violations(q)
        .iter()
        .map(|d| d.to_string())
        .collect();
    if !v.is_empty() {
        if strict {
            bail!("{what}: {} (--strict)", v.join("; "));
        }
        for w in &v {
            eprintln!("warning: {what}: {w}");
        }
    }
    Ok(v)
}

fn batch(
    model: &Surrogate,
    a: &PredictArgs,
    csv: &std::path::Path,
    out: &std::path::Path,
) -> Result<()> {
    let file = File::open(csv).with_context(|| format!("opening {}", csv.display()))?;
    let rows = read_queries(file, &csv.display().to_string(), model)?;
    let mut results: Vec<(_, Prediction, bool)> = Vec::with_capacity(rows.len());
    let mut pred = model.new_prediction();
    for row in rows {
        let warnings = domain_check(
            model,
            &row.query,
            a.strict,
            &format!("{} line {}", csv.display(), row.line),
        )?;
        if a.std {
            model.predict_with_std_into(&row.query, &mut pred)?;
        } else {
            model.predict_into(&row.query, &mut pred)?;
        }
        results.push((row, pred.clone(), warnings.is_empty()));
    }
    let file = File::create(out).with_context(|| format!("creating {}", out.display()))?;
    write_predictions(file, &results, a.std)?;
    eprintln!("{} predictions -> {}", results.len(), out.display());
    Ok(())
}
