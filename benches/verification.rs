//! Runs every FE verification case at every refinement level, prints a table and writes
//! `fe_reference/verification.json`.
//!
//! ```sh
//! cargo bench --bench verification
//! ```
//!
//! The cases and their tolerances live in `tests/common/` and are shared with the
//! `verification_*` tests, which assert them at one refinement level each; here every level is
//! run (the coarser ones are reported for the convergence study, without a tolerance).
//! Exits with an error if an asserted tolerance is not met.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;

use anyhow::{bail, Context};
use common::Check;
use serde::Serialize;

/// Where the results go, relative to the crate root.
const OUTPUT: &str = "fe_reference/verification.json";

/// A verification case: its name and the function running it at every refinement level.
type Case = (&'static str, fn() -> Vec<Check>);

/// The file's content.
#[derive(Serialize)]
struct Report {
    /// The command that regenerates the file.
    command: &'static str,
    /// `relative_error = |computed − reference| / scale`; see each quantity.
    checks: Vec<Check>,
}

fn main() -> anyhow::Result<()> {
    let cases: [Case; 5] = [
        ("homogeneous Ogden stretch", common::homogeneous::study),
        ("patch test", common::patch::study),
        ("Cook's membrane", common::cook::study),
        ("cylinder inflation", common::cylinder::study),
        ("cantilever elastica", common::cantilever::study),
    ];
    println!(
        "{:<30} {:<12} {:<42} {:>14} {:>14} {:>10} {:>6}",
        "case", "refinement", "quantity", "computed", "reference", "rel.error", "tol"
    );
    let mut checks = Vec::new();
    for (name, study) in cases {
        let start = Instant::now();
        let results = study();
        for c in &results {
            println!("{}", c.row());
        }
        println!("-- {name}: {:.1} s", start.elapsed().as_secs_f64());
        checks.extend(results);
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(OUTPUT);
    let report = Report {
        command: "cargo bench --bench verification",
        checks,
    };
    let json = serde_json::to_string_pretty(&report)?;
    std::fs::write(&path, json + "\n").with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    let failed = report.checks.iter().filter(|c| !c.passes()).count();
    if failed > 0 {
        bail!("{failed} asserted checks failed");
    }
    Ok(())
}
