//! `N` as an ordinal input: a model trained with `ordinal_n` predicts every integer `N`
//! between its trained ends and says which it was trained at; the held-out-`N` study measures
//! how well it interpolates, and refuses to extrapolate.

use surrogate::case::{OgdenSet, Query};
use surrogate::rom::data::CaseSet;
use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
use surrogate::rom::{held_out_n, train, RomError, SnapshotSet, Surrogate, TrainConfig};

const OGDEN_002: OgdenSet = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);

fn set(n_values: Vec<u32>, n_cases: usize) -> CaseSet {
    let cfg = SyntheticConfig {
        n_cases,
        n_values,
        ..Default::default()
    };
    let mut buf = Vec::new();
    write_csv(&cfg, &mut buf).unwrap();
    SnapshotSet::from_reader(buf.as_slice(), "synthetic")
        .unwrap()
        .into_cases()
        .unwrap()
}

fn model(cases: &CaseSet, ordinal_n: bool) -> Surrogate {
    let cfg = TrainConfig {
        folds: 4,
        ordinal_n,
        ..Default::default()
    };
    train(cases, "synthetic", 0, &cfg, &|_, _| {})
        .unwrap()
        .surrogate
}

#[test]
fn an_ordinal_model_predicts_between_its_trained_n_and_says_which_it_trained() {
    let cases = set(vec![9, 11, 13], 36);
    let discrete = model(&cases, false);
    let ordinal = model(&cases, true);
    let q10 = Query::new(10, 2.0, 2.0, OGDEN_002);
    let err = discrete.predict(&q10).unwrap_err();
    assert!(
        matches!(&err, RomError::InvalidInput { field, .. } if field == "n"),
        "{err}"
    );
    assert!(err.to_string().contains("--ordinal-n"), "{err}");
    assert_eq!(ordinal.n_allowed, (9..=13).collect::<Vec<u32>>());
    assert_eq!(ordinal.n_trained(), [9, 11, 13]);
    assert_eq!(discrete.n_trained(), [9, 11, 13]);
    assert!(ordinal.training.ordinal_n() && !discrete.training.ordinal_n());
    assert!(ordinal.domain_violations(&q10).is_empty());
    // N is never extrapolated
    for n in [8, 14] {
        assert!(ordinal
            .predict(&Query::new(n, 2.0, 2.0, OGDEN_002))
            .is_err());
    }
    // what the model file says survives a round trip; a model without ordinal N writes no
    // trained list (its file is unchanged)
    let back = Surrogate::from_json(&ordinal.to_json().unwrap(), "m").unwrap();
    assert_eq!(back.n_trained(), [9, 11, 13]);
    assert_eq!(back.n_allowed, ordinal.n_allowed);
    assert!(!discrete.to_json().unwrap().contains("n_trained"));
    // the same regression: at a trained N the two models agree
    let q11 = Query::new(11, 2.0, 2.0, OGDEN_002);
    let (a, b) = (
        discrete.predict(&q11).unwrap(),
        ordinal.predict(&q11).unwrap(),
    );
    assert_eq!(a.tip_uz_mm(), b.tip_uz_mm());
}

#[test]
fn held_out_n_are_predicted_close_to_their_cases() {
    let cases = set(vec![7, 8, 9, 10, 11, 12, 13], 70);
    let report = held_out_n::study(
        &cases,
        "synthetic",
        &[8, 10, 12],
        &TrainConfig {
            folds: 4,
            ..Default::default()
        },
        &|_, _| {},
    )
    .unwrap();
    assert_eq!(report.trained, [7, 9, 11, 13]);
    assert_eq!(report.per_n.len(), 3);
    let held: usize = report.per_n.iter().map(|e| e.cases).sum();
    assert_eq!(held + report.training_cases, cases.cases.len());
    assert_eq!(report.all.cases, held);
    // the errors are those of the held-out cases, through a model that never saw them:
    // recompute N = 10's
    let mut kept = cases.clone();
    kept.cases
        .retain(|c| ![8, 10, 12].contains(&c.inputs.n_bellows));
    let m = model(&kept, true);
    let (mut sum, mut count) = (0.0, 0);
    for case in cases.cases.iter().filter(|c| c.inputs.n_bellows == 10) {
        for (&p, fe) in cases.pressures.iter().zip(&case.values) {
            if p > 0.0 {
                let pred = m.predict(&Query::from_case(&case.inputs, p)).unwrap();
                sum += (pred.tip_uz_mm() - fe[18]).hypot(pred.tip_uy_mm() - fe[19]);
                count += 1;
            }
        }
    }
    assert_eq!(count, report.per_n[1].points);
    assert!(
        (sum / count as f64 - report.per_n[1].tip_mm).abs() < 1e-9,
        "{} vs {}",
        sum / count as f64,
        report.per_n[1].tip_mm
    );
    println!("{}", report.table());
    assert!(report.all.tip_mm < 1.0, "{}", report.table());
    assert!(report.all.angle_deg < 1.0, "{}", report.table());
}

#[test]
fn the_study_refuses_extrapolation_and_absent_n() {
    let cases = set(vec![9, 10, 11], 24);
    let cfg = TrainConfig {
        folds: 3,
        ..Default::default()
    };
    for (held, why) in [
        (vec![9], "strictly between"),
        (vec![11], "strictly between"),
        (vec![12], "with cases"),
    ] {
        let err = held_out_n::study(&cases, "s", &held, &cfg, &|_, _| {}).unwrap_err();
        assert!(err.to_string().contains(why), "{held:?}: {err}");
    }
}
