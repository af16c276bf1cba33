//! `surrogate predict`: one query → JSON on stdout, or a CSV batch → CSV (`--out -`: stdout).
use std::fs::File;
use std::io::Write as _;

use anyhow::{bail, Context, Result};
use surrogate::rom::batch::{
    material_params, predict_table, read_queries, write_predictions, PredictionRecord,
};
use surrogate::rom::domain::BatchDomainReport;
use surrogate::rom::{Query, RomError, Surrogate};

use crate::args::PredictArgs;

/// The hint added to a refused extrapolation.
const ALLOW_HINT: &str = "give --allow-extrapolation to predict anyway (the output then says \
                          which inputs were outside and whether they were clamped)";

pub fn run(a: PredictArgs) -> Result<()> {
    crate::files::announce_default("model", &a.model, crate::files::DEFAULT_MODEL);
    let model = crate::files::load_model(&a.model)?;
    if a.validation {
        let mut text = model.validation.table();
        if let Some(c) = &model.training.correction {
            text.push_str(&format!(
                "\ntrained on a corrected set: {} high-fidelity cases ({}); discrepancy surrogate, held out (adds to the errors above):\n{}",
                c.matched_cases,
                c.high_source,
                c.validation.table()
            ));
            if let Some(e) = &c.end_to_end {
                text.push_str(&format!("\n{}", e.table()));
            }
        }
        writeln!(std::io::stdout(), "{text}")?;
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
    model.check_query(&q)?;
    let (q, snapped) = model.snap_to_domain(&q);
    for s in &snapped {
        eprintln!("note: {s}");
    }
    let outside = model
        .check_domain(&q, a.allow_extrapolation)
        .map_err(refused)?;
    for v in &outside {
        eprintln!("warning: {v}");
    }
    let mut pred = model.new_prediction();
    if a.std {
        model.predict_with_std_into(&q, &mut pred)?;
    } else {
        model.predict_into(&q, &mut pred)?;
    }
    let record = PredictionRecord::new(&q, &pred.values, a.std.then_some(&pred.std), &outside);
    writeln!(
        std::io::stdout(),
        "{}",
        serde_json::to_string_pretty(&record)?
    )?;
    Ok(())
}

/// A refused extrapolation gets the flag that allows it.
fn refused(e: RomError) -> anyhow::Error {
    match e {
        RomError::OutsideDomain(m) => anyhow::anyhow!("{m}; {ALLOW_HINT}"),
        e => e.into(),
    }
}

fn batch(
    model: &Surrogate,
    a: &PredictArgs,
    csv: &std::path::Path,
    out: &std::path::Path,
) -> Result<()> {
    let file = File::open(csv).with_context(|| format!("opening {}", csv.display()))?;
    let table = read_queries(file, &csv.display().to_string(), model)?;
    let predicted = predict_table(model, table, a.std, a.allow_extrapolation)
        .map_err(|e| refused(e).context(csv.display().to_string()))?;
    if predicted.domain.outside > 0 {
        eprintln!("warning: {}: {}", csv.display(), predicted.domain);
    }
    let snapped: Vec<_> = predicted
        .rows
        .iter()
        .filter(|r| !r.snapped.is_empty())
        .collect();
    for r in snapped.iter().take(BatchDomainReport::LISTED) {
        let notes: Vec<String> = r.snapped.iter().map(|s| s.to_string()).collect();
        eprintln!(
            "note: {} line {}: {}",
            csv.display(),
            r.row.line,
            notes.join("; ")
        );
    }
    if snapped.len() > BatchDomainReport::LISTED {
        eprintln!(
            "note: {} rows in all with an input moved onto an end of the domain",
            snapped.len()
        );
    }
    if out.as_os_str() == "-" {
        write_predictions(std::io::stdout().lock(), &predicted)?;
        return Ok(());
    }
    let mut buf = Vec::new();
    write_predictions(&mut buf, &predicted)?;
    crate::files::write_file(out, &buf)?;
    eprintln!(
        "wrote {} predictions to {}",
        predicted.rows.len(),
        out.display()
    );
    Ok(())
}
