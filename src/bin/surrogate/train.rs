//! `surrogate train`: read snapshots → train with cross-validation → save → print validation.
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::rom::data::{CaseSet, SnapshotSet};
use surrogate::rom::fidelity::{correct, discrepancy, CorrectionInfo};
use surrogate::rom::regression::RegressorKind;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::{train, TrainConfig};

use crate::args::{OnlyArg, TrainArgs};

/// The low-fidelity set corrected by a discrepancy surrogate fitted on the high-fidelity one.
fn correct_set(
    low: &SnapshotSet,
    high: &SnapshotSet,
    cfg: &TrainConfig,
) -> Result<(SnapshotSet, CorrectionInfo)> {
    let delta = discrepancy(low, high)?;
    let source = delta.source.clone();
    let cases = delta.into_cases()?;
    eprintln!(
        "discrepancy {source}: {} cases on a {}-pressure grid ({} dropped)",
        cases.cases.len(),
        cases.pressures.len(),
        cases.dropped.len()
    );
    let report = train(&cases, &source, 0, cfg, &|_, _| {})?;
    println!("discrepancy surrogate (high − low fidelity), held out:");
    println!("{}", report.surrogate.validation.table());
    let (set, replaced_rows, corrected_rows) = correct(low, high, &report.surrogate)?;
    eprintln!("corrected set: {replaced_rows} rows replaced by high fidelity, {corrected_rows} rows corrected");
    let info = CorrectionInfo {
        high_source: high.source.clone(),
        matched_cases: cases.cases.len(),
        replaced_rows,
        corrected_rows,
        validation: report.surrogate.validation,
    };
    Ok((set, info))
}

/// Trains on the first `k` cases (by case id) for each `k` and prints the held-out RMSE of
/// every output: how accuracy grows with the size of the set.
fn learning_curve(
    cases: &CaseSet,
    source: &str,
    skipped: usize,
    cfg: &TrainConfig,
    sizes: &[usize],
) -> Result<()> {
    let mut order: Vec<usize> = (0..cases.cases.len()).collect();
    order.sort_by(|&i, &j| cases.cases[i].case_id.cmp(&cases.cases[j].case_id));
    let mut header = false;
    for &k in sizes {
        anyhow::ensure!(
            (cfg.folds..=cases.cases.len()).contains(&k),
            "invalid --learning-curve size {k}: expected {} to {} (folds to the number of complete cases)",
            cfg.folds,
            cases.cases.len()
        );
        let mut sub = cases.clone();
        sub.cases = order[..k].iter().map(|&i| cases.cases[i].clone()).collect();
        sub.partial.clear();
        let report = train(&sub, source, skipped, cfg, &|_, _| {})?;
        let v = &report.surrogate.validation;
        if !header {
            let names: Vec<&str> = v.outputs.iter().map(|o| o.name.as_str()).collect();
            println!(
                "learning curve ({}, RMSE): cases {}",
                v.scheme,
                names.join(" ")
            );
            header = true;
        }
        let rmse: Vec<String> = v
            .outputs
            .iter()
            .map(|o| format!("{:.4}", o.total.rmse))
            .collect();
        println!("learning curve: {k} {}", rmse.join(" "));
    }
    Ok(())
}

pub fn run(a: TrainArgs) -> Result<()> {
    anyhow::ensure!(
        a.prefer_poly_within >= 0.0 && a.prefer_poly_within.is_finite(),
        "invalid --prefer-poly-within {}: expected a finite number ≥ 0",
        a.prefer_poly_within
    );
    let set = match (&a.data, a.synthetic) {
        (_, Some(n_cases)) => {
            let cfg = SyntheticConfig {
                n_cases,
                n_values: vec![9, 11, 13],
                ..Default::default()
            };
            let mut buf = Vec::new();
            write_csv(&cfg, &mut buf)?;
            SnapshotSet::from_reader(buf.as_slice(), &format!("synthetic({n_cases} cases)"))?
        }
        (Some(path), None) => SnapshotSet::read(path)?,
        (None, None) => anyhow::bail!("give --data or --synthetic"),
    };
    let cfg = TrainConfig {
        folds: a.folds,
        seed: a.seed,
        pod_tol: a.pod_tol,
        only: a.only.map(|o| match o {
            OnlyArg::Gp => RegressorKind::Gp,
            OnlyArg::Poly => RegressorKind::Poly,
        }),
        prefer_poly_within: a.prefer_poly_within,
        fill_truncated: a.fill_truncated,
        ..Default::default()
    };
    let (set, correction) = match &a.high_fidelity {
        Some(path) => {
            let (set, info) = correct_set(&set, &SnapshotSet::read(path)?, &cfg)?;
            (set, Some(info))
        }
        None => (set, None),
    };
    let (source, skipped) = (set.source.clone(), set.skipped_unconverged);
    let cases = set.into_cases()?;
    eprintln!(
        "{source}: {} cases on a {}-pressure grid; {skipped} unconverged rows skipped, {} cases dropped, {} points interpolated, {} off-grid rows ignored",
        cases.cases.len(),
        cases.pressures.len(),
        cases.dropped.len(),
        cases.interpolated_points,
        cases.off_grid_rows
    );
    for (id, why) in &cases.dropped {
        eprintln!("  dropped {id}: {why}");
    }
    if !cases.partial.is_empty() {
        let how = if a.fill_truncated {
            "used for the regression through gappy POD"
        } else {
            "unused (see --fill-truncated)"
        };
        eprintln!(
            "{} truncated cases cover at least half of the grid: {how}",
            cases.partial.len()
        );
    }
    if !a.learning_curve.is_empty() {
        learning_curve(&cases, &source, skipped, &cfg, &a.learning_curve)?;
    }
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(cfg.folds as u64 + 1)
    };
    bar.set_style(ProgressStyle::with_template(
        "{msg} [{bar:30}] {pos}/{len} fits ({elapsed})",
    )?);
    bar.set_message("training");
    let report = train(&cases, &source, skipped, &cfg, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    let mut report = report;
    report.surrogate.training.correction = correction;
    let s = &report.surrogate;
    report
        .surrogate
        .save(&a.out)
        .with_context(|| format!("saving {}", a.out.display()))?;
    println!("{}", s.validation.candidates_table());
    println!("{}", s.validation.table());
    let modes: Vec<String> = s
        .blocks
        .iter()
        .map(|b| {
            format!(
                "{}: {} modes ({})",
                b.name,
                b.pod.n_modes,
                b.regressor.name()
            )
        })
        .collect();
    println!("POD: {}", modes.join(", "));
    println!(
        "trained on {} cases in {:.1} s -> {}",
        s.training.n_cases,
        report.seconds,
        a.out.display()
    );
    Ok(())
}
