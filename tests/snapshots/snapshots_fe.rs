//! The snapshot machinery with the real FE runner on a tiny problem (N = 7, coarse mesh with
//! 20 mm elements, gravity, 0 and 0.5 bar): a failing case is recorded with the solver's error,
//! and stored values reproduce to 1e-9 when cases are re-simulated.

use std::path::PathBuf;

use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{simulate, Case};
use surrogate::snapshots::fe_runner::fe_runner;
use surrogate::snapshots::run::Progress;
use surrogate::snapshots::verify::resimulate;
use surrogate::snapshots::{merge, run_shard, Plan, PlanSettings, Ranges, RunOptions, Shard};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "surrogate_snapshots_fe_{name}_{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A plan of `cases` tiny FE cases with N = 7.
fn tiny_plan(cases: usize, seed: u64, edit: impl FnOnce(&mut PlanSettings)) -> Plan {
    let mut settings = PlanSettings {
        pressures_bar: vec![0.0, 0.5],
        mesh: MeshOptions {
            level: MeshLevel::Coarse,
            element_size: Some(20.0),
            wall_elements: None,
        },
        ..PlanSettings::default()
    };
    edit(&mut settings);
    let ranges = Ranges {
        n_bellows: vec![7],
        ..Ranges::default()
    };
    Plan::generate(cases, seed, ranges, settings).unwrap()
}

fn run_all(plan: &Plan, dir: &std::path::Path, threads: usize) {
    let options = RunOptions {
        shard: Shard::ALL,
        threads: Some(threads),
        retry_failed: false,
    };
    run_shard(plan, dir, &options, &fe_runner, &|_: Progress| {}).unwrap();
}

#[test]
fn a_failing_fe_case_is_recorded_with_the_solver_error() {
    let root = scratch("fail");
    let plan = tiny_plan(1, 1, |s| {
        s.solver.max_iterations = 1;
        s.solver.max_cutbacks = 0;
    });
    let dir = root.join("d");
    run_all(&plan, &dir, 1);
    let text = std::fs::read_to_string(dir.join("cases/case_000000.csv")).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 2);
    for r in rows {
        assert!(r.contains(",false,NaN,") && r.contains("bending: "), "{r}");
    }
    std::fs::remove_dir_all(root).unwrap();
}

/// Runs a plan of 4 tiny FE cases, then (1) re-runs 3 cases chosen at random with the plan
/// (`snapshots::verify`) and (2) rebuilds one case from nothing but its CSV rows (inputs and
/// provenance columns) and runs `fe::simulate` on it; every stored output must agree to 1e-9.
/// About 3 minutes on 2 busy cores, hence ignored:
/// `cargo test --release --test snapshots -- --ignored`.
#[test]
#[ignore = "real FE, about 3 minutes; run: cargo test --release --test snapshots -- --ignored fe_snapshots_reproduce_when_re_simulated"]
fn fe_snapshots_reproduce_when_re_simulated() {
    let root = scratch("reproduce");
    let plan = tiny_plan(4, 5, |_| {});
    let dir = root.join("d");
    run_all(&plan, &dir, 2);
    let out = root.join("fe.csv");
    let summary = merge(&[dir], &out).unwrap();
    assert_eq!((summary.cases, summary.failed_cases), (4, 0));

    let checks = resimulate(&out, &plan, 3, 2024, &fe_runner).unwrap();
    assert_eq!(checks.len(), 3);
    for c in &checks {
        assert!(c.same_convergence, "{c:?}");
        assert!(c.max_abs_diff <= 1e-9, "{c:?}");
    }

    // one case from the CSV alone
    let mut rdr = csv::Reader::from_path(&out).unwrap();
    let header = rdr.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = rdr.records().map(|r| r.unwrap()).collect();
    let f = |r: &csv::StringRecord, name: &str| r[col(name)].parse::<f64>().unwrap();
    let chunk = &rows[2 * plan.settings.pressures_bar.len()..3 * plan.settings.pressures_bar.len()];
    let r0 = &chunk[0];
    let material = format!(
        "{},{},{},{}",
        &r0[col("mu1_mpa")],
        &r0[col("alpha1")],
        &r0[col("mu2_mpa")],
        &r0[col("alpha2")]
    );
    let case = Case {
        design: DesignParams::new(
            r0[col("n_bellows")].parse().unwrap(),
            f(r0, "wall_thickness_mm"),
        )
        .validate()
        .unwrap(),
        material: Material::from_spec(&material, f(r0, "bulk_ratio")).unwrap(),
        pressures_bar: chunk.iter().map(|r| f(r, "pressure_bar")).collect(),
        gravity: &r0[col("gravity")] == "true",
        mesh: MeshOptions {
            level: r0[col("mesh")].parse().unwrap(),
            element_size: Some(f(r0, "element_size_mm")),
            wall_elements: None,
        },
        solver: surrogate::fe::solver::SolverSettings {
            rtol: f(r0, "solver_rtol"),
            ..Default::default()
        },
        mode: surrogate::fe::simulate::Mode::Bending,
        contact: Default::default(),
        effects: Default::default(),
    };
    let again = simulate(&case).unwrap();
    assert_eq!(again.steps.len(), chunk.len());
    for (row, step) in chunk.iter().zip(&again.steps) {
        assert_eq!(&row[col("converged")], "true");
        let mut pairs = vec![
            (f(row, "tip_uz_mm"), step.tip_uz_mm),
            (f(row, "tip_uy_mm"), step.tip_uy_mm),
            (f(row, "angle_deg"), step.angle_deg),
        ];
        for (k, m) in step.markers.iter().enumerate() {
            pairs.push((f(row, &format!("m{}_uz_mm", k + 1)), m[0]));
            pairs.push((f(row, &format!("m{}_uy_mm", k + 1)), m[1]));
        }
        for (stored, fresh) in pairs {
            assert!(
                (stored - fresh).abs() <= 1e-9,
                "{}: {stored} vs {fresh}",
                &row[0]
            );
        }
    }
    std::fs::remove_dir_all(root).unwrap();
}
