//! The report a person reads first (Markdown): the findings in words at the top, what the
//! recordings lack, then the tables they rest on.

use std::fmt::Write;

use super::cells::{Family, Group};
use super::groups::Share;
use super::locate::Localisation;
use super::report::{Diagnosis, Stage};
use super::structure::Structure;
use super::wording::fmt_p;

/// The Markdown summary of a diagnosis.
pub fn summary_markdown(d: &Diagnosis) -> String {
    let mut s = String::new();
    let l = &d.locate;
    header(&mut s, d);
    let _ = writeln!(s, "## Findings\n");
    for f in &l.findings {
        let _ = writeln!(s, "- {}", f.text);
    }
    let _ = writeln!(
        s,
        "\nz = (predicted − recorded)/σ with the calibrator's noise model; every statement \
         rests on a test significant at α = {} after Holm's correction over all {} tests of \
         this report (`diagnosis.json` has each one).\n",
        l.alpha, l.tests
    );
    let _ = writeln!(s, "## What the recordings lack\n");
    if l.missing.is_empty() {
        let _ = writeln!(
            s,
            "Nothing: force at every configuration, markers along the actuator, every design \
             and pressure of the shipped plan."
        );
    }
    for m in &l.missing {
        let _ = writeln!(s, "- {} ({})", m.what, m.consequence);
    }
    let _ = writeln!(s, "\n## Stages\n");
    let _ = writeln!(s, "- **Locate**: run (this report).");
    for (name, st) in [("Name", &d.name), ("Model and show", &d.model_and_show)] {
        match st {
            Stage::NotRun { reason } => {
                let _ = writeln!(s, "- **{name}**: not run: {reason}.");
            }
            Stage::Named(n) if l.consistent_with_scatter() => {
                let _ = writeln!(
                    s,
                    "- **{name}** (a hypothesis: Locate finds the residuals consistent with the \
                     recorded scatter): {}",
                    n.verdict
                );
            }
            Stage::Named(n) => {
                let _ = writeln!(s, "- **{name}**: {}", n.verdict);
            }
            Stage::Modelled(r) => {
                let _ = writeln!(s, "- **{name}**: {}", r.verdict);
            }
        }
    }
    if let Some(r) = &d.fe_ranking {
        let hyp = if l.consistent_with_scatter() {
            " (a hypothesis: Locate finds the residuals consistent with the recorded scatter)"
        } else {
            ""
        };
        let _ = writeln!(s, "- **Name, ranked by FE**{hyp}: {}", r.verdict);
    }
    if let Some(c) = d
        .sensitivity_coverage
        .as_ref()
        .filter(|c| c.enough() && !c.complete())
    {
        let _ = writeln!(s, "- **FE sensitivities**: {}.", c.text());
    }
    if let Some(p) = &d.measurement_plan {
        let _ = write!(s, "\n## What to measure next\n\n{}", p.markdown());
    }
    if let Stage::Named(n) = &d.name {
        naming(&mut s, n);
    }
    if let Some(r) = &d.fe_ranking {
        fe_ranking(&mut s, r);
    }
    if let Some(me) = &d.mesh_error {
        let _ = writeln!(
            s,
            "\nThe model's own mesh error (candidate `{}`): `{}` differs from the diagnosing \
             model by {:.2} σ rms at the calibrated material ({}); its size is in multiples of \
             that difference.",
            me.direction.name,
            me.reference,
            me.rms_sigma,
            me.rms_sigma_by_output
                .iter()
                .map(|(o, v)| format!("{o} {v:.2} σ"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if let Some(r) = d.refitted() {
        refit_section(&mut s, r);
    }
    residual_map(&mut s, l);
    shares(&mut s, l);
    structures(&mut s, l);
    groups(&mut s, l);
    if l.along_actuator {
        along(&mut s, l);
    }
    let _ = write!(s, "\n{}", crate::calibrate::inputs::markdown(&d.inputs));
    s
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("—".to_string(), |x| format!("{x:.digits$}"))
}

/// The FE-confirmed ranking of the top candidates.
fn fe_ranking(s: &mut String, r: &super::refit::FeRanking) {
    let _ = writeln!(
        s,
        "\n## Name: the top candidates fitted with FE\n\n{} cells; each candidate refitted \
         with the material, run on the FE model ({} mesh) at its refitted value and refitted \
         around the FE; ranked by the FE's χ². z: likelihood ratio of the first's FE fit \
         against this one's (Vuong), tied below the two-sided normal quantile of α = {}.\n",
        r.n_cells, r.mesh, r.alpha
    );
    let _ = writeln!(
        s,
        "| FE rank | effect | linearised rank | linearised Δχ² | value | FE χ² | mean tip BE (mm) \
         | mean abs. force error (N) | FE − linearised (rms σ) | rounds | z | tied with the \
         first |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (i, c) in r.candidates.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} | {:.4} {} | {:.1} | {} | {} | {:.2}{} | {} | {} | {} |",
            i + 1,
            c.effect,
            c.linear_rank,
            c.linear_delta_chi2,
            c.value,
            c.unit,
            c.fe_chi2,
            opt(c.fe_mean_be_mm, 2),
            opt(c.fe_mean_abs_force_error_n, 3),
            c.rms_fe_minus_linear,
            if c.confirmed { "" } else { " (not confirmed)" },
            c.rounds,
            opt(c.vuong_z, 2),
            if i == 0 {
                "–"
            } else if c.tied_with_first {
                "yes"
            } else {
                "no"
            }
        );
    }
}

/// The refit: sizes, fit before and after, held-out designs, FE rounds.
fn refit_section(s: &mut String, r: &super::refit::Refit) {
    let _ = writeln!(s, "\n## Model and show: the refit with the effect\n");
    let _ = writeln!(
        s,
        "{} cells; the effect linearised with the {}.\n",
        r.n_cells, r.linearised_at
    );
    let _ = writeln!(s, "| effect | value | std. error | interval | note |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for e in &r.effects {
        let _ = writeln!(
            s,
            "| {} | {:.4}{} | {:.4} | [{:.4}, {:.4}] | {} |",
            e.effect,
            e.value,
            super::wording::unit_suffix(&e.unit),
            e.std_error,
            e.interval.0,
            e.interval.1,
            e.at_bound.as_deref().unwrap_or("")
        );
    }
    let _ = writeln!(
        s,
        "\n| fit | μ1 | α1 | μ2 | α2 | χ² | mean tip BE (mm) | mean force error (N) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for (what, f) in [
        ("material only", &r.before),
        ("material + effect", &r.after),
    ] {
        let m = &f.material;
        let _ = writeln!(
            s,
            "| {what} | {:.4} | {:.3} | {:.4} | {:.3} | {:.1} | {} | {} |",
            m.mu1_mpa,
            m.alpha1,
            m.mu2_mpa,
            m.alpha2,
            f.quality.chi2,
            opt(f.quality.mean_be_mm, 2),
            opt(f.quality.mean_force_error_n, 3)
        );
    }
    let _ = writeln!(
        s,
        "\nF = {:.2}, {}; a perfect model would show a mean tip BE of {} mm under the \
         recordings' noise.",
        r.f,
        fmt_p(r.p_value),
        opt(r.noise_be_mm, 2)
    );
    if let Some(h) = &r.held_out {
        let _ = writeln!(
            s,
            "\n### Held out: each design left out of both fits in turn\n\n| N | T (mm) | tip BE \
             before (mm) | after (mm) | χ² before | after | effect fitted without it |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for d in &h.designs {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1} | {:.1} | {} |",
                d.n_bellows,
                d.wall_thickness_mm,
                opt(d.before.mean_be_mm, 2),
                opt(d.after.mean_be_mm, 2),
                d.before.chi2,
                d.after.chi2,
                d.effects
                    .iter()
                    .map(|v| format!("{v:.4}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let _ = writeln!(
            s,
            "| all | | {} | {} | {:.1} | {:.1} | |",
            opt(h.mean_be_before_mm, 2),
            opt(h.mean_be_after_mm, 2),
            h.chi2_before,
            h.chi2_after
        );
    }
    if !r.fe.is_empty() {
        let _ = writeln!(
            s,
            "\n### FE confirmation\n\n| round | effect(s) | mean tip BE (mm) | mean force error \
             (N) | rms (FE − linearised)/σ | worst | ramps run |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for (i, f) in r.fe.iter().enumerate() {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.2} | {:.2} σ ({}) | {} |",
                i + 1,
                f.effects
                    .iter()
                    .map(|v| format!("{v:.4}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                opt(f.quality.mean_be_mm, 2),
                opt(f.quality.mean_force_error_n, 3),
                f.rms_fe_minus_linear,
                f.worst.0,
                f.worst.1,
                f.ramps_run
            );
        }
    }
}

/// Title, recordings, model and the calibration diagnosed.
fn header(s: &mut String, d: &Diagnosis) {
    let c = &d.calibration;
    let b = &c.best;
    let _ = writeln!(s, "# Diagnosis\n");
    let _ = writeln!(s, "Recordings: {}. Model {}.\n", sources(d), c.model);
    let _ = writeln!(
        s,
        "Calibrated with objective `{}` ({} observations at {} configurations): μ1 = {:.4} MPa, \
         α1 = {:.4}, μ2 = {:.4} MPa, α2 = {:.4} (μ0 = {:.3} MPa); χ²/dof = {:.2}, mean tip \
         error {:.2} mm{}.{}\n",
        c.objective,
        c.n_observations,
        c.n_configurations,
        b.mu1_mpa,
        b.alpha1,
        b.mu2_mpa,
        b.alpha2,
        b.mu0_mpa(),
        c.chi2_per_dof,
        c.mean_be_mm,
        c.mean_force_error_n
            .map_or(String::new(), |f| format!(", mean force error {f:+.3} N")),
        if c.active_bounds.is_empty() {
            String::new()
        } else {
            format!(
                " Active bounds of the training domain: {}.",
                c.active_bounds.join("; ")
            )
        }
    );
}

fn sources(d: &Diagnosis) -> String {
    let r = &d.recordings;
    let default = |src: &str| {
        if d.inputs.iter().any(|f| f.default && f.path == src) {
            " (default)"
        } else {
            ""
        }
    };
    let mut v = vec![format!("bending {}{}", r.bending, default(&r.bending))];
    for (what, src) in [("force", &r.force), ("markers", &r.markers)] {
        if !src.is_empty() {
            v.push(format!("{what} {src}{}", default(src)));
        }
    }
    v.join(", ")
}

/// The scalar outputs present.
fn scalar_families(l: &Localisation) -> Vec<Family> {
    [Family::TipUz, Family::TipUy, Family::Angle, Family::Force]
        .into_iter()
        .filter(|&f| l.cells_of(f).next().is_some())
        .collect()
}

fn residual_map(s: &mut String, l: &Localisation) {
    let fams = scalar_families(l);
    let _ = writeln!(
        s,
        "\n## Residual map: z per design and pressure\n\n(* = not fitted: the calibration's \
         objective left the output out)\n"
    );
    let head: Vec<String> = fams
        .iter()
        .map(|f| {
            let fitted = l.cells_of(*f).any(|c| c.fitted);
            format!("{}{}", f.label(), if fitted { "" } else { " *" })
        })
        .collect();
    let _ = writeln!(s, "| N | T (mm) | P (bar) | {} |", head.join(" | "));
    let _ = writeln!(s, "|---|---|---|{}", "---|".repeat(fams.len()));
    let mut configs: Vec<(u32, f64, f64)> = l
        .cells
        .iter()
        .map(|c| (c.n_bellows, c.wall_thickness_mm, c.pressure_bar))
        .collect();
    configs.dedup();
    for (n, t, p) in configs {
        let row: Vec<String> = fams
            .iter()
            .map(|&f| {
                l.cells
                    .iter()
                    .find(|c| {
                        c.family == f
                            && c.n_bellows == n
                            && c.wall_thickness_mm == t
                            && c.pressure_bar == p
                    })
                    .map_or("—".into(), |c| format!("{:+.2}", c.standardised))
            })
            .collect();
        let _ = writeln!(s, "| {n} | {t} | {p} | {} |", row.join(" | "));
    }
}

/// A table of shares; the mean z only for whole outputs (a group mixes outputs whose signs
/// mean different things).
fn share_table(s: &mut String, title: &str, rows: &[Share]) {
    if rows.is_empty() {
        return;
    }
    let by_output = rows.iter().all(|r| r.family.is_some());
    let _ = writeln!(s, "\n{title}\n");
    let _ = writeln!(
        s,
        "| | cells | χ² | share of χ² | share of cells |{} rms z |",
        if by_output { " mean z |" } else { "" }
    );
    let _ = writeln!(
        s,
        "|---|---|---|---|---|{}---|",
        if by_output { "---|" } else { "" }
    );
    for r in rows {
        let name = match (r.family, r.group) {
            (Some(f), _) => f.label().to_string(),
            (None, Some(g)) => g.label(),
            (None, None) => "all".into(),
        };
        let mean = if by_output {
            format!(" {:+.2} |", r.mean_z)
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "| {name} | {} | {:.1} | {:.1} % | {:.1} % |{mean} {:.2} |",
            r.cells,
            r.chi2,
            100.0 * r.share,
            100.0 * r.cell_fraction,
            r.rms_z
        );
    }
}

fn shares(s: &mut String, l: &Localisation) {
    let _ = writeln!(
        s,
        "\n## Where the χ² is\n\nχ² = Σ z² = {:.1} over {} cells (each recorded number once).",
        l.chi2,
        l.cells.len()
    );
    let sh = &l.shares;
    share_table(s, "By output:", &sh.by_output);
    share_table(s, "By design:", &sh.by_design);
    share_table(s, "By N:", &sh.by_n);
    share_table(s, "By T:", &sh.by_t);
    share_table(s, "By P:", &sh.by_p);
    share_table(s, "By marker:", &sh.by_marker);
    let _ = writeln!(
        s,
        "\nMisfit of each output against the recorded scatter (χ²(n) test):\n"
    );
    let _ = writeln!(
        s,
        "| output | fitted | cells | χ² | rms z | p | significant |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for m in &l.misfits {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} | {:.2} | {} | {} |",
            m.family.label(),
            yes(m.fitted),
            m.cells,
            m.chi2,
            m.rms_z,
            fmt_p(m.p_value),
            yes(m.significant)
        );
    }
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

fn structure_table(s: &mut String, st: &Structure) {
    let _ = writeln!(
        s,
        "\n**{}** ({} cells, {} residual degrees of freedom): all terms explain {:.0} % of its \
         χ² (F = {:.2}, {}), the significant ones {:.0} %; unstructured scatter ŝ = {:.2} σ; \
         median σ = {:.3} {}.\n",
        st.family.label(),
        st.cells,
        st.dof,
        100.0 * st.explained,
        st.f,
        fmt_p(st.f_p_value),
        100.0 * st.explained_by_significant,
        st.scale,
        st.median_sigma,
        st.family.unit()
    );
    let _ = writeln!(
        s,
        "| term | centre | coefficient | std error | t | p | significant |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for t in &st.terms {
        let _ = writeln!(
            s,
            "| {} | {:.3} | {:+.3} {} | {:.3} | {:+.2} | {} | {} |",
            t.term.label(),
            t.centre,
            t.coefficient,
            t.term.unit(),
            t.std_error,
            t.t,
            fmt_p(t.p_value),
            yes(t.significant)
        );
    }
    for d in &st.dropped {
        let _ = writeln!(s, "\n{} left out: {}.", d.term.label(), d.reason);
    }
}

fn structures(s: &mut String, l: &Localisation) {
    let _ = writeln!(
        s,
        "\n## Structure over N, T, P\n\nz ≈ β₀ + β_T (T − T̄) + β_N (N − N̄) + β_P (P − P̄) + \
         β_PT (P − P̄)(T − T̄) [+ β_s (s − s̄) along the actuator], least squares per output; \
         t-tests with the scale estimated from what the structure leaves."
    );
    for st in &l.structures {
        structure_table(s, st);
    }
}

fn groups(s: &mut String, l: &Localisation) {
    let _ = writeln!(
        s,
        "\n## Group means and signs\n\nZ = Σ z / √n per output and group (N(0, 1) under the \
         noise model); `+/−`: cells above / below the recordings.\n"
    );
    let _ = writeln!(
        s,
        "| output | group | cells | mean z | + / − | Z | p | significant |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for g in &l.groups {
        if matches!(g.group, Group::Marker { .. }) {
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:+.2} | {} / {} | {:+.2} | {} | {} |",
            g.family.label(),
            g.group.label(),
            g.cells,
            g.mean_z,
            g.positive,
            g.negative,
            g.z,
            fmt_p(g.p_value),
            yes(g.significant)
        );
    }
}

fn along(s: &mut String, l: &Localisation) {
    let _ = writeln!(
        s,
        "\n## Along the actuator\n\nMean z per marker (marker k at k·Lf/9 from the support; 9 \
         is the tip).\n"
    );
    let _ = writeln!(
        s,
        "| marker | output | cells | mean z | + / − | Z | significant |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for g in &l.groups {
        if let Group::Marker { marker } = g.group {
            let _ = writeln!(
                s,
                "| {marker} | {} | {} | {:+.2} | {} / {} | {:+.2} | {} |",
                g.family.label(),
                g.cells,
                g.mean_z,
                g.positive,
                g.negative,
                g.z,
                yes(g.significant)
            );
        }
    }
}

/// The Name stage's table: every candidate, the pairs the recordings cannot separate, and
/// what could not be tested.
fn naming(s: &mut String, n: &crate::diagnose::name::Naming) {
    let _ = writeln!(
        s,
        "\n## Name: candidate effects\n\n{} cells with FE sensitivities; χ² {:.1} at the \
         calibrated set, {:.1} after a linearised material re-fit on every cell.\n",
        n.n_cells, n.chi2, n.chi2_material
    );
    let _ = writeln!(
        s,
        "| effect | size | ± | unit | material absorbs | explains | F | p | Holm | ΔAIC | ΔBIC | plausible |\n|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for c in &n.candidates {
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {} | {:.0} % | {:.1} % | {:.2} | {:.2e} | {} | {:+.1} | {:+.1} | {} |",
            c.effect,
            c.size_text(4),
            c.std_error,
            c.unit,
            100.0 * c.absorbed_by_material,
            100.0 * c.explained,
            c.f,
            c.p_value,
            if c.significant { "significant" } else { "-" },
            c.delta_aic,
            c.delta_bic,
            if c.plausible { "yes" } else { "no" }
        );
    }
    for p in &n.indistinguishable {
        let _ = writeln!(
            s,
            "\n{} and {} cannot be told apart on these recordings ({}){}.",
            p.a,
            p.b,
            p.why(),
            p.separated_by.as_ref().map_or(String::new(), |w| format!(
                "; what would separate them: {w}"
            ))
        );
    }
    for u in &n.untestable {
        let _ = writeln!(s, "\n{} not testable: {}.", u.effect, u.reason);
    }
    if !n.spikes.is_empty() {
        let _ = writeln!(
            s,
            "\nFE derivative spikes (a derivative more than 10 times its value at the ramp's \
             other pressures, as at a contact switch; these cells' linearisation is doubtful):\n"
        );
        for sp in &n.spikes {
            let _ = writeln!(s, "- {sp}");
        }
    }
}
