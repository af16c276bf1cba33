//! Model and show's verdict in words.

use super::outcome::Refit;

/// The verdict on `r` in words, its intervals at `level`.
pub(crate) fn verdict(r: &Refit, level: f64) -> String {
    let sizes: Vec<String> = r
        .effects
        .iter()
        .map(|e| {
            format!(
                "{} = {:.4}{} ({:.0} % interval [{:.4}, {:.4}]{})",
                e.effect,
                e.value,
                crate::diagnose::wording::unit_suffix(&e.unit),
                100.0 * level,
                e.interval.0,
                e.interval.1,
                e.at_bound
                    .as_ref()
                    .map_or(String::new(), |b| format!("; {b}"))
            )
        })
        .collect();
    let mut s = format!(
        "Refitted with {}: χ² {:.1} → {:.1} on {} cells (F = {:.1}, p = {:.2e})",
        sizes.join(", "),
        r.before.quality.chi2,
        r.after.quality.chi2,
        r.n_cells,
        r.f,
        r.p_value
    );
    if let (Some(b0), Some(b1)) = (r.before.quality.mean_be_mm, r.after.quality.mean_be_mm) {
        s.push_str(&format!("; mean tip BE {b0:.2} → {b1:.2} mm"));
    }
    if let Some(h) = &r.held_out {
        if let (Some(b0), Some(b1)) = (h.mean_be_before_mm, h.mean_be_after_mm) {
            s.push_str(&format!(
                "; on designs left out one at a time {b0:.2} → {b1:.2} mm"
            ));
        }
        if let (Some(f0), Some(f1)) = (
            h.mean_abs_force_error_before_n,
            h.mean_abs_force_error_after_n,
        ) {
            s.push_str(&format!(", force |error| {f0:.3} → {f1:.3} N"));
        }
        s.push_str(&format!(
            ", held-out χ² {:.1} → {:.1}",
            h.chi2_before, h.chi2_after
        ));
    }
    if let Some(nb) = r.noise_be_mm {
        s.push_str(&format!(" (noise alone: {nb:.2} mm)"));
    }
    s.push('.');
    s
}
