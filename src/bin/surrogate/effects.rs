//! `surrogate effects`: the effect library as a table or JSON.

use std::io::Write;

use surrogate::fe::effects::{Acts, EFFECTS};

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
        "{:<24} {:<7} {:>7} {:>15}  {:<7} meaning",
        "name", "unit", "neutral", "range", "rig"
    )?;
    for e in &EFFECTS {
        let rig = match e.acts_on {
            Acts::Both => "both",
            Acts::Force => "force",
        };
        writeln!(
            out,
            "{:<24} {:<7} {:>7} {:>15}  {:<7} {}",
            e.name,
            e.unit,
            e.neutral,
            format!("[{}, {}]", e.range.0, e.range.1),
            rig,
            e.meaning
        )?;
    }
    writeln!(
        out,
        "\nuse: surrogate simulate --effect NAME=VALUE [--effect …]; docs: surrogate::fe::effects"
    )?;
    Ok(())
}
