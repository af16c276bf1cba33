//! The shipped coarse snapshot set and the model trained on it (`models/actuator_coarse.json`):
//! the set is the merge of the committed case files, the model is what the shipped command
//! (`bash training_data/snapshots/ship.sh --coarse`) makes of the set, and its stored held-out
//! errors meet the surrogate's accuracy targets.
use std::path::{Path, PathBuf};

use surrogate::rom::{train, Query, SnapshotSet, Surrogate, TrainConfig};
use surrogate::snapshots::merge;

const SET: &str = "training_data/snapshots_coarse.csv";
const MODEL: &str = "models/actuator_coarse.json";

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

#[test]
fn shipped_coarse_set_is_the_merge_of_the_committed_case_files() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("shipped_coarse_merge.csv");
    let summary = merge(&[root("training_data/snapshots/coarse")], &out)
        .expect("the committed coarse case files merge without --partial (the set is complete)");
    assert_eq!(summary.failed_cases, 0, "failed cases in the shipped set");
    let merged = std::fs::read(&out).unwrap();
    let shipped = std::fs::read(root(SET)).unwrap();
    assert!(
        merged == shipped,
        "{SET} differs from the merge of training_data/snapshots/coarse: re-run ship.sh --coarse"
    );
}

/// Every output's pooled held-out RMSE against the targets: tip ≤ 0.3 mm, markers
/// ≤ 0.5 mm, blocked force ≤ 2 % of its range, angle ≤ 0.3°.
#[test]
fn shipped_coarse_model_meets_the_accuracy_targets() {
    let m = Surrogate::load(&root(MODEL)).unwrap();
    let v = &m.validation;
    assert!(
        v.scheme.contains("3 fold assignments pooled"),
        "{}",
        v.scheme
    );
    let rmse = |name: &str| {
        v.outputs
            .iter()
            .find(|o| o.name == name)
            .unwrap_or_else(|| panic!("{name} not in the stored validation"))
            .total
    };
    assert!(rmse("tip_uz_mm").rmse <= 0.3, "{:?}", rmse("tip_uz_mm"));
    assert!(rmse("tip_uy_mm").rmse <= 0.3, "{:?}", rmse("tip_uy_mm"));
    assert!(rmse("markers_mm").rmse <= 0.5, "{:?}", rmse("markers_mm"));
    assert!(rmse("angle_deg").rmse <= 0.3, "{:?}", rmse("angle_deg"));
    let f = rmse("force_n");
    assert!(f.rmse <= 0.02 * f.range, "{f:?}");
}

/// Retraining on the shipped set with the shipped settings gives the shipped model: the same
/// stored validation and the same predictions (to round-off: the SIMD paths of another CPU may
/// change the last bits of the hyperparameter search).
#[test]
fn shipped_coarse_model_is_reproduced_from_the_shipped_set() {
    let shipped = Surrogate::load(&root(MODEL)).unwrap();
    let set = SnapshotSet::read(&root(SET)).unwrap();
    let skipped = set.skipped_unconverged;
    let cases = set.into_cases().unwrap();
    let cfg = TrainConfig {
        folds: 5,
        repeats: 3,
        ..Default::default()
    };
    let report = train(&cases, SET, skipped, &cfg, &|_, _| {}).unwrap();
    let again = report.surrogate;
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-6 * scale.max(1e-12);
    for (a, b) in shipped
        .validation
        .outputs
        .iter()
        .zip(&again.validation.outputs)
    {
        assert_eq!(a.name, b.name);
        assert_eq!(a.source, b.source, "{}", a.name);
        assert!(
            close(a.total.rmse, b.total.rmse, a.total.rmse),
            "{}: stored RMSE {} retrained {}",
            a.name,
            a.total.rmse,
            b.total.rmse
        );
    }
    let scale = |q: &[f64]| q.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    for (i, case) in cases.cases.iter().enumerate().step_by(7) {
        let c = &case.inputs;
        for p in [0.5, 1.0, 2.0, 3.0, 3.4] {
            let q = Query::from_case(c, p);
            let (a, b) = (shipped.predict(&q).unwrap(), again.predict(&q).unwrap());
            let (a, b) = (a.values, b.values);
            let s = scale(&a);
            for (k, (x, y)) in a.iter().zip(&b).enumerate() {
                assert!(
                    close(*x, *y, s),
                    "case {i} P {p}: output {k} shipped {x} retrained {y}"
                );
            }
        }
    }
}
