//! `surrogate train`: read snapshots → train with cross-validation → save → print validation.
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use surrogate::rom::data::{CaseSet, SnapshotSet};
use surrogate::rom::fidelity::correct_low_fidelity;
use surrogate::rom::held_out_n;
use surrogate::rom::provenance::{BuiltWith, CorrectionInfo};
use surrogate::rom::regression::gp::GpParams;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::train::{HeldOutPoint, TrainReport};
use surrogate::rom::{train, Surrogate, TrainConfig};
use surrogate::schema;
use surrogate::snapshots::merge::sidecar_path;
use surrogate::snapshots::plan::Plan;

use crate::args::TrainArgs;

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

/// The plan beside a snapshot file (`<stem>.plan.json`, written by `snapshots merge`), read,
/// with its path; `None` when there is none.
fn plan_beside(data: &std::path::Path) -> Option<Result<(Plan, std::path::PathBuf)>> {
    let path = sidecar_path(data);
    path.exists().then(|| {
        Plan::read(&path)
            .with_context(|| format!("reading the plan beside the data, {}", path.display()))
            .map(|plan| (plan, path))
    })
}

/// Runs the subcommand: the snapshots read (and corrected by the high fidelity), the learning
/// curve if asked, the surrogate trained, its plan's domain stated, saved and described.
pub fn run(a: TrainArgs) -> Result<()> {
    check_args(&a)?;
    // the sets appended with --add-data are checked before minutes of training
    let appended = appended_built_with(&a)?;
    let set = read_set(&a)?;
    let cfg = train_config(&a);
    let (set, correction) = correct(&a, set, &cfg)?;
    let (source, skipped) = (set.source.clone(), set.skipped_unconverged);
    let cases = set.into_cases()?;
    describe_cases(&source, skipped, &cases, a.fill_truncated);
    if !a.learning_curve.is_empty() {
        learning_curve(&cases, &source, skipped, &cfg, &a.learning_curve)?;
    }
    let held_out_n = hold_out_n(&a, &cases, &source, &cfg)?;
    let mut report = train_with_progress(&cases, &source, skipped, &cfg, a.quiet)?;
    report.surrogate.training.correction = correction;
    report.surrogate.validation.held_out_n = held_out_n;
    match appended {
        Some(built) => {
            report.surrogate.training.built_with = built;
            println!(
                "domain: the box of the cases (of --data and the {} appended)",
                a.add_data.len()
            );
            describe_built_with(&report.surrogate);
        }
        None => state_plan_domain(&a, &cases, &mut report.surrogate)?,
    }
    report
        .surrogate
        .save_new(&a.out, a.force)
        .with_context(|| format!("saving {}", a.out.display()))?;
    describe_model(&report, &a.out);
    write_held_out_outputs(&a, &report)
}

/// With `--hold-out-n`: the errors of a model trained without those numbers of bellows at
/// their cases, printed.
fn hold_out_n(
    a: &TrainArgs,
    cases: &CaseSet,
    source: &str,
    cfg: &TrainConfig,
) -> Result<Option<held_out_n::HeldOutNReport>> {
    if a.hold_out_n.is_empty() {
        return Ok(None);
    }
    eprintln!("holding out N = {:?}: training without them", a.hold_out_n);
    let report = held_out_n::study(cases, source, &a.hold_out_n, cfg, &|_, _| {})?;
    println!(
        "held-out N (model trained without them):\n{}",
        report.table()
    );
    Ok(Some(report))
}

/// The checks made before minutes of training, not after: the output file, the margin, the
/// number of inducing points.
fn check_args(a: &TrainArgs) -> Result<()> {
    surrogate::rom::model::refuse_existing(&a.out, a.force)
        .map_err(|e| anyhow::anyhow!("{e}; give --force to replace it, or another --out"))?;
    anyhow::ensure!(
        a.prefer_poly_within >= 0.0 && a.prefer_poly_within.is_finite(),
        "invalid --prefer-poly-within {}: expected a finite number ≥ 0",
        a.prefer_poly_within
    );
    let inputs = surrogate::case::FEATURE_NAMES.len();
    if let Some(m) = a.inducing {
        anyhow::ensure!(
            m >= 2 * inputs,
            "invalid --inducing {m}: expected at least {} (twice the {inputs} regression inputs)",
            2 * inputs
        );
    }
    Ok(())
}

/// The snapshots of `--data`, or the built-in synthetic set of `--synthetic` cases.
fn read_set(a: &TrainArgs) -> Result<SnapshotSet> {
    Ok(match (&a.data, a.synthetic) {
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
        (Some(path), None) => {
            let mut set = SnapshotSet::read(path)?;
            for more in &a.add_data {
                set.append(SnapshotSet::read(more)?)?;
            }
            set
        }
        (None, None) => anyhow::bail!("give --data or --synthetic"),
    })
}

/// The training settings of the flags.
fn train_config(a: &TrainArgs) -> TrainConfig {
    TrainConfig {
        folds: a.folds,
        seed: a.seed,
        repeats: usize::from(a.repeats),
        pod_tol: a.pod_tol,
        max_field_modes: usize::from(a.max_field_modes),
        max_direct_modes: usize::from(a.max_direct_modes),
        only: a.only.clone(),
        prefer_poly_within: a.prefer_poly_within,
        kernel_per_block: a.kernel_per_block,
        fill_truncated: a.fill_truncated,
        ordinal_n: a.ordinal_n,
        gp: GpParams {
            inducing: a.inducing,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// With `--high-fidelity`: `set` corrected by the high-fidelity snapshots, and how; else
/// `set` as it is.
fn correct(
    a: &TrainArgs,
    set: SnapshotSet,
    cfg: &TrainConfig,
) -> Result<(SnapshotSet, Option<CorrectionInfo>)> {
    let Some(path) = &a.high_fidelity else {
        return Ok((set, None));
    };
    let start = std::time::Instant::now();
    let (set, info) = correct_low_fidelity(
        &set,
        &SnapshotSet::read(path)?,
        cfg,
        a.pressure_warp,
        a.check_high_fidelity,
        &|line| println!("{line}"),
    )?;
    println!(
        "multi-fidelity correction{} in {:.1} s",
        if a.check_high_fidelity {
            " and its end-to-end check"
        } else {
            ""
        },
        start.elapsed().as_secs_f64()
    );
    Ok((set, Some(info)))
}

/// What the snapshots gave as cases (on stderr).
fn describe_cases(source: &str, skipped: usize, cases: &CaseSet, fill_truncated: bool) {
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
        let how = if fill_truncated {
            "used for the regression through gappy POD"
        } else {
            "unused (see --fill-truncated)"
        };
        eprintln!(
            "{} truncated cases cover at least half of the grid: {how}",
            cases.partial.len()
        );
    }
}

/// Trains on `cases` with a progress bar of the fits (hidden with `quiet`).
fn train_with_progress(
    cases: &CaseSet,
    source: &str,
    skipped: usize,
    cfg: &TrainConfig,
    quiet: bool,
) -> Result<TrainReport> {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new((cfg.folds * cfg.repeats.max(1)) as u64 + 1)
    };
    bar.set_style(ProgressStyle::with_template(
        "{msg} [{bar:30}] {pos}/{len} fits ({elapsed})",
    )?);
    bar.set_message("training");
    let report = train(cases, source, skipped, cfg, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    Ok(report)
}

/// With `--add-data`: how the cases of `--data` and of every added set were built (from the
/// plans beside them), when they were all built alike; `None` without `--add-data`.
fn appended_built_with(a: &TrainArgs) -> Result<Option<Option<BuiltWith>>> {
    let (Some(data), false) = (a.data.as_deref(), a.add_data.is_empty()) else {
        return Ok(None);
    };
    let (plan, path) = plan_beside(data).unwrap_or_else(|| {
        Err(anyhow::anyhow!(
            "--add-data needs the plan beside --data ({}), to check that every set was built \
             alike",
            sidecar_path(data).display()
        ))
    })?;
    let mut plans = vec![(plan, path)];
    for more in &a.add_data {
        plans.push(plan_beside(more).unwrap_or_else(|| {
            Err(anyhow::anyhow!(
                "--add-data {}: no plan beside it ({}): expected the plan its cases were run \
                 with, to check they were built as --data's",
                more.display(),
                sidecar_path(more).display()
            ))
        })?);
    }
    let refs: Vec<&Plan> = plans.iter().map(|(p, _)| p).collect();
    let built = BuiltWith::of_plans(&refs).map_err(|i| {
        anyhow::anyhow!(
            "--add-data {}: its plan {} builds its cases otherwise than {} (geometry or fixed \
             effects): expected sets of the same actuator",
            a.add_data[i - 1].display(),
            plans[i].1.display(),
            plans[0].1.display()
        )
    })?;
    Ok(Some(built))
}

/// The domain of the plan beside `--data` stated in the model
/// ([`Surrogate::state_plan_domain`]), when that plan holds every training case.
fn state_plan_domain(a: &TrainArgs, cases: &CaseSet, surrogate: &mut Surrogate) -> Result<()> {
    let Some(plan) = a.data.as_deref().and_then(plan_beside) else {
        return Ok(());
    };
    let (plan, path) = plan?;
    if !surrogate.state_plan_domain(&plan, cases, &path.display().to_string()) {
        eprintln!(
            "warning: {} does not hold every training case: the domain is the box of the \
             cases",
            path.display()
        );
    }
    if let Some(stated) = &surrogate.training.plan_domain {
        let ranges: Vec<String> = stated
            .ranges
            .iter()
            .map(|r| format!("{} {}..{}", r.name, r.min, r.max))
            .collect();
        println!(
            "domain (the plan's nominal ends where its cases reach within one stratum, {}): {}",
            stated.plan,
            ranges.join(", ")
        );
    }
    describe_built_with(surrogate);
    Ok(())
}

/// The model saved to `out`: its validation tables, POD modes, training time and worst
/// held-out cases.
fn describe_model(report: &TrainReport, out: &std::path::Path) {
    let s = &report.surrogate;
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
    if let Some(m) = s.training.gp_inducing {
        println!("GP: sparse on {m} inducing points (exact where a fit had no more cases)");
    }
    println!(
        "trained on {} cases in {:.1} s ({} fits on {} threads; the final fit alone {:.1} s) -> {}",
        s.training.n_cases,
        report.seconds,
        report.fits,
        rayon::current_num_threads(),
        report.final_fit_seconds,
        out.display()
    );
    print_worst(&report.held_out);
}

/// `--held-out` and `--plot`: the held-out predictions as CSV and as a figure.
fn write_held_out_outputs(a: &TrainArgs, report: &TrainReport) -> Result<()> {
    if let Some(path) = &a.held_out {
        write_held_out(path, &report.held_out)?;
        println!("held-out predictions -> {}", path.display());
    }
    if let Some(path) = &a.plot {
        plot_held_out(path, &report.held_out, &report.surrogate.validation.scheme)
            .with_context(|| format!("plotting {}", path.display()))?;
        println!("held-out error plot -> {}", path.display());
    }
    Ok(())
}

/// The case with the largest held-out error of each scalar output.
fn print_worst(points: &[HeldOutPoint]) {
    for (name, _) in OUTPUTS {
        let worst = points.iter().filter(|h| h.output == name).max_by(|a, b| {
            (a.predicted - a.truth)
                .abs()
                .total_cmp(&(b.predicted - b.truth).abs())
        });
        if let Some(h) = worst {
            println!(
                "largest held-out error of {name}: {:+.4} at {} (N = {}, {:.2} bar; FE {:.4}, predicted {:.4} ± {:.4})",
                h.predicted - h.truth,
                h.case_id,
                h.n_bellows,
                h.p_bar,
                h.truth,
                h.predicted,
                h.std
            );
        }
    }
}

const OUTPUTS: [(&str, &str); 4] = [
    (schema::TIP_UZ.name, "tip Uz (mm)"),
    (schema::TIP_UY.name, "tip Uy (mm)"),
    (schema::ANGLE.name, "bending angle (°)"),
    (schema::FORCE.name, "blocked force (N)"),
];

/// The held-out predictions as CSV, written atomically.
fn write_held_out(path: &std::path::Path, points: &[HeldOutPoint]) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "case_id",
        "n_bellows",
        "repeat",
        "fold",
        "pressure_bar",
        "output",
        "fe",
        "predicted",
        "std",
        "error",
    ])?;
    for h in points {
        w.write_record([
            h.case_id.clone(),
            h.n_bellows.to_string(),
            h.repeat.to_string(),
            h.fold.to_string(),
            h.p_bar.to_string(),
            h.output.to_string(),
            h.truth.to_string(),
            h.predicted.to_string(),
            h.std.to_string(),
            (h.predicted - h.truth).to_string(),
        ])?;
    }
    let bytes = w.into_inner().context("CSV buffer")?;
    crate::files::write_file(path, &bytes)?;
    Ok(())
}

/// Held-out error (surrogate − FE) against the FE value, one panel per scalar output, coloured
/// by N; the title gives the pooled RMSE. With several fold assignments only the first one's
/// points are drawn (each case once per pressure; the RMSE pools all of them).
fn plot_held_out(path: &std::path::Path, points: &[HeldOutPoint], scheme: &str) -> Result<()> {
    use plotters::prelude::*;
    let root = SVGBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((2, 2));
    let mut ns: Vec<u32> = points.iter().map(|h| h.n_bellows).collect();
    ns.sort_unstable();
    ns.dedup();
    let repeats = points.iter().map(|h| h.repeat + 1).max().unwrap_or(1);
    let shown = if repeats > 1 {
        format!("; points: fold assignment 1 of {repeats}")
    } else {
        String::new()
    };
    for ((name, label), area) in OUTPUTS.iter().zip(panels.iter()) {
        let pts: Vec<&HeldOutPoint> = points.iter().filter(|h| h.output == *name).collect();
        if pts.is_empty() {
            continue;
        }
        let ((x_lo, x_hi), (e_lo, e_hi)) = held_out_axes(&pts);
        let rmse = (pts
            .iter()
            .map(|h| (h.predicted - h.truth).powi(2))
            .sum::<f64>()
            / pts.len() as f64)
            .sqrt();
        let unit = label
            .rsplit_once('(')
            .map_or("", |(_, u)| u.trim_end_matches(')'));
        let mut c = ChartBuilder::on(area)
            .caption(
                format!("{label}: held-out RMSE {rmse:.3} {unit}"),
                ("sans-serif", 17),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x_lo..x_hi, e_lo..e_hi)?;
        c.configure_mesh()
            .x_desc(format!("FE {label} ({scheme}{shown})"))
            .y_desc(format!("surrogate − FE, held out ({unit})"))
            .draw()?;
        c.draw_series(LineSeries::new(
            vec![(x_lo, 0.0), (x_hi, 0.0)],
            BLACK.mix(0.5),
        ))?;
        for (k, &n) in ns.iter().enumerate() {
            let col = crate::figure::colour(k);
            c.draw_series(
                pts.iter()
                    .filter(|h| h.n_bellows == n && h.repeat == 0)
                    .map(|h| Circle::new((h.truth, h.predicted - h.truth), 3, col.filled())),
            )?
            .label(format!("N = {n}"))
            .legend(move |(x, y)| Circle::new((x, y), 5, col.filled()));
        }
        c.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 13))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// Axis ranges of one held-out panel: the FE values (x) and the errors, symmetric about 0 (y).
fn held_out_axes(pts: &[&HeldOutPoint]) -> ((f64, f64), (f64, f64)) {
    (
        crate::figure::axis_range(pts.iter().map(|h| h.truth)),
        crate::figure::symmetric_range(pts.iter().map(|h| h.predicted - h.truth)),
    )
}

/// The geometry and fixed effects the model states it was built with, printed.
fn describe_built_with(surrogate: &Surrogate) {
    if let Some(built) = &surrogate.training.built_with {
        let effects: Vec<String> = built
            .effects
            .iter()
            .map(|(e, v)| format!("{}={v}", e.name()))
            .collect();
        println!(
            "built with geometry '{}'{}{} (stated in the model: an FE run compared with it must \
             use the same)",
            built.geometry.name,
            if effects.is_empty() { "" } else { " and " },
            effects.join(", ")
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::holds;

    #[test]
    fn held_out_axes_hold_every_point() {
        let p = |truth: f64, predicted: f64| HeldOutPoint {
            case_id: "c".into(),
            n_bellows: 11,
            repeat: 0,
            fold: 0,
            p_bar: 1.0,
            output: "tip_uz_mm",
            truth,
            predicted,
            std: 0.1,
        };
        let pts = [p(-3.0, -2.0), p(95.0, 97.5), p(40.0, 39.0)];
        let refs: Vec<&HeldOutPoint> = pts.iter().collect();
        let (x, e) = held_out_axes(&refs);
        assert!(holds(x, pts.iter().map(|h| h.truth)));
        assert!(holds(e, pts.iter().map(|h| h.predicted - h.truth)));
        assert!(x.0 < -3.0 && x.1 > 95.0 && e.1 > 2.5);
    }
}
