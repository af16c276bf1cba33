//! The Name stage's verdict in words, from the ranked candidates and the tied pairs.

use super::naming::{Candidate, Indistinguishable};
use crate::diagnose::wording::unit_suffix;

/// The verdict in words: the best significant candidate at a plausible size is named; a
/// significant one whose size is outside the library's plausible range is reported as such,
/// not named.
pub(crate) fn verdict(c: &[Candidate], pairs: &[Indistinguishable], chi2_material: f64) -> String {
    let implausible: Vec<String> = c
        .iter()
        .filter(|t| t.significant && !t.plausible)
        .take(3)
        .map(|t| format!("{} ({}{})", t.effect, sized(t), unit_suffix(&t.unit)))
        .collect();
    let Some(top) = c.iter().find(|t| t.significant && t.plausible) else {
        return nothing_named(&implausible, chi2_material);
    };
    if top.model_error {
        return model_error_named(top, c);
    }
    effect_named(top, c, pairs, &implausible)
}

/// A candidate's estimate in the verdict's words ([`Candidate::size_text`]).
fn sized(t: &Candidate) -> String {
    t.size_text(3)
}

/// No candidate significant at a plausible size: nothing named, and why.
fn nothing_named(implausible: &[String], chi2_material: f64) -> String {
    if implausible.is_empty() {
        return format!(
            "No effect of the library explains the residual left after the material \
             re-fit (χ² = {chi2_material:.1}) significantly: nothing is named."
        );
    }
    format!(
        "No effect of the library explains the residual at a plausible size: the \
         significant ones would need sizes outside their ranges ({}), so nothing is \
         named (the residual left after the material re-fit, χ² = {chi2_material:.1}, \
         is larger than one effect of the library can make).",
        implausible.join(", ")
    )
}

/// The model's own error explains the residual best: no physics named.
fn model_error_named(top: &Candidate, c: &[Candidate]) -> String {
    let next = c
        .iter()
        .find(|t| t.significant && t.plausible && !t.model_error)
        .map_or(String::new(), |t| {
            format!(
                "; of the effects, {} would explain {:.0} % ({}{})",
                t.effect,
                100.0 * t.explained,
                sized(t),
                unit_suffix(&t.unit)
            )
        });
    format!(
        "The residual left after the material re-fit looks most like the diagnosing \
         model's own discretisation error ({} explains {:.0} %, size {:+.2} ± {:.2} {}, \
         F = {:.1}, p = {:.2e}){next}: no physics is named. Refine the model's mesh (or \
         diagnose with the finer model) before reading the residual as missing physics.",
        top.effect,
        100.0 * top.explained,
        top.estimate,
        top.std_error,
        top.unit,
        top.f,
        top.p_value,
    )
}

/// `top` named, with the candidates tied with it, the runners-up and those significant at
/// implausible sizes.
fn effect_named(
    top: &Candidate,
    c: &[Candidate],
    pairs: &[Indistinguishable],
    implausible: &[String],
) -> String {
    let mut s = format!(
        "{} explains {:.0} % of the residual left after the material re-fit (size {} ± \
         {:.3}{}, F = {:.1}, p = {:.2e})",
        top.effect,
        100.0 * top.explained,
        sized(top),
        top.std_error,
        unit_suffix(&top.unit),
        top.f,
        top.p_value,
    );
    let twins: Vec<&str> = pairs
        .iter()
        .filter_map(|p| {
            if p.a == top.effect {
                Some(p.b.as_str())
            } else if p.b == top.effect {
                Some(p.a.as_str())
            } else {
                None
            }
        })
        .collect();
    if !twins.is_empty() {
        s.push_str(&format!(
            "; on these recordings it cannot be told apart from {}",
            twins.join(", ")
        ));
    }
    let runners_up: Vec<String> = c
        .iter()
        .filter(|t| t.significant && t.plausible && !t.model_error && t.effect != top.effect)
        .take(2)
        .map(|t| {
            format!(
                "{} ({:.0} %, {}{})",
                t.effect,
                100.0 * t.explained,
                sized(t),
                unit_suffix(&t.unit)
            )
        })
        .collect();
    if !runners_up.is_empty() {
        s.push_str(&format!(
            "; also significant at a plausible size, explaining less: {}",
            runners_up.join(", ")
        ));
    }
    if !implausible.is_empty() {
        s.push_str(&format!(
            "; significant but at implausible sizes: {}",
            implausible.join(", ")
        ));
    }
    s.push('.');
    s
}
