//! The findings in words: each sentence is built from a test of the report that came out
//! significant (or from the absence of any), with its numbers.

use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::cells::Family;
use super::groups::{GroupMean, Misfit, Share, Shares};
use super::patterns::{mixed_groups, sign_patterns, Sentence};
use super::structure::{Structure, Term};
use super::wording::{capital, fmt_p, meaning, signed};

/// What a finding is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FindingKind {
    /// An output's residual against the recordings' scatter.
    Misfit,
    /// A significant trend over N, T, P or along the actuator.
    Structure,
    /// A group of cells all on one side of the recordings.
    SignPattern,
    /// Where the χ² is concentrated.
    Concentration,
    /// No significant structure.
    NoStructure,
}

/// One finding.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// Its kind.
    pub kind: FindingKind,
    /// The outputs it is about (empty: all).
    pub outputs: Vec<Family>,
    /// The sentence.
    pub text: String,
}

/// The numbers the findings are built from.
pub struct Evidence<'a> {
    /// Misfit per output.
    pub misfits: &'a [Misfit],
    /// Structure per output.
    pub structures: &'a [Structure],
    /// Group means.
    pub groups: &'a [GroupMean],
    /// χ² shares.
    pub shares: &'a Shares,
    /// Number of tests in the Holm family.
    pub tests: usize,
    /// Family-wise level.
    pub alpha: f64,
}

/// A value in σ with its rough size in the output's unit (times the median σ).
fn sized(v: f64, s: &Structure) -> String {
    format!(
        "{} σ ≈ {} {}",
        signed(v),
        signed(v * s.median_sigma),
        s.family.unit()
    )
}

/// The findings: the misfit, each output's structure, the sign patterns, where χ² is
/// concentrated; or that nothing is significant.
pub fn findings(e: &Evidence<'_>) -> Vec<Finding> {
    let mut out = Vec::new();
    let any_misfit = e.misfits.iter().any(|m| m.significant);
    let any_term = e
        .structures
        .iter()
        .any(|s| s.terms.iter().any(|t| t.significant));
    let any_group = e.groups.iter().any(|g| g.significant);
    if !any_misfit && !any_term && !any_group {
        let n: usize = e.misfits.iter().map(|m| m.cells).sum();
        let chi2: f64 = e.misfits.iter().map(|m| m.chi2).sum();
        out.push(Finding {
            kind: FindingKind::NoStructure,
            outputs: Vec::new(),
            text: format!(
                "Nothing is significant at α = {} (Holm over {} tests): the residuals are \
                 consistent with the recordings' scatter (χ²/n = {:.2} over {n} cells) and show \
                 no structure over N, T or P.",
                e.alpha,
                e.tests,
                chi2 / n.max(1) as f64
            ),
        });
        // one more test beside the stage's: at its strictest Holm level
        out.extend(more_precise_than_stated(
            e.misfits,
            e.alpha / (e.tests + 1) as f64,
        ));
        return out;
    }
    out.push(misfit(e.misfits));
    if !any_term && !any_group {
        out.push(Finding {
            kind: FindingKind::NoStructure,
            outputs: Vec::new(),
            text: format!(
                "The residual exceeds the recorded scatter but no term over N, T or P and no \
                 group mean is significant at α = {} (Holm over {} tests): it is not located.",
                e.alpha, e.tests
            ),
        });
    }
    for s in e.structures {
        if let Some(f) = structure(s) {
            out.push(f);
        }
    }
    let pattern = |p: Sentence| Finding {
        kind: FindingKind::SignPattern,
        outputs: p.outputs,
        text: p.text,
    };
    let patterns = sign_patterns(e.groups);
    if patterns.is_empty() && any_group {
        out.push(pattern(mixed_groups(e.groups)));
    }
    out.extend(patterns.into_iter().map(pattern));
    if any_misfit {
        out.extend(concentration(e.shares));
    }
    out
}

/// When the residuals are smaller than the recorded scatter makes likely (the lower tail of
/// `χ²(n)` over every cell below `alpha`; the caller passes the stage's strictest Holm level,
/// since the calibrated parameters alone lower `χ²` a little: noise at its stated σ gives
/// `χ²/n` about 0.8 on the shipped plan): the recordings are more precise than their stated
/// σ, so the tests are conservative.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn more_precise_than_stated(ms: &[Misfit], alpha: f64) -> Option<Finding> {
    let n: usize = ms.iter().map(|m| m.cells).sum();
    let chi2: f64 = ms.iter().map(|m| m.chi2).sum();
    let lower = ChiSquared::new(n as f64).map_or(f64::NAN, |d| d.cdf(chi2));
    (n > 0 && lower < alpha).then(|| Finding {
        kind: FindingKind::Misfit,
        outputs: Vec::new(),
        text: format!(
            "The residuals are smaller than the recorded scatter makes likely (χ²/n = {:.2} over \
             {n} cells, P(χ²({n}) ≤ χ²) = {lower:.1e}): the recordings are more precise than \
             their stated σ, so every test here is conservative; a σ from the recordings' own \
             repeat scatter would be smaller.",
            chi2 / n as f64
        ),
    })
}

/// Which outputs miss by more than the recorded scatter, and which do not.
fn misfit(ms: &[Misfit]) -> Finding {
    let part = |m: &Misfit| {
        format!(
            "{} {:.1}×{} ({} cells, {})",
            m.family.label(),
            m.rms_z,
            if m.fitted { "" } else { ", not fitted" },
            m.cells,
            fmt_p(m.p_value)
        )
    };
    let (over, within): (Vec<&Misfit>, Vec<&Misfit>) = ms.iter().partition(|m| m.significant);
    let mut text = String::new();
    if !over.is_empty() {
        text.push_str(&format!(
            "Residuals larger than the recorded scatter (rms z, χ²(n) test): {}.",
            over.iter().map(|m| part(m)).collect::<Vec<_>>().join("; ")
        ));
    }
    if !within.is_empty() {
        text.push_str(&format!(
            "{}Consistent with the recorded scatter: {}.",
            if text.is_empty() { "" } else { " " },
            within
                .iter()
                .map(|m| part(m))
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    if ms.iter().any(|m| !m.fitted) {
        text.push_str(
            " (Not fitted: outputs the calibration's objective left out, predicted at the \
             calibrated set.)",
        );
    }
    Finding {
        kind: FindingKind::Misfit,
        outputs: over.iter().map(|m| m.family).collect(),
        text,
    }
}

/// `x = lo` and `x = hi` in words for a term's variable.
fn at(term: Term, x: f64) -> String {
    match term {
        Term::T => format!("T = {x} mm"),
        Term::N => format!("N = {x}"),
        Term::P => format!("{x} bar"),
        Term::Position => format!("marker {}", (x * 9.0).round()),
        Term::Constant | Term::PT => String::new(),
    }
}

/// One trend term in words, from the structure's value at the ends of its variable.
fn trend(s: &Structure, term: Term) -> Option<String> {
    let f = s.term(term).filter(|f| f.significant)?;
    let stat = format!("{:+.2} {}, t = {:.1}", f.coefficient, term.unit(), f.t);
    if term == Term::PT {
        let steeper = s
            .term(Term::T)
            .filter(|t| t.significant)
            .map(|t| t.coefficient.signum() == f.coefficient.signum());
        let how = match steeper {
            Some(true) => "the trend over T is steeper at higher P",
            Some(false) => "the trend over T is flatter at higher P",
            None => "the residual's dependence on T changes with P",
        };
        return Some(format!("{how} ({stat})"));
    }
    let (lo, hi) = (f.range[0], f.range[1]);
    let (a, b) = (s.along(term, lo, true), s.along(term, hi, true));
    let (alo, ahi) = (at(term, lo), at(term, hi));
    let var = match term {
        Term::Position => "along the actuator".to_string(),
        _ => format!("with {}", term.label()),
    };
    let words = if a.signum() != b.signum() && a.abs() >= 0.5 && b.abs() >= 0.5 {
        format!(
            "changes sign {var}: the model {} at {alo} ({}) and {} at {ahi} ({})",
            meaning(s.family, a),
            sized(a, s),
            meaning(s.family, b),
            sized(b, s)
        )
    } else {
        let grows = if b.abs() > a.abs() {
            "grows"
        } else {
            "shrinks"
        };
        format!(
            "the miss {grows} {var}, {} at {alo} to {} at {ahi}",
            sized(a, s),
            sized(b, s)
        )
    };
    Some(format!("{words}; slope {stat}"))
}

fn structure(s: &Structure) -> Option<Finding> {
    let mut clauses = Vec::new();
    if let Some(c) = s.term(Term::Constant).filter(|c| c.significant) {
        clauses.push(format!(
            "on average the model {} ({} at the centre of the recorded designs and pressures, \
             t = {:.1})",
            meaning(s.family, c.coefficient),
            sized(c.coefficient, s),
            c.t
        ));
    }
    for term in [Term::T, Term::N, Term::P, Term::Position, Term::PT] {
        clauses.extend(trend(s, term));
    }
    if clauses.is_empty() {
        return None;
    }
    Some(Finding {
        kind: FindingKind::Structure,
        outputs: vec![s.family],
        text: format!(
            "{} (predicted − recorded): {}; these terms explain {:.0} % of its χ².",
            capital(s.family.label()),
            clauses.join("; "),
            100.0 * s.explained_by_significant
        ),
    })
}

/// The output, designs, pressure and markers holding at least twice their cells' fraction
/// of χ².
fn concentration(s: &Shares) -> Vec<Finding> {
    let mut out = Vec::new();
    let top = |v: &[Share], k: usize| -> Vec<Share> {
        let mut v: Vec<Share> = v
            .iter()
            .filter(|x| x.share >= 2.0 * x.cell_fraction)
            .cloned()
            .collect();
        v.sort_by(|a, b| b.share.total_cmp(&a.share));
        v.truncate(k);
        v
    };
    for (what, list) in [
        ("output", top(&s.by_output, 1)),
        ("design", top(&s.by_design, 3)),
        ("pressure", top(&s.by_p, 1)),
        ("marker", top(&s.by_marker, 2)),
    ] {
        if list.is_empty() {
            continue;
        }
        let parts: Vec<String> = list
            .iter()
            .map(|x| {
                let name = match (x.family, x.group) {
                    (Some(f), _) => f.label().to_string(),
                    (None, Some(g)) => g.label(),
                    (None, None) => String::new(),
                };
                format!(
                    "{name} holds {:.0} % of χ² with {:.0} % of the cells",
                    100.0 * x.share,
                    100.0 * x.cell_fraction
                )
            })
            .collect();
        out.push(Finding {
            kind: FindingKind::Concentration,
            outputs: list.iter().filter_map(|x| x.family).collect(),
            text: format!("Concentrated by {what}: {}.", parts.join("; ")),
        });
    }
    out
}
