//! `surrogate effects`: the effect library as a table or JSON.

use std::io::Write;

use serde::Serialize;
use surrogate::fe::effects::{Acts, EffectInfo, Kind, BUILTIN_EFFECTS};

use crate::args::EffectsArgs;

/// One effect as listed: its name, its description and its rig.
#[derive(Serialize)]
struct Entry {
    effect: &'static str,
    #[serde(flatten)]
    info: &'static EffectInfo,
    acts_on: Acts,
}

/// Prints the library.
pub fn run(a: EffectsArgs) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    if a.json {
        let entries: Vec<Entry> = BUILTIN_EFFECTS
            .iter()
            .map(|e| Entry {
                effect: e.name(),
                info: e.info(),
                acts_on: e.acts_on(),
            })
            .collect();
        writeln!(out, "{}", serde_json::to_string_pretty(&entries)?)?;
        return Ok(());
    }
    writeln!(
        out,
        "{:<24} {:<7} {:>7} {:>15}  {:<7} {:<10} meaning",
        "name", "unit", "neutral", "range", "rig", "kind"
    )?;
    for &effect in BUILTIN_EFFECTS {
        let e = effect.info();
        let rig = match effect.acts_on() {
            Acts::Both => "both",
            Acts::Force => "force",
        };
        let kind = match e.kind {
            Kind::Tolerance => "tolerance",
            Kind::Unstated => "unstated",
        };
        writeln!(
            out,
            "{:<24} {:<7} {:>7} {:>15}  {:<7} {:<10} {}",
            e.name,
            e.unit,
            e.neutral,
            format!("[{}, {}]", e.range.0, e.range.1),
            rig,
            kind,
            e.meaning
        )?;
    }
    writeln!(
        out,
        "\ntolerance: a print or rig error around a value the reference study states; unstated: a \
         dimension it does not state, over its physically possible range (--json gives each \
         entry's source: the study's sentence or its silence)"
    )?;
    writeln!(
        out,
        "\nuse: surrogate simulate --effect NAME=VALUE [--effect …]; docs: surrogate::fe::effects"
    )?;
    Ok(())
}
