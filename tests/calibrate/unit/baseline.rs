//! The unit tests of `src/calibrate/baseline/mod.rs`.
//!
//! Tests of the sweep: the order of its queue, the committed caches read under their keys, the
//! reference study's nine and the summary, the sensitivities file with its geometry. (A cached
//! ramp reused only under its own key: `surrogate::fe::runner`'s, `tests/fe/unit/runner.rs`.)

use std::path::{Path, PathBuf};

use surrogate::calibrate::baseline::*;
use surrogate::fe::effects::Effects;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;
use surrogate::fe::simulate::Mode;

#[test]
fn the_queue_starts_thin_walls_and_forces_first_and_returns_in_item_order() {
    let designs: Vec<SweepDesign> = [(9, 2.4), (13, 1.6), (11, 2.0), (13, 2.4)]
        .iter()
        .map(|&(n, t)| SweepDesign {
            n_bellows: n,
            wall_thickness_mm: t,
            pressures_bar: vec![0.0, 1.0],
        })
        .collect();
    let jobs: Vec<(&SweepDesign, Mode)> = designs
        .iter()
        .flat_map(|d| [(d, Mode::Bending), (d, Mode::Force)])
        .collect();
    let order = cost_order(&jobs);
    let first: Vec<(usize, f64, Mode)> = order
        .iter()
        .take(3)
        .map(|&i| (jobs[i].0.n_bellows, jobs[i].0.wall_thickness_mm, jobs[i].1))
        .collect();
    assert_eq!(
        first,
        vec![
            (13, 1.6, Mode::Force),
            (13, 1.6, Mode::Bending),
            (11, 2.0, Mode::Force)
        ]
    );
    let started = std::sync::Mutex::new(Vec::new());
    let out = surrogate::fe::runner::in_order(&jobs, &order, |&(d, m)| {
        started
            .lock()
            .unwrap()
            .push((d.n_bellows, m == Mode::Force));
        (d.n_bellows, d.wall_thickness_mm, m)
    });
    let expected: Vec<(usize, f64, Mode)> = jobs
        .iter()
        .map(|&(d, m)| (d.n_bellows, d.wall_thickness_mm, m))
        .collect();
    assert_eq!(out, expected);
    assert_eq!(started.into_inner().unwrap().len(), jobs.len());
}

fn committed(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The committed literature baseline is read from its cache: every ramp's key is the one
/// written before the settings were gathered and effects existed; an effect changes the
/// key (nothing read), a neutral one given explicitly does not.
#[test]
fn committed_baseline_ramps_keep_their_keys() {
    let bending = surrogate::calibrate::experiments::shipped_bending().unwrap();
    let designs = recorded_designs(&bending);
    assert_eq!(designs.len(), 9);
    assert_eq!(designs[0].pressures_bar, [0.0, 1.0, 2.0, 3.0]);
    let dir = committed("fe_reference/baseline/ogden_002_standard_ramps");
    let material = Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap();
    let mut settings = SweepSettings::new(material, MeshOptions::level(MeshLevel::Standard));
    let sources = |s: &SweepSettings| -> Vec<RampSource> {
        cached_ramps(s, &designs, &dir)
            .unwrap()
            .iter()
            .map(|r| r.source)
            .collect()
    };
    assert_eq!(sources(&settings), vec![RampSource::Cache; 18]);
    settings.effects = Effects::parse(["wall_bias=0"]).unwrap();
    assert_eq!(sources(&settings), vec![RampSource::Cache; 18]);
    settings.effects = Effects::parse(["wall_bias=0.1"]).unwrap();
    assert_eq!(sources(&settings), vec![RampSource::Missing; 18]);
    // another geometry: every dimension is in the key, nothing read; the historical one
    // given explicitly keeps the keys
    settings.effects = Effects::default();
    settings.geometry = Geometry {
        name: "other".into(),
        side_wall_mm: Some(2.0),
        ..Geometry::as_modelled()
    };
    assert_eq!(sources(&settings), vec![RampSource::Missing; 18]);
    settings.geometry = Geometry::as_modelled();
    assert_eq!(sources(&settings), vec![RampSource::Cache; 18]);
    // the rows of the table: every configuration reached
    let force = surrogate::calibrate::experiments::shipped_force().unwrap();
    settings.effects = Effects::default();
    let rows = cached_baseline(&settings, &bending, &force, &dir).unwrap();
    assert!(rows
        .iter()
        .all(|r| r.error.is_empty() && r.be_mm.is_finite()));
}

/// The committed standard-mesh verification of the set calibrated through the shipped model
/// (what `demo` and `calibrate --verify-fe standard --fe-cache …` read), built as the model's
/// training cases were (the identified geometry, the force rig's plate), is found whole in its
/// cache.
#[test]
fn committed_verification_ramps_keep_their_keys() {
    let model = surrogate::rom::Surrogate::load(&committed("models/actuator.json")).unwrap();
    // the set of the committed calibration as reported (4 significant digits), as `demo` and
    // `calibrate --verify-fe` run it
    let report = committed("fe_reference/identification/shipped_surrogate/report.json");
    let set = surrogate::rom::batch::material_params(report.to_str().unwrap())
        .unwrap()
        .rounded(4);
    let material = surrogate::calibrate::verify::fe_material(&set).unwrap();
    let settings = SweepSettings::new(material, MeshOptions::level(MeshLevel::Standard))
        .built_as(model.training.built_with.as_ref());
    let bending = surrogate::calibrate::experiments::shipped_bending().unwrap();
    let dir = committed("data/demo/fe_standard_ramps");
    let ramps = cached_ramps(&settings, &recorded_designs(&bending), &dir).unwrap();
    assert_eq!(ramps.len(), 18);
    assert!(ramps.iter().all(|r| r.source == RampSource::Cache));
}

fn row(n: usize, t: f64, p: f64, be: f64, force_error: f64) -> BaselineRow {
    BaselineRow {
        n_bellows: n,
        wall_thickness_mm: t,
        pressure_bar: p,
        uz_exp_mm: 0.0,
        uz_sim_mm: 0.0,
        uy_exp_mm: 0.0,
        uy_sim_mm: 0.0,
        angle_exp_deg: 0.0,
        angle_sim_deg: 0.0,
        be_mm: be,
        force_exp_n: 0.0,
        force_sim_n: 0.0,
        force_error_n: force_error,
        error: String::new(),
    }
}

#[test]
fn the_paper_nine_move_t_and_p_together_for_each_n() {
    let (ns, ts, ps) = ([9, 11, 13], [1.6, 2.0, 2.4], [1.0, 2.0, 3.0]);
    let mut chosen = Vec::new();
    for &n in &ns {
        for &t in &ts {
            for &p in &ps {
                if in_paper_nine(&ns, &ts, &ps, n, t, p).unwrap() {
                    chosen.push((n, t, p));
                }
            }
        }
    }
    assert_eq!(chosen.len(), 9);
    for &n in &ns {
        for (t, p) in [(1.6, 1.0), (2.0, 2.0), (2.4, 3.0)] {
            assert!(chosen.contains(&(n, t, p)), "N = {n}, T = {t}, P = {p}");
        }
    }
    assert_eq!(in_paper_nine(&ns, &ts, &ps, 10, 2.0, 1.0), None);
    assert!(!in_paper_nine(&ns, &ts, &ps, 9, 1.6, 2.0).unwrap());
}

#[test]
fn summary_separates_the_paper_nine_and_the_top_pressure() {
    let mut rows = Vec::new();
    for n in [9, 11, 13] {
        for t in [1.6, 2.0, 2.4] {
            for p in [1.0, 2.0, 3.0] {
                // BE 1 inside the L9 subset and 4 outside; force error p − 2
                let l9 = in_paper_nine(&[9, 11, 13], &[1.6, 2.0, 2.4], &[1.0, 2.0, 3.0], n, t, p)
                    .unwrap();
                rows.push(row(n, t, p, if l9 { 1.0 } else { 4.0 }, p - 2.0));
            }
        }
    }
    rows[0].be_mm = f64::NAN;
    rows[0].error = "stopped".into();
    let s = summarize(&rows);
    assert_eq!(
        (s.configurations, s.failed, s.paper_nine_configurations),
        (27, 1, 9)
    );
    assert!((s.paper_nine_mean_be_mm - 1.0).abs() < 1e-12);
    assert!((s.mean_be_mm - (8.0 * 1.0 + 18.0 * 4.0) / 26.0).abs() < 1e-12);
    assert!((s.mean_force_error_top_pressure_n - 1.0).abs() < 1e-12);
    assert!(s.mean_force_error_n.abs() < 1e-12);
    assert_eq!(s.top_pressure_bar, 3.0);
}

/// The committed sensitivities (written before the sweep's geometry was recorded) read as of
/// the geometry as modelled and write back byte for byte; another geometry is written and
/// read back.
#[test]
fn sensitivities_keep_their_geometry_and_old_files_read_as_modelled() {
    for f in [
        "data/sensitivities/calibrated_coarse.json",
        "data/sensitivities/ogden002_coarse.json",
    ] {
        let path = committed(f);
        let s = SweepSensitivities::read(&path).unwrap();
        assert_eq!(s.geometry, Geometry::as_modelled());
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(serde_json::to_string(&s).unwrap(), text.trim_end(), "{f}");
    }
    let mut s =
        SweepSensitivities::read(&committed("data/sensitivities/ogden002_coarse.json")).unwrap();
    s.geometry = Geometry {
        name: "identified".into(),
        gap_mm: 1.2,
        side_wall_mm: Some(1.4),
        ..Geometry::as_modelled()
    };
    s.effects = Effects::neutral()
        .with(surrogate::fe::effects::Effect::PlateOffset, -4.5)
        .unwrap();
    let text = serde_json::to_string(&s).unwrap();
    assert!(text.contains(r#""geometry":{"name":"identified","gap_mm":1.2,"#));
    let dir = std::env::temp_dir().join(format!("sweep_geometry_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sensitivities.json");
    std::fs::write(&path, &text).unwrap();
    let back = SweepSensitivities::read(&path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(back, s);
    assert_eq!(back.base(surrogate::fe::effects::Effect::PlateOffset), -4.5);
}
