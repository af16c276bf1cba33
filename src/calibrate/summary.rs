//! The calibration's report in Markdown, the one a person reads first: a sequence of sections,
//! each a function of the part of the [`Calibration`] it describes (and of the FE verification,
//! when one ran).
//!
//! ```text
//!   verdict, objective, inputs ─► the sets (literature, calibrated) ─► bending errors
//!   ─► minima of the multistart ─► active bounds (─► box extension) ─► what the data determine
//!   ─► data checks ─► exclusions ─► the study's per-configuration procedure
//!   ─► FE verification ─► wall time
//! ```
use std::fmt::Write;

use super::extend::{BoxExtension, ExtendStop};
use super::fit::{describe_exclusions, Calibration};
use super::identify::{Determinacy, Identifiability};
use super::inputs;
use super::study::PerConfigurationStudy;
use super::verdict;
use super::verify::FeVerification;

/// The calibration report in Markdown (`summary.md` of `surrogate calibrate`), with the FE
/// verification `fe` of the calibrated set when there is one.
pub fn summary_markdown(cal: &Calibration, fe: Option<&FeVerification>) -> String {
    summary_markdown_extended(cal, fe, None)
}

/// [`summary_markdown`] of `cal`, the calibration through the last surrogate of a box
/// extension `extension` (`surrogate calibrate --extend-box`; its
/// [`last`](BoxExtension::last)), with the extension's section after the active bounds.
pub fn summary_markdown_extended(
    cal: &Calibration,
    fe: Option<&FeVerification>,
    extension: Option<&BoxExtension>,
) -> String {
    let mut s = String::new();
    heading(&mut s, cal);
    sets(&mut s, cal);
    bending_errors(&mut s, cal, fe);
    minima(&mut s, cal);
    bounds(&mut s, cal, extension);
    if let Some(e) = extension {
        let _ = writeln!(s, "\n{}", e.summary_markdown());
    }
    determined(&mut s, cal);
    if !cal.identifiability.extra_measurements.is_empty() {
        extra_measurements(&mut s, &cal.identifiability);
    }
    data_checks(&mut s, cal);
    if let Some(st) = &cal.per_configuration {
        per_configuration(&mut s, st);
    }
    if let Some(why) = &cal.per_configuration_skipped {
        let _ = writeln!(
            s,
            "\nThe study's procedure (one set per configuration): not run: {why}."
        );
    }
    if let Some(v) = fe {
        fe_verification(&mut s, v);
    }
    let _ = writeln!(s, "\nCalibration time: {:.2} s.", cal.wall_time_s);
    s
}

/// The verdict in words, the objective and the input files.
fn heading(s: &mut String, cal: &Calibration) {
    let _ = writeln!(s, "# Calibration\n");
    let _ = writeln!(
        s,
        "{}\n",
        verdict::fit_verdict(cal.chi2, cal.identifiability.dof)
    );
    let _ = writeln!(
        s,
        "Objective `{}`: {} observations at {} configurations, model {}.\n",
        cal.objective, cal.n_observations, cal.n_configurations, cal.model
    );
    let _ = writeln!(s, "{}", inputs::markdown(&cal.inputs));
}

/// The literature and the calibrated set with their `χ²`, and the calibrated one as a
/// material argument.
fn sets(s: &mut String, cal: &Calibration) {
    let _ = writeln!(s, "| set | μ1 (MPa) | α1 | μ2 (MPa) | α2 | μ0 (MPa) | χ² |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (name, p, c) in [
        ("literature", &cal.literature, cal.chi2_literature),
        ("calibrated", &cal.best, cal.chi2),
    ] {
        // the set at full precision (shortest round trip): it is typed back as a material
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} | {} | {:.3} | {:.1} |",
            p.mu1_mpa,
            p.alpha1,
            p.mu2_mpa,
            p.alpha2,
            p.mu0_mpa(),
            c
        );
    }
    let b = &cal.best;
    let _ = writeln!(
        s,
        "\nThe calibrated set as a material: `--material DIR/report.json` (this report's \
         directory; any command that takes a material), or `--material {},{},{},{}`.\n",
        b.mu1_mpa, b.alpha1, b.mu2_mpa, b.alpha2
    );
}

/// Bending and force errors of both sets through the surrogate (and of the calibrated one by
/// FE), with the reference study's own figure when the recordings are its experiments.
fn bending_errors(s: &mut String, cal: &Calibration, fe: Option<&FeVerification>) {
    let _ = writeln!(
        s,
        "| through the surrogate | mean BE (mm) | median BE (mm) | the study's nine: mean BE (mm) | mean F error (N) | mean |F error| (N) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    let fe_row = fe.map(|v| (format!("calibrated, FE ({} mesh)", v.mesh), &v.summary));
    for (name, x) in [
        ("literature".to_string(), &cal.literature_summary),
        ("calibrated".to_string(), &cal.calibrated),
    ]
    .into_iter()
    .chain(fe_row)
    {
        let _ = writeln!(
            s,
            "| {name} | {:.2} | {:.2} | {:.2} | {:+.3} | {:.3} |",
            x.mean_be_mm,
            x.median_be_mm,
            x.paper_nine_mean_be_mm,
            x.mean_force_error_n,
            x.mean_abs_force_error_n
        );
    }
    if let Some(line) = verdict::reference_study_line(&cal.inputs) {
        let _ = writeln!(s, "\n{line}");
    }
    let _ = writeln!(s);
}

/// The distinct minima the multistart reached, one row each.
fn minima(s: &mut String, cal: &Calibration) {
    let _ = writeln!(
        s,
        "{} starts reached {} distinct minima (every end point is in report.json).",
        cal.starts.len(),
        cal.minima
    );
    let _ = writeln!(
        s,
        "\n| minimum | starts | χ² | μ1 (MPa) | α1 | μ2 (MPa) | α2 | on a bound |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for k in 0..cal.minima {
        let starts: Vec<_> = cal.starts.iter().filter(|st| st.minimum == k).collect();
        if let Some(f) = starts.first() {
            let e = &f.end;
            let _ = writeln!(
                s,
                "| {} | {} | {:.1} | {:.4} | {:.4} | {:.4} | {:.4} | {} |",
                k + 1,
                starts.len(),
                f.chi2,
                e.mu1_mpa,
                e.alpha1,
                e.mu2_mpa,
                e.alpha2,
                f.active_bounds.len()
            );
        }
    }
    let _ = writeln!(s);
}

/// Whether the training box truncates the optimum (and, after a box extension, whether the
/// physical limits do).
fn bounds(s: &mut String, cal: &Calibration, extension: Option<&BoxExtension>) {
    if cal.active_bounds.is_empty() {
        let _ = writeln!(
            s,
            "No bound of the training domain is active at the optimum."
        );
        return;
    }
    if let Some(ExtendStop::PhysicalLimit {
        bounds,
        undetermined,
    }) = extension.map(|e| &e.stop)
    {
        let _ = writeln!(
            s,
            "**The physical limits truncate this optimum**: it ends on {}, and the box was \
             extended up to the physical limits there ({}); beyond them the parametrisation \
             describes no elastomer.{} Material alone does not reach the recordings: the \
             diagnoser (`surrogate diagnose`) looks for what else is missing.",
            cal.active_bounds.join("; "),
            bounds.join("; "),
            if undetermined.is_empty() {
                String::new()
            } else {
                format!(
                    " The bounds of coordinates the recordings do not determine ({}) were \
                     left: their profiles are open on both sides, so moving them would change \
                     nothing the recordings see.",
                    undetermined.join("; ")
                )
            }
        );
        return;
    }
    let _ = writeln!(
        s,
        "**The training box truncates this optimum**: it ends on {} (the fit would move \
         further if the box let it, and the surrogate does not know what lies there). The \
         numbers above are the best inside the box, not the best material; \
         `surrogate calibrate --extend-box K` extends the box there (new FE cases, retrained \
         surrogate, refit), `surrogate identify` fits straight on the FE model, without the \
         box, and with the unstated dimensions.",
        cal.active_bounds.join("; ")
    );
}

/// What the data determine: the scaled covariance, each parameter's standard error and
/// profile interval, the eigen-directions of the information.
fn determined(s: &mut String, cal: &Calibration) {
    let id = &cal.identifiability;
    let _ = writeln!(
        s,
        "\n## What the data determine\n\nχ²/dof = {:.2} ({} observations − 4 parameters); covariance scaled by ŝ² = {:.2}.\n",
        cal.chi2 / id.dof as f64,
        cal.n_observations,
        id.variance_scale
    );
    let _ = writeln!(
        s,
        "| parameter | estimate | std error | 95 % profile interval | |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for (k, p) in id.profiles.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.3} | [{:.4}, {:.4}] | {} |",
            p.name,
            p.optimum,
            id.std_errors[k],
            p.interval[0],
            p.interval[1],
            p.determinacy.describe()
        );
    }
    let _ = writeln!(
        s,
        "\nEigen-directions of the information (unit box; std as a fraction of the box):\n"
    );
    for d in &id.directions {
        let v: Vec<String> = d
            .vector
            .iter()
            .filter(|(_, c)| c.abs() > 0.1)
            .map(|(n, c)| format!("{c:+.2} {n}"))
            .collect();
        let _ = writeln!(s, "- {} : std {:.3}", v.join(" "), d.std_fraction);
    }
}

/// What each extra measurement would do to the standard errors, and the one that sharpens
/// each parameter the data leave undetermined.
fn extra_measurements(s: &mut String, id: &Identifiability) {
    let _ = writeln!(
        s,
        "\nExtra measurements (linearised; each row: the standard errors of {} with it added, as a fraction of today's):\n",
        id.names.join(" / ")
    );
    for m in &id.extra_measurements {
        let _ = writeln!(
            s,
            "- {}: × {}",
            m.measurement,
            m.ratio
                .iter()
                .map(|r| format!("{r:.2}"))
                .collect::<Vec<_>>()
                .join(" / ")
        );
    }
    for (k, p) in id.profiles.iter().enumerate() {
        if p.determinacy == Determinacy::Determined {
            continue;
        }
        if let Some(m) = id
            .extra_measurements
            .iter()
            .min_by(|a, b| a.ratio[k].total_cmp(&b.ratio[k]))
        {
            let _ = writeln!(
                s,
                "\n{} is {}; the measurement that sharpens it most: {} (its standard error × {:.2}).",
                p.name,
                p.determinacy.describe(),
                m.measurement,
                m.ratio[k]
            );
        }
    }
}

/// The rows the data checks flag, and the rows left out.
fn data_checks(s: &mut String, cal: &Calibration) {
    if !cal.flags.is_empty() {
        let _ = writeln!(s, "\n## Data checks\n");
        for f in &cal.flags {
            let _ = writeln!(s, "- {} ({}): {}", f.config.label(), f.source, f.message);
        }
    }
    if !cal.excluded.is_empty() {
        let _ = writeln!(s, "\n## Excluded\n");
        for e in describe_exclusions(&cal.excluded) {
            let _ = writeln!(s, "- {e}");
        }
    }
}

/// The reference study's procedure (one set per configuration) against one set, and the
/// spread of its sets.
fn per_configuration(s: &mut String, st: &PerConfigurationStudy) {
    let _ = writeln!(
        s,
        "\n## The study's procedure: one set per configuration (±{:.0} % of the literature set)\n",
        100.0 * st.fraction
    );
    let _ = writeln!(
        s,
        "| | literature | per configuration | one set, same box |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    for (name, v) in [
        ("all, mean BE (mm)", &st.all),
        ("the study's nine, mean BE (mm)", &st.paper_nine),
    ] {
        let _ = writeln!(
            s,
            "| {name} | {:.2} | {:.2} | {:.2} |",
            v[0].mean_mm, v[1].mean_mm, v[2].mean_mm
        );
    }
    for (name, v) in [
        ("all, median BE (mm)", &st.all),
        ("the study's nine, median BE (mm)", &st.paper_nine),
    ] {
        let _ = writeln!(
            s,
            "| {name} | {:.2} | {:.2} | {:.2} |",
            v[0].median_mm, v[1].median_mm, v[2].median_mm
        );
    }
    let _ = writeln!(s, "\nSpread of the per-configuration sets:\n");
    let _ = writeln!(
        s,
        "| parameter | mean | std | CV | min | max | on the box |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for p in &st.spread {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.4} | {:.1} % | {:.4} | {:.4} | {} of {} |",
            p.name,
            p.mean,
            p.std,
            100.0 * p.cv,
            p.min,
            p.max,
            p.on_box,
            st.fits.len()
        );
    }
}

/// Surrogate against FE at the optimum, and the designs to add as high-fidelity cases.
fn fe_verification(s: &mut String, v: &FeVerification) {
    let _ = writeln!(
        s,
        "\n## FE verification ({} mesh)\n\nSurrogate vs FE at the optimum: mean |Δ| tip Uz {:.2} mm, tip Uy {:.2} mm, force {:.3} N (max {:.2} / {:.2} / {:.3}); {} configurations outside the surrogate's 2σ band.",
        v.mesh,
        v.mean_abs_sur_fe[0],
        v.mean_abs_sur_fe[1],
        v.mean_abs_sur_fe[2],
        v.max_abs_sur_fe[0],
        v.max_abs_sur_fe[1],
        v.max_abs_sur_fe[2],
        v.disagreements
    );
    if !v.designs_to_refine.is_empty() {
        let d: Vec<String> = v
            .designs_to_refine
            .iter()
            .map(|(n, t)| format!("N={n} T={t}"))
            .collect();
        let _ = writeln!(
            s,
            "Designs to add as high-fidelity cases before refitting: {}.",
            d.join(", ")
        );
    }
}
