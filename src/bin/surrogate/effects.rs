//! `surrogate effects`: the effect library as a table or JSON.

use std::io::Write;

use surrogate::fe::effects::{Acts, Kind, EFFECTS};

use crate::args::EffectsArgs;

/// Prints the library.
pub fn run(a: EffectsArgs) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    if a.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&EFFECTS)?)?;
        return Ok(());
    }
    writeln!(
        out,
        "{:<24} {:<7} {:>7} {:>15}  {:<7} {:<10} meaning",
        "name", "unit", "neutral", "range", "rig", "kind"
    )?;
    for e in &EFFECTS {
        let rig = match e.acts_on {
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
