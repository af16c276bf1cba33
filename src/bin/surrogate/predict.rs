//! `surrogate predict`: one query → JSON on stdout, or a CSV batch → CSV (`--out -`: stdout).
//! Beside the prediction, the model-form error when the model carries one (labelled, in the
//! JSON and the CSV, and a line on stderr), and `--std` labelled as the surrogate vs FE.
use std::fs::File;
use std::io::Write as _;

use anyhow::{bail, Context, Result};
use surrogate::case::{BatchDomainReport, Query};
use surrogate::rom::batch::{
    material_params, predict_table, read_queries, write_predictions, PredictionRecord,
};
use surrogate::rom::{model_form, RomError, Surrogate};

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
        if let Some(h) = &model.validation.held_out_n {
            text.push_str(&format!(
                "\nN {}; numbers of bellows held out of a second training:\n{}",
                model.training.n_treatment,
                h.table()
            ));
        }
        match model.model_form() {
            Some(m) => text.push_str(&format!("\n{}", m.table())),
            None => text.push_str(&format!("\n{}\n", no_model_form())),
        }
        writeln!(std::io::stdout(), "{text}")?;
    }
    if let Some(data) = &a.check {
        return check(&model, data, a.check_json.as_deref());
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
    let record = PredictionRecord::new(&q, &pred.values, a.std.then_some(&pred.std), &outside)
        .with_model_form(&model, &q);
    eprintln!("{}", model_form_line(&model, &q));
    writeln!(
        std::io::stdout(),
        "{}",
        serde_json::to_string_pretty(&record)?
    )?;
    Ok(())
}

/// What a model without a model-form error says about it.
fn no_model_form() -> String {
    format!(
        "note: the model file carries no {}: how far the model misses real actuators is not \
         known here (--std is the {} only); `surrogate model-form` attaches one",
        model_form::LABEL,
        model_form::STD_LABEL
    )
}

/// The model-form error of a prediction in one line, labelled, beside what `--std` is.
fn model_form_line(model: &Surrogate, q: &Query) -> String {
    let Some(m) = model.model_form() else {
        return no_model_form();
    };
    let e = m.at(q.p_bar);
    let parts: Vec<String> = [
        ("tip Uz", e.tip_uz_mm(), "mm"),
        ("tip Uy", e.tip_uy_mm(), "mm"),
        ("angle", e.angle_deg(), "deg"),
        ("force", e.force_n(), "N"),
    ]
    .iter()
    .filter_map(|(name, v, unit)| v.map(|v| format!("{name} ±{v:.3} {unit}")))
    .collect();
    format!(
        "{} at {} bar (rms, from {}): {}; --std is the {} only",
        model_form::LABEL,
        q.p_bar,
        m.calibration.report,
        parts.join(", "),
        model_form::STD_LABEL
    )
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
    if model.model_form().is_none() {
        eprintln!("{}", no_model_form());
    }
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

/// `--check`: the model against the FE cases of a snapshot CSV it never saw.
fn check(model: &Surrogate, data: &std::path::Path, json: Option<&std::path::Path>) -> Result<()> {
    let set = surrogate::rom::SnapshotSet::read(data)
        .with_context(|| format!("--check {}", data.display()))?;
    let cases = set
        .into_cases()
        .with_context(|| format!("--check {}", data.display()))?;
    let report = surrogate::rom::unseen::check(model, &cases)?;
    writeln!(
        std::io::stdout(),
        "{} cases of {} against the model:\n{}",
        report.cases.len(),
        data.display(),
        report.table()
    )?;
    if let Some(out) = json {
        let text = serde_json::to_string_pretty(&report)?;
        surrogate::io::write_atomic(out, text.as_bytes())
            .with_context(|| format!("--check-json {}", out.display()))?;
    }
    Ok(())
}
