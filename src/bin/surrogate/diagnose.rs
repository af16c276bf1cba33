//! `surrogate diagnose`: calibrate, then locate the residual ([`surrogate::diagnose`]); the
//! report as JSON and Markdown, and its figures.
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use surrogate::calibrate::experiments::{BENDING_FILE, FORCE_FILE, MARKERS_FILE};
use surrogate::calibrate::objective::Exclusion;
use surrogate::calibrate::{CalibrationSettings, Recordings, Selection, Weights};
use surrogate::diagnose::summary::summary_markdown;
use surrogate::diagnose::{diagnose, DiagnoseSettings, Diagnosis, LocateSettings};

use crate::args::DiagnoseArgs;
use crate::diagnose_plots::write_plots;
use crate::files::{load_model, write_file};

/// The validated settings of the run.
fn settings(a: &DiagnoseArgs) -> Result<DiagnoseSettings> {
    let exclude = a
        .exclude
        .iter()
        .map(|e| Exclusion::parse(e))
        .collect::<Result<Vec<_>, _>>()?;
    let locate = LocateSettings { alpha: a.alpha };
    locate.validate()?;
    Ok(DiagnoseSettings {
        calibration: CalibrationSettings {
            weights: Weights::parse(&a.objective)?,
            selection: Selection {
                exclude,
                ..Selection::default()
            },
            exclude_flagged: a.exclude_flagged,
            ..CalibrationSettings::default()
        },
        locate,
    })
}

/// The recordings of `dir`; a path that is not a directory says what was expected there.
fn recordings(dir: &Path) -> Result<Recordings> {
    if !dir.is_dir() {
        anyhow::bail!(
            "--recordings {}: not a directory (expected a directory holding {BENDING_FILE} and, \
             where recorded, {FORCE_FILE} and {MARKERS_FILE}, like training_data/)",
            dir.display()
        );
    }
    Recordings::read_dir(dir)
        .with_context(|| format!("reading the recordings in {}", dir.display()))
}

/// Runs the subcommand.
pub fn run(a: DiagnoseArgs) -> Result<()> {
    let s = settings(&a)?;
    let rec = recordings(&a.recordings)?;
    let model = load_model(&a.model)?;
    let d = diagnose(&model, &rec, &s, &|stage| eprintln!("{stage}"))?;
    let written = write_outputs(&a.out, &d)?;
    println!("Findings:");
    for f in &d.locate.findings {
        println!("- {}", f.text);
    }
    if !d.locate.missing.is_empty() {
        println!("Not in the recordings:");
        for m in &d.locate.missing {
            println!("- {}", m.what);
        }
    }
    println!("Name (candidate physics): not run in this version.");
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Writes diagnosis.json, summary.md and the figures (each atomically).
pub fn write_outputs(dir: &Path, d: &Diagnosis) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut written = Vec::new();
    let p = dir.join("diagnosis.json");
    write_file(&p, d.to_json()?.as_bytes())?;
    written.push(p);
    let p = dir.join("summary.md");
    write_file(&p, summary_markdown(d).as_bytes())?;
    written.push(p);
    written.extend(write_plots(&d.locate, dir)?);
    Ok(written)
}
