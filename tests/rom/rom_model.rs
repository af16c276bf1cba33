//! Model files (round trip, version, corruption, checksum), validation, queries and domain.
use surrogate::case::{OgdenSet, Query};
use surrogate::rom::{RomError, Surrogate, TrainConfig};

use crate::rom_common;

fn q(n: u32, p: f64) -> Query {
    Query {
        n,
        t_mm: 2.0,
        p_bar: p,
        material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    }
}

#[test]
fn save_load_predict_is_bit_identical() {
    let m = rom_common::small_model(None);
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rom_model_roundtrip");
    let path = dir.join("m.json");
    m.save(&path).unwrap();
    let back = Surrogate::load(&path).unwrap();
    assert_eq!(back, m);
    assert_bit_identical_predictions(&m, &back);
}

/// The two models predict the same bits along a ramp.
fn assert_bit_identical_predictions(m: &Surrogate, back: &Surrogate) {
    for p in [0.0, 0.3, 1.7, 3.5] {
        let (a, b) = (
            m.predict(&q(11, p)).unwrap(),
            back.predict(&q(11, p)).unwrap(),
        );
        for k in 0..22 {
            assert_eq!(a.values[k].to_bits(), b.values[k].to_bits());
        }
    }
}

#[test]
fn load_rejects_version_corruption_and_checksum_mismatch() {
    let m = rom_common::small_model(None);
    let text = m.to_json().unwrap();
    let wrong_version = text.replacen("\"format_version\":3", "\"format_version\":99", 1);
    let e = Surrogate::from_json(&wrong_version, "m.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("format version 99 is not supported") && e.contains("m.json"),
        "{e}"
    );
    let truncated = &text[..text.len() / 2];
    let e = Surrogate::from_json(truncated, "m.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("corrupt or truncated"), "{e}");
    // change one value inside the model: the checksum no longer matches
    let pos = text.find("\"pressures\":[0.0,0.25").unwrap();
    let tampered = format!(
        "{}\"pressures\":[0.0,0.26{}",
        &text[..pos],
        &text[pos + 21..]
    );
    let e = Surrogate::from_json(&tampered, "m.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("checksum mismatch"), "{e}");
    let other = text.replacen("surrogate-rom", "something-else", 1);
    assert!(Surrogate::from_json(&other, "m.json")
        .unwrap_err()
        .to_string()
        .contains("format is"));
}

#[test]
fn validation_is_stored_with_every_output() {
    let m = rom_common::small_model(None);
    let names: Vec<&str> = m
        .validation
        .outputs
        .iter()
        .map(|o| o.name.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "markers_mm",
            "tip_uz_mm",
            "tip_uy_mm",
            "angle_deg",
            "force_n"
        ]
    );
    for o in &m.validation.outputs {
        assert!(
            o.total.rmse > 0.0 && o.total.max_abs >= o.total.rmse && o.total.r2 > 0.99,
            "{o:?}"
        );
        // total² ≈ projection² + regression² (orthogonality in the scaled norm, per block)
        assert!(o.total.rmse <= o.projection_rmse + o.regression_rmse + 1e-12);
    }
    for o in &m.validation.outputs {
        // the std is neither useless nor wildly over- or under-confident on smooth data
        assert!(
            o.std_ratio > 0.1 && o.std_ratio < 10.0,
            "{}: z_rms {}",
            o.name,
            o.std_ratio
        );
    }
    assert!(m.validation.candidates.len() >= 9);
    assert_eq!(m.validation.pressure_interpolation.len(), 5);
    assert!(m.validation.table().contains("tip_uz_mm"));
}

#[test]
fn bad_queries_are_errors_and_out_of_domain_is_flagged() {
    let m = rom_common::small_model(None);
    let e = m.predict(&q(12, 1.0)).unwrap_err();
    assert!(
        matches!(e, RomError::InvalidInput { ref field, .. } if field == "n"),
        "{e}"
    );
    assert!(e.to_string().contains("[9, 11, 13]"));
    let mut bad = q(11, 1.0);
    bad.p_bar = f64::NAN;
    assert!(m.predict(&bad).unwrap_err().to_string().contains("p_bar"));
    bad = q(11, 1.0);
    bad.material.alpha2 = 0.6;
    assert!(m
        .predict(&bad)
        .unwrap_err()
        .to_string()
        .contains("mu2*alpha2"));
    assert!(m.domain_violations(&q(11, 1.0)).is_empty());
    let far = Query {
        t_mm: 3.5,
        p_bar: 4.0,
        ..q(11, 1.0)
    };
    let v: Vec<String> = m
        .domain_violations(&far)
        .iter()
        .map(|d| d.name.clone())
        .collect();
    assert_eq!(v, ["wall_thickness_mm", "pressure_bar"]);
}

#[test]
fn predictions_track_the_synthetic_truth_and_std_is_available() {
    let m = rom_common::small_model(None);
    let held_out = rom_common::synthetic_cases(10, 99);
    let mut pred = m.new_prediction();
    let mut worst: f64 = 0.0;
    for c in &held_out.cases {
        let qq = Query::from_case(&c.inputs, 1.25);
        if !m.domain_violations(&qq).is_empty() {
            continue;
        }
        m.predict_with_std_into(&qq, &mut pred).unwrap();
        let truth = surrogate::rom::synthetic::response(&c.inputs, 1.25);
        worst = worst.max((pred.tip_uz_mm() - truth[18]).abs());
        assert!(pred.has_std && pred.std.iter().all(|s| s.is_finite() && *s >= 0.0));
    }
    assert!(
        worst < 2.0,
        "tip Uz error {worst} mm with 40 training cases"
    );
}

/// The named accessors read the outputs and their standard deviations by the schema's
/// columns, and markers are numbered 1 … 9 as the columns `m1` … `m9` (marker 9 is the tip).
#[test]
fn prediction_names_its_outputs_and_their_std() {
    use surrogate::predict::{marker_uy, marker_uz, ANGLE, FORCE, TIP_UY, TIP_UZ};
    use surrogate::rom::QUANTITY_NAMES;
    let m = rom_common::small_model(None);
    let q = Query::new(
        11,
        2.0,
        1.5,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    let mut p = m.new_prediction();
    m.predict_with_std_into(&q, &mut p).unwrap();
    let by_name = |name: &str| QUANTITY_NAMES.iter().position(|n| *n == name).unwrap();
    assert_eq!(p.tip_uz_mm(), p.values[by_name("tip_uz_mm")]);
    assert_eq!(p.angle_deg(), p.values[ANGLE]);
    assert_eq!(p.std_tip_uz_mm(), p.std[by_name("tip_uz_mm")]);
    assert_eq!(p.std_tip_uy_mm(), p.std[by_name("tip_uy_mm")]);
    assert_eq!(p.std_angle_deg(), p.std[by_name("angle_deg")]);
    assert_eq!(p.std_force_n(), p.std[by_name("force_n")]);
    assert_eq!((TIP_UZ, TIP_UY, FORCE), (18, 19, 21));
    for k in 1..=9 {
        let (z, y) = (
            by_name(&format!("m{k}_uz_mm")),
            by_name(&format!("m{k}_uy_mm")),
        );
        assert_eq!((marker_uz(k), marker_uy(k)), (z, y));
        assert_eq!(p.marker(k), (p.values[z], p.values[y]));
        assert_eq!(p.std_marker(k), (p.std[z], p.std[y]));
    }
    assert!(p.std_angle_deg() > 0.0);
    let mut j = surrogate::rom::Jacobian::default();
    m.gradient_into(&q, &mut p, &mut j).unwrap();
    assert_eq!(j.marker(1).0, j.of(by_name("m1_uz_mm")));
    assert_eq!(j.marker(9).1, j.of(by_name("m9_uy_mm")));
    assert!(std::panic::catch_unwind(|| p.marker(0)).is_err());
    assert!(std::panic::catch_unwind(|| p.std_marker(10)).is_err());
}

#[test]
fn training_does_not_depend_on_the_thread_count() {
    let cases = rom_common::synthetic_cases(24, 3);
    let cfg = surrogate::rom::TrainConfig {
        folds: 3,
        ..Default::default()
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            surrogate::rom::train(&cases, "s", 0, &cfg, &|_, _| {})
                .unwrap()
                .surrogate
        })
    };
    // the POD SVD runs with Par::Seq and the folds are independent tasks
    assert!(
        run(1) == run(2),
        "models trained with 1 and 2 threads differ"
    );
}

/// A first FE set may vary only N and T for one material: the material features are then
/// constant, dropped from the regression, and any other material is out of the domain.
#[test]
fn one_material_and_one_n_train_and_flag_other_materials() {
    use surrogate::rom::data::SnapshotSet;
    use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
    let ogden_002 = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);
    let cfg = SyntheticConfig {
        n_cases: 16,
        n_values: vec![11],
        fixed_material: Some(ogden_002),
        ..Default::default()
    };
    let mut buf = Vec::new();
    write_csv(&cfg, &mut buf).unwrap();
    let cases = SnapshotSet::from_reader(buf.as_slice(), "s")
        .unwrap()
        .into_cases()
        .unwrap();
    let tc = surrogate::rom::TrainConfig {
        folds: 4,
        ..Default::default()
    };
    let m = surrogate::rom::train(&cases, "s", 0, &tc, &|_, _| {})
        .unwrap()
        .surrogate;
    assert_eq!(m.features.index, vec![1], "only T varies");
    assert_eq!(m.n_allowed, vec![11]);
    let qq = q(11, 2.2);
    assert!(m.domain_violations(&qq).is_empty());
    let p = m.predict(&qq).unwrap();
    let truth = surrogate::rom::synthetic::response(
        &surrogate::case::CaseInputs {
            n_bellows: 11,
            wall_thickness_mm: 2.0,
            material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
        },
        2.2,
    );
    assert!(
        (p.tip_uz_mm() - truth[18]).abs() < 0.5,
        "{} vs {}",
        p.tip_uz_mm(),
        truth[18]
    );
    let other = Query {
        material: OgdenSet::from_array([0.13, 3.05, -1214.0, -0.0054]),
        ..qq
    };
    let names: Vec<String> = m
        .domain_violations(&other)
        .iter()
        .map(|d| d.name.clone())
        .collect();
    // the material is checked in the regression's coordinates (μ0, s, α₁, α₂), which are
    // constant here: another material is outside in each of them it changes
    assert_eq!(
        names,
        ["mu0_mpa", "term1_share", "alpha1", "alpha2"],
        "{names:?}"
    );
    let mut pred = m.new_prediction();
    let mut jac = surrogate::rom::Jacobian::default();
    m.gradient_into(&qq, &mut pred, &mut jac).unwrap();
    assert!(
        jac.d[18][2] == 0.0 && jac.d[18][0] != 0.0,
        "no material sensitivity without material data"
    );
}

/// Truncated ramps (unconverged last steps) can feed the regression through gappy POD.
#[test]
fn truncated_ramps_fill_the_regression_through_gappy_pod() {
    use surrogate::rom::data::SnapshotSet;
    use surrogate::rom::synthetic::{response, write_csv, SyntheticConfig};
    let cfg = SyntheticConfig {
        n_cases: 40,
        unconverged_fraction: 0.3,
        ..Default::default()
    };
    let mut buf = Vec::new();
    write_csv(&cfg, &mut buf).unwrap();
    let cases = SnapshotSet::from_reader(buf.as_slice(), "s")
        .unwrap()
        .into_cases()
        .unwrap();
    assert!(!cases.partial.is_empty() && cases.partial.len() == cases.dropped.len());
    let truncated = cases.partial.clone();
    let train = |fill: bool| {
        let tc = surrogate::rom::TrainConfig {
            folds: 3,
            fill_truncated: fill,
            ..Default::default()
        };
        surrogate::rom::train(&cases, "s", 0, &tc, &|_, _| {})
            .unwrap()
            .surrogate
    };
    let (without, with) = (train(false), train(true));
    assert_eq!(
        (without.training.filled_cases, with.training.filled_cases),
        (0, truncated.len())
    );
    // at the truncated cases' own inputs, the model that saw their converged part is closer
    let err = |m: &Surrogate| {
        let mut worst: f64 = 0.0;
        for c in &truncated {
            for p in [1.0, 3.5] {
                let truth = response(&c.inputs, p);
                let pred = m.predict(&Query::from_case(&c.inputs, p)).unwrap();
                worst = worst.max((pred.tip_uz_mm() - truth[18]).abs());
            }
        }
        worst
    };
    let (e0, e1) = (err(&without), err(&with));
    println!(
        "worst tip Uz error at truncated cases: without {e0:.3} mm, with gappy fill {e1:.3} mm"
    );
    assert!(
        e1 < 1.0 && e1 <= e0 * 1.05,
        "worst tip Uz error: without {e0}, with gappy fill {e1}"
    );
}

/// After the CV rescaling, the std is calibrated on fresh held-out cases (RMS z ≈ 1).
#[test]
fn calibrated_std_matches_fresh_held_out_errors() {
    let m = rom_common::small_model(None);
    assert!(m.std_scale.iter().all(|s| *s > 0.0));
    let fresh = rom_common::synthetic_cases(30, 2025);
    let mut pred = m.new_prediction();
    let (mut z2, mut n) = (0.0, 0usize);
    for c in &fresh.cases {
        for p in [0.5, 1.5, 2.5, 3.5] {
            let qq = Query::from_case(&c.inputs, p);
            if !m.domain_violations(&qq).is_empty() {
                continue;
            }
            m.predict_with_std_into(&qq, &mut pred).unwrap();
            let truth = surrogate::rom::synthetic::response(&c.inputs, p);
            for k in [18, 19, 20, 21] {
                z2 += ((truth[k] - pred.values[k]) / pred.std[k]).powi(2);
                n += 1;
            }
        }
    }
    let z_rms = (z2 / n as f64).sqrt();
    println!("fresh held-out z_rms {z_rms:.2} over {n} values");
    assert!(n > 50 && z_rms > 0.4 && z_rms < 2.5, "z_rms {z_rms}");
}

#[test]
fn held_out_points_reproduce_the_stored_validation() {
    let cases = rom_common::synthetic_cases(40, 7);
    let cfg = TrainConfig {
        folds: 3,
        ..Default::default()
    };
    let report = surrogate::rom::train(&cases, "synthetic", 0, &cfg, &|_, _| {}).unwrap();
    let v = &report.surrogate.validation;
    let n_points = cases.cases.len() * cases.pressures.len();
    assert_eq!(report.held_out.len(), 4 * n_points);
    for o in &v.outputs[1..] {
        let pts: Vec<_> = report
            .held_out
            .iter()
            .filter(|h| h.output == o.name)
            .collect();
        assert_eq!(pts.len(), n_points, "{}", o.name);
        let rmse = (pts
            .iter()
            .map(|h| (h.predicted - h.truth).powi(2))
            .sum::<f64>()
            / pts.len() as f64)
            .sqrt();
        let max = pts
            .iter()
            .map(|h| (h.predicted - h.truth).abs())
            .fold(0.0, f64::max);
        assert!(
            (rmse - o.total.rmse).abs() <= 1e-9 * o.total.rmse,
            "{}: {rmse} vs {}",
            o.name,
            o.total.rmse
        );
        assert!((max - o.total.max_abs).abs() <= 1e-9 * o.total.max_abs);
        // each case is held out by exactly one fold, and its truth is the FE value
        for h in &pts {
            let c = cases.cases.iter().find(|c| c.case_id == h.case_id).unwrap();
            let p = cases.pressures.iter().position(|&p| p == h.p_bar).unwrap();
            let q = surrogate::rom::QUANTITY_NAMES
                .iter()
                .position(|&n| n == h.output)
                .unwrap();
            assert_eq!(h.truth, c.values[p][q]);
            assert!(h.fold < 3 && h.std.is_finite() && h.std >= 0.0);
        }
        // a std where the output varies (it is 0 only where every case has the same value)
        assert!(pts.iter().filter(|h| h.std > 0.0).count() >= pts.len() / 2);
    }
}

/// Repeated k-fold: every repeat holds each case out exactly once, the stored errors pool all
/// repeats' held-out predictions, and the final fit does not depend on the folds.
#[test]
fn repeated_folds_pool_every_assignment() {
    use std::collections::BTreeMap;
    let cases = rom_common::synthetic_cases(24, 5);
    let run = |repeats: usize| {
        let cfg = surrogate::rom::TrainConfig {
            folds: 3,
            repeats,
            ..Default::default()
        };
        surrogate::rom::train(&cases, "s", 0, &cfg, &|_, _| {}).unwrap()
    };
    let (one, three) = (run(1), run(3));
    assert_eq!(three.held_out.len(), 3 * one.held_out.len());
    assert!(three
        .surrogate
        .validation
        .scheme
        .contains("3 fold assignments"));
    assert_eq!(one.surrogate.regressors, three.surrogate.regressors);
    assert_eq!(one.surrogate.blocks, three.surrogate.blocks);
    // each (case, repeat) has one fold; each (case, repeat, output, pressure) appears once
    let mut fold_of: BTreeMap<(String, usize), usize> = BTreeMap::new();
    let mut seen = std::collections::BTreeSet::new();
    for h in &three.held_out {
        let f = *fold_of
            .entry((h.case_id.clone(), h.repeat))
            .or_insert(h.fold);
        assert_eq!(f, h.fold);
        assert!(seen.insert((h.case_id.clone(), h.repeat, h.output, h.p_bar.to_bits())));
    }
    assert_eq!(fold_of.len(), 3 * cases.cases.len());
    let moved = cases
        .cases
        .iter()
        .filter(|c| fold_of[&(c.case_id.clone(), 0)] != fold_of[&(c.case_id.clone(), 1)])
        .count();
    assert!(moved > 0, "the repeats drew the same folds");
    // the stored RMSE of each scalar is the RMS over all repeats' held-out predictions
    for v in &three.surrogate.validation.outputs[1..] {
        let e: Vec<f64> = three
            .held_out
            .iter()
            .filter(|h| h.output == v.name)
            .map(|h| h.predicted - h.truth)
            .collect();
        let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        assert!(
            (rms - v.total.rmse).abs() <= 1e-12 * (1.0 + rms),
            "{}: {rms} vs stored {}",
            v.name,
            v.total.rmse
        );
    }
}

/// A model with one GP kernel per POD block: save → load → predict is bit-identical, each
/// block has its own length scales, and column groups that do not match the tables or that
/// split a block are rejected by the consistency check.
#[test]
fn kernel_per_block_round_trip_and_consistency() {
    use surrogate::rom::regression::gp::Gp;
    let m = rom_common::grouped_model();
    let gp = m.regressors.get::<Gp>().unwrap();
    assert_eq!(gp.n_groups(), m.blocks.len());
    for (g, b) in m.blocks.iter().enumerate() {
        assert_eq!(gp.group_columns(g).start, b.coef_offset);
    }
    assert_ne!(gp.group_inv_len(0), gp.group_inv_len(1));
    let text = m.to_json().unwrap();
    assert!(text.contains("\"groups\":["));
    let back = Surrogate::from_json(&text, "m.json").unwrap();
    assert_eq!(back, m);
    assert_bit_identical_predictions(&m, &back);
    // a single-kernel model writes no groups (files of earlier builds read the same)
    assert!(!rom_common::small_model(None)
        .to_json()
        .unwrap()
        .contains("\"groups\""));
    let mut split = m.clone();
    split.regressors.get_mut::<Gp>().unwrap().groups[1] += 1;
    let e = split.check_consistency().unwrap_err();
    assert!(
        e.contains("column groups") && e.contains("do not split a block"),
        "{e}"
    );
    let mut short = m.clone();
    short.regressors.get_mut::<Gp>().unwrap().inv_len.pop();
    assert!(short
        .check_consistency()
        .unwrap_err()
        .contains("inconsistent sizes"));
}
