//! The study's results in Markdown: the header, the targets, the confusion matrix, every
//! twin.

use std::fmt::Write;

use super::plan::StudyPlan;
use super::results::{StudyResults, StudySummary};

/// The results in Markdown: the targets, the confusion matrix, every twin.
pub fn study_markdown(plan: &StudyPlan, r: &StudyResults) -> String {
    let mut o = String::new();
    header(&mut o, plan, r);
    targets(&mut o, r);
    confusion(&mut o, &r.summary);
    every_twin(&mut o, r);
    o
}

/// `a of b (p %)`, or a dash when `b` is 0.
fn pct(a: usize, b: usize) -> String {
    if b == 0 {
        "—".to_string()
    } else {
        format!("{a} of {b} ({:.0} %)", 100.0 * a as f64 / b as f64)
    }
}

/// The title, what was diagnosed and how (mesh, seeds, markers, the model's own errors).
fn header(o: &mut String, plan: &StudyPlan, r: &StudyResults) {
    let s = &r.summary;
    let _ = writeln!(o, "# Blind twin study: results\n");
    let _ = writeln!(
        o,
        "{} twins diagnosed ({} effect, {} null), {} pending. Twins on {} elements{}; seeds {:?}; markers {}.\n",
        r.twins.len(),
        s.effect_twins,
        s.nulls,
        r.pending.len(),
        plan.mesh.element_size.map_or(plan.mesh.level.name().to_string(), |h| format!("{h} mm")),
        plan.mesh.wall_elements.map_or(String::new(), |k| format!(", {k} through a wall")),
        plan.seeds,
        if r.markers { "used" } else { "left out (as the shipped experiments have none)" }
    );
    let _ = writeln!(
        o,
        "{}\n",
        match &r.mesh_reference {
            Some(m) => format!(
                "The diagnosing model's mesh error is projected out: its direction is the difference \
                 to `{m}` at the calibrated material (`diagnose::mesh_error`)."
            ),
            None => "The diagnosing model's mesh error is not tested as a direction.".to_string(),
        }
    );
    let _ = writeln!(
        o,
        "{}\n",
        match &r.approximation_error {
            Some(a) => format!(
                "Approximation error (`diagnose::approx_error`): {a}. The recordings are \
                 corrected by its mean; the Name stage weighs the residual by its covariance."
            ),
            None => "No approximation error: the recordings' σ alone weigh the residual.".into(),
        }
    );
}

/// The targets' table and what "indistinguishable" counts.
fn targets(o: &mut String, r: &StudyResults) {
    let s = &r.summary;
    let _ = writeln!(o, "| target | result |\n|---|---|");
    let rows = [
        (
            "concealed effect ranked first, twins whose effect moves the tip > 2σ (≥ 90 %)",
            (s.visible_first, s.visible),
        ),
        (
            "… first or reported indistinguishable from the first",
            (s.visible_first_or_indistinguishable, s.visible),
        ),
        ("… named by the verdict", (s.visible_named, s.visible)),
        (
            "concealed effect ranked first, every effect twin",
            (s.effect_first, s.effect_twins),
        ),
        (
            "false alarms on null twins (≤ 10 %)",
            (s.false_alarms, s.nulls),
        ),
        (
            "recovered size within 25 % or interval covering the truth (correctly named)",
            s.sizes_recovered,
        ),
        (
            "held-out tip BE with the named effect ≤ 1.2 × noise (correctly named)",
            s.held_out_within,
        ),
    ];
    for (what, (a, b)) in rows {
        let _ = writeln!(o, "| {what} | {} |", pct(a, b));
    }
    if r.mesh_reference.is_some() {
        let _ = writeln!(
            o,
            "| the model's own mesh error explains the residual best (no physics named): effect twins, null twins | {}; {} |",
            pct(s.model_error_best.0, s.effect_twins),
            pct(s.model_error_best.1, s.nulls)
        );
    }
    let _ = writeln!(
        o,
        "\nOn the visible twins the recordings cannot tell the first candidate from {:.1} others \
         on average (of {:.1} ranked): the pairs whose signatures are collinear, or where the \
         better one adds nothing significant beyond the other, or neither one-effect fit is \
         significantly better (`diagnose::name`). \"First or indistinguishable\" counts those \
         twins too; it says the concealed effect is among what these recordings allow, not \
         that they single it out.",
        s.visible_mean_tied.0, s.visible_mean_tied.1
    );
}

/// The confusion matrix: rows concealed, columns named.
fn confusion(o: &mut String, s: &StudySummary) {
    let _ = writeln!(
        o,
        "\n## Confusion matrix (rows: concealed, columns: named)\n"
    );
    let mut rows: Vec<String> = s.confusion.iter().map(|c| c.0.clone()).collect();
    rows.sort();
    rows.dedup();
    let mut cols: Vec<String> = s.confusion.iter().map(|c| c.1.clone()).collect();
    cols.sort();
    cols.dedup();
    let _ = writeln!(o, "| concealed \\ named | {} |", cols.join(" | "));
    let _ = writeln!(o, "|---|{}", "---|".repeat(cols.len()));
    for row in &rows {
        let cells: Vec<String> = cols
            .iter()
            .map(|c| {
                s.confusion
                    .iter()
                    .find(|x| &x.0 == row && &x.1 == c)
                    .map_or(String::new(), |x| x.2.to_string())
            })
            .collect();
        let _ = writeln!(o, "| {row} | {} |", cells.join(" | "));
    }
}

/// Every twin's row, and the pending ones.
fn every_twin(o: &mut String, r: &StudyResults) {
    let _ = writeln!(
        o,
        "\n## Every twin\n\n| twin | concealed | true value | tip move (σ) | named | first | rank | Name estimate | refit value [interval] | held-out BE before → after (noise) mm |"
    );
    let _ = writeln!(o, "|---|---|---|---|---|---|---|---|---|---|");
    for t in &r.twins {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {:.1} | {} | {} | {} | {} | {} | {} |",
            t.twin,
            t.truth.as_deref().unwrap_or("none"),
            t.true_value.map_or(String::new(), |v| format!("{v}")),
            t.tip_move_sigma,
            t.named.as_deref().unwrap_or("nothing"),
            t.first.as_deref().unwrap_or("—"),
            t.rank.map_or(String::new(), |k| k.to_string()),
            t.name_estimate
                .map_or(String::new(), |(v, se)| format!("{v:.4} ± {se:.4}")),
            t.refit_value.map_or(String::new(), |(v, lo, hi)| format!(
                "{v:.4} [{lo:.4}, {hi:.4}]"
            )),
            t.held_out_be.map_or(String::new(), |(b, a, n)| format!(
                "{b:.2} → {a:.2} ({n:.2})"
            ))
        );
    }
    if !r.pending.is_empty() {
        let _ = writeln!(o, "\nPending (FE not run yet): {}.", r.pending.join(", "));
    }
}

/// A count of the summary, of how many.
type Count = fn(&StudySummary) -> (usize, usize);

/// The closed loop's results in Markdown: the three columns (before, planned, random) against
/// the targets, then every twin with the measurements each chooser added.
pub fn loop_markdown(r: &super::closed_loop::LoopResults) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "# Blind twin study: the measurement plans, tested\n");
    let _ = writeln!(
        o,
        "{} twins; up to {} measurements per twin, chosen by the diagnosis's plan (T-optimal \
         discrimination, {}) or drawn at random from the same menu ({}), made on the twin's own \
         FE with fresh noise; markers of the recordings {}. A twin whose diagnosis leaves no \
         tie gets no measurement.\n",
        r.twins.len(),
        r.k,
        if r.sequential {
            "one at a time, each planned on the diagnosis with the ones before"
        } else {
            "planned together on the recordings"
        },
        r.kinds
            .iter()
            .map(|k| k.label())
            .collect::<Vec<_>>()
            .join(", "),
        if r.markers { "used" } else { "left out" },
    );
    let rows: [(&str, Count); 5] = [
        (
            "concealed effect ranked first (visible twins; target ≥ 90 %)",
            |s| (s.visible_first, s.visible),
        ),
        ("… first or tied with the first", |s| {
            (s.visible_first_or_indistinguishable, s.visible)
        }),
        ("… named by the verdict", |s| (s.visible_named, s.visible)),
        ("every effect twin ranked first", |s| {
            (s.effect_first, s.effect_twins)
        }),
        ("false alarms on null twins (target ≤ 10 %)", |s| {
            (s.false_alarms, s.nulls)
        }),
    ];
    let _ = writeln!(o, "| | before | planned | random |");
    let _ = writeln!(o, "|---|---|---|---|");
    for (label, f) in rows {
        let cell = |s: &StudySummary| {
            let (a, b) = f(s);
            pct(a, b)
        };
        let _ = writeln!(
            o,
            "| {label} | {} | {} | {} |",
            cell(&r.before),
            cell(&r.planned),
            cell(&r.random)
        );
    }
    let _ = writeln!(
        o,
        "| other candidates tied with the first (mean, visible twins) | {:.1} | {:.1} | {:.1} |\n",
        r.before.visible_mean_tied.0, r.planned.visible_mean_tied.0, r.random.visible_mean_tied.0
    );
    let _ = writeln!(
        o,
        "| twin | concealed | first: before | planned | random | planned measurements |"
    );
    let _ = writeln!(o, "|---|---|---|---|---|---|");
    for t in &r.twins {
        let first = |s: &super::score::TwinScore| s.first.clone().unwrap_or_else(|| "—".into());
        let items = if t.planned.is_empty() {
            t.note.clone()
        } else {
            t.planned
                .iter()
                .map(|m| m.measurement.text())
                .collect::<Vec<_>>()
                .join("; ")
        };
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {} |",
            t.twin,
            t.before.truth.as_deref().unwrap_or("none"),
            first(&t.before),
            first(&t.after_planned),
            first(&t.after_random),
            items
        );
    }
    o
}
