//! Sign patterns: significant groups of cells on one side of the recordings, the outputs that
//! agree on a group merged, the groups that say the same thing in one sentence.

use super::cells::{Family, Group};
use super::groups::GroupMean;
use super::wording::{and_list, capital, count, meaning, signed};

/// One sentence about a sign pattern.
pub struct Sentence {
    /// The outputs it is about.
    pub outputs: Vec<Family>,
    /// The words.
    pub text: String,
}

/// One sign pattern: the outputs that agree on a group, and what they say.
struct Pattern<'a> {
    what: String,
    means: Vec<&'a GroupMean>,
}

/// Significant one-sided groups (one T, N, P, design or marker); bending outputs that agree on a
/// group are one pattern about the bending; the patterns that say the same thing are one
/// sentence listing their groups.
pub fn sign_patterns(groups: &[GroupMean]) -> Vec<Sentence> {
    let one_sided: Vec<&GroupMean> = groups
        .iter()
        .filter(|g| g.significant && g.one_sided())
        .collect();
    let mut patterns: Vec<Pattern<'_>> = Vec::new();
    let mut done = vec![false; one_sided.len()];
    for i in 0..one_sided.len() {
        if done[i] {
            continue;
        }
        let g = one_sided[i];
        let dir = meaning(g.family, g.mean_z);
        let mut means = vec![g];
        if g.family.bends_too_far(1.0).is_some() {
            for j in i + 1..one_sided.len() {
                let h = one_sided[j];
                if !done[j] && h.group == g.group && meaning(h.family, h.mean_z) == dir {
                    means.push(h);
                    done[j] = true;
                }
            }
        }
        let names: Vec<String> = means.iter().map(|h| h.family.label().to_string()).collect();
        let what = if means.len() > 1 {
            format!("the model {dir} ({} agree)", and_list(names))
        } else if g.family == Family::Force {
            format!("the model {dir}")
        } else {
            format!("the model {} ({})", g.family.direction(g.mean_z), names[0])
        };
        patterns.push(Pattern { what, means });
    }
    // a design inside a T or N that says the same is not said again
    let covers = |g: &Group, d: &Group| match (g, d) {
        (
            Group::T { wall_thickness_mm },
            Group::Design {
                wall_thickness_mm: t,
                ..
            },
        ) => (wall_thickness_mm - t).abs() < 1e-9,
        (Group::N { n_bellows }, Group::Design { n_bellows: n, .. }) => n_bellows == n,
        _ => false,
    };
    let patterns: Vec<&Pattern<'_>> = patterns
        .iter()
        .filter(|p| {
            !patterns.iter().any(|q| {
                q.what == p.what
                    && q.means.len() == p.means.len()
                    && covers(&q.means[0].group, &p.means[0].group)
            })
        })
        .collect();
    let mut out: Vec<Sentence> = Vec::new();
    let mut said: Vec<String> = Vec::new();
    for p in &patterns {
        if said.contains(&p.what) {
            continue;
        }
        said.push(p.what.clone());
        let same: Vec<&Pattern<'_>> = patterns
            .iter()
            .filter(|q| q.what == p.what)
            .copied()
            .collect();
        let parts = pattern_parts(&same);
        let mut outputs: Vec<Family> = same
            .iter()
            .flat_map(|q| q.means.iter().map(|h| h.family))
            .collect();
        outputs.dedup();
        out.push(Sentence {
            outputs,
            text: format!("{}: {}.", capital(&p.what), parts.join("; ")),
        });
    }
    out
}

/// The kind of a group (its factor), for putting levels of one factor together.
fn factor(g: &Group) -> u8 {
    match g {
        Group::T { .. } => 0,
        Group::N { .. } => 1,
        Group::P { .. } => 2,
        Group::Design { .. } => 3,
        Group::Marker { .. } => 4,
    }
}

/// Significant group means none of which is one-sided, in words (the five largest |Z|).
pub fn mixed_groups(groups: &[GroupMean]) -> Sentence {
    let mut gs: Vec<&GroupMean> = groups.iter().filter(|g| g.significant).collect();
    gs.sort_by(|a, b| b.z.abs().total_cmp(&a.z.abs()));
    let n = gs.len();
    gs.truncate(5);
    let parts: Vec<String> = gs
        .iter()
        .map(|g| {
            format!(
                "{} at {} (mean {} σ, Z = {:.1}, {} on that side)",
                g.family.label(),
                g.group.label(),
                signed(g.mean_z),
                g.z,
                count(g.on_side(), g.cells)
            )
        })
        .collect();
    let mut outputs: Vec<Family> = gs.iter().map(|g| g.family).collect();
    outputs.sort();
    outputs.dedup();
    Sentence {
        outputs,
        text: format!(
            "{n} group mean(s) differ from the recordings without a sign pattern (fewer than \
             80 % of their cells on one side): {}.",
            parts.join("; ")
        ),
    }
}

/// Several levels of one factor in words: `N = 9, 11 and 13`, `markers 2–9`.
fn levels_label(gs: &[Group]) -> String {
    let nums =
        |f: &dyn Fn(&Group) -> Option<f64>| -> Vec<f64> { gs.iter().filter_map(f).collect() };
    match gs.first() {
        Some(Group::N { .. }) => format!(
            "N = {}",
            and_list(
                nums(&|g| match g {
                    Group::N { n_bellows } => Some(f64::from(*n_bellows)),
                    _ => None,
                })
                .iter()
                .map(|v| v.to_string())
                .collect()
            )
        ),
        Some(Group::T { .. }) => format!(
            "T = {} mm",
            and_list(
                nums(&|g| match g {
                    Group::T { wall_thickness_mm } => Some(*wall_thickness_mm),
                    _ => None,
                })
                .iter()
                .map(|v| v.to_string())
                .collect()
            )
        ),
        Some(Group::P { .. }) => format!(
            "P = {} bar",
            and_list(
                nums(&|g| match g {
                    Group::P { pressure_bar } => Some(*pressure_bar),
                    _ => None,
                })
                .iter()
                .map(|v| v.to_string())
                .collect()
            )
        ),
        Some(Group::Design { .. }) => format!(
            "(N, T) = {}",
            and_list(
                gs.iter()
                    .filter_map(|g| match g {
                        Group::Design {
                            n_bellows,
                            wall_thickness_mm,
                        } => Some(format!("({n_bellows}, {wall_thickness_mm} mm)")),
                        _ => None,
                    })
                    .collect()
            )
        ),
        Some(Group::Marker { .. }) => {
            let k = nums(&|g| match g {
                Group::Marker { marker } => Some(f64::from(*marker)),
                _ => None,
            });
            let consecutive = k.windows(2).all(|w| w[1] - w[0] == 1.0);
            if consecutive && k.len() > 2 {
                format!("markers {}–{}", k[0], k[k.len() - 1])
            } else {
                format!(
                    "markers {}",
                    and_list(k.iter().map(|v| v.to_string()).collect())
                )
            }
        }
        _ => gs.iter().map(Group::label).collect::<Vec<_>>().join(", "),
    }
}

/// The groups of patterns that say the same thing, in words: one part per group, or, for
/// one output and several levels of a factor, one part per factor (cells pooled, the
/// smallest |Z|).
fn pattern_parts(same: &[&Pattern<'_>]) -> Vec<String> {
    let mut parts = Vec::new();
    let mut kinds: Vec<u8> = same.iter().map(|q| factor(&q.means[0].group)).collect();
    kinds.sort_unstable();
    kinds.dedup();
    for kind in kinds {
        let qs: Vec<&&Pattern<'_>> = same
            .iter()
            .filter(|q| factor(&q.means[0].group) == kind)
            .collect();
        let single = qs.iter().all(|q| q.means.len() == 1);
        if qs.len() > 1 && single {
            let ms: Vec<&GroupMean> = qs.iter().map(|q| q.means[0]).collect();
            let cells: usize = ms.iter().map(|h| h.cells).sum();
            let on: usize = ms.iter().map(|h| h.on_side()).sum();
            let mean = ms.iter().map(|h| h.mean_z * h.cells as f64).sum::<f64>() / cells as f64;
            let zmin = ms.iter().map(|h| h.z.abs()).fold(f64::INFINITY, f64::min);
            let groups: Vec<Group> = ms.iter().map(|h| h.group).collect();
            parts.push(format!(
                "{} {} ({}, mean {} σ, every |Z| ≥ {:.1})",
                levels_label(&groups),
                ms[0].group.across(),
                count(on, cells),
                signed(mean),
                zmin
            ));
            continue;
        }
        for q in qs {
            let detail: Vec<String> = q
                .means
                .iter()
                .map(|h| {
                    let name = if q.means.len() > 1 {
                        format!("{} ", h.family.label())
                    } else {
                        String::new()
                    };
                    format!(
                        "{name}{}, mean {} σ, Z = {:.1}",
                        count(h.on_side(), h.cells),
                        signed(h.mean_z),
                        h.z
                    )
                })
                .collect();
            parts.push(format!(
                "{} {} ({})",
                q.means[0].group.label(),
                q.means[0].group.across(),
                detail.join(" / ")
            ));
        }
    }
    parts
}
