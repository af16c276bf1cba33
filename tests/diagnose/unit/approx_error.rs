//! The unit tests of `src/diagnose/approx_error.rs`.

use super::cells::UnitCell;
use std::path::Path;
use surrogate::calibrate::objective::Output;
use surrogate::calibrate::{ParamSpace, Recordings};
use surrogate::case::OgdenSet;
use surrogate::diagnose::approx_error::*;
use surrogate::diagnose::cells::Cell;
use surrogate::rom::Surrogate;

fn sample(source: &str, errors: &[(Output, f64)]) -> ErrorSample {
    ErrorSample {
        source: source.into(),
        material: OgdenSet::literature("ogden_002").unwrap(),
        values: errors
            .iter()
            .map(|&(output, error)| ErrorValue {
                n_bellows: 9,
                wall_thickness_mm: 2.0,
                pressure_bar: 1.0,
                output,
                error,
            })
            .collect(),
    }
}

#[test]
fn mean_and_spread_are_those_of_the_samples() {
    let a = ApproximationError::new(
        "m",
        "r",
        vec![
            sample("a", &[(Output::TipUz, 1.0), (Output::Force, 0.1)]),
            sample("b", &[(Output::TipUz, 3.0), (Output::Force, 0.3)]),
            sample("c", &[(Output::TipUz, 5.0)]),
        ],
    )
    .unwrap();
    assert_eq!(a.mean_at(9, 2.0, 1.0, Output::TipUz), Some(3.0));
    assert!((a.mean_at(9, 2.0, 1.0, Output::Force).unwrap() - 0.2).abs() < 1e-12);
    assert_eq!(a.mean_at(9, 2.0, 2.0, Output::TipUz), None);
    let cells = [
        Cell::unit(9, 2.0, 1.0, Output::TipUz, 0.0),
        Cell::unit(9, 2.0, 1.0, Output::Force, 0.0),
        Cell::unit(9, 2.0, 2.0, Output::TipUz, 0.0),
    ];
    let s = a.spread(&cells);
    // tip: deviations −2, 0, 2 over √2; the sample variance is 4 = Σ d²
    let var: f64 = s.deviations.iter().map(|d| d[0] * d[0]).sum();
    assert!((var - 4.0).abs() < 1e-12, "{var}");
    // force: two samples, variance 0.02; the third sample lacks it
    let var: f64 = s.deviations.iter().map(|d| d[1] * d[1]).sum();
    assert!((var - 0.02).abs() < 1e-12, "{var}");
    assert_eq!(s.deviations[2][1], 0.0);
    assert!(s.deviations.iter().all(|d| d[2] == 0.0));
    assert!(a.without(&["a", "b"]).is_err());
    assert_eq!(a.without(&["c"]).unwrap().samples.len(), 2);
}

#[test]
fn spread_materials_are_reproducible_and_inside_the_central_domain() {
    let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json")).unwrap();
    let domain = ParamSpace::training_domain(&model).unwrap();
    let a = spread_materials(&domain, 6, 7).unwrap();
    assert_eq!(a, spread_materials(&domain, 6, 7).unwrap());
    assert_ne!(a, spread_materials(&domain, 6, 8).unwrap());
    for m in &a {
        let u = domain.unit(m);
        assert!(u.iter().all(|v| (0.099..=0.901).contains(v)), "{u:?}");
    }
    // one per stratum in every coordinate
    for i in 0..4 {
        let mut strata: Vec<usize> = a
            .iter()
            .map(|m| ((domain.unit(m)[i] - 0.1) / 0.8 * 6.0).floor() as usize)
            .collect();
        strata.sort_unstable();
        assert_eq!(strata, vec![0, 1, 2, 3, 4, 5], "coordinate {i}");
    }
    assert!(spread_materials(&domain, 1, 7).is_err());
}

#[test]
fn corrected_recordings_are_shifted_by_the_mean_error() {
    let rec = Recordings::shipped().unwrap();
    let r0 = &rec.bending[0];
    let (n, t, p) = (r0.n_bellows as u32, r0.wall_thickness_mm, r0.pressure_bar);
    let mut s1 = sample("a", &[(Output::TipUz, 1.0), (Output::Angle, -2.0)]);
    let mut s2 = sample("b", &[(Output::TipUz, 3.0), (Output::Angle, -4.0)]);
    for v in s1.values.iter_mut().chain(s2.values.iter_mut()) {
        (v.n_bellows, v.wall_thickness_mm, v.pressure_bar) = (n, t, p);
    }
    let a = ApproximationError::new("m", "5 mm FE", vec![s1, s2]).unwrap();
    let c = a.correct(&rec);
    assert!((c.bending[0].tip_uz_mm - (r0.tip_uz_mm + 2.0)).abs() < 1e-12);
    assert!((c.bending[0].angle_deg - (r0.angle_deg - 3.0)).abs() < 1e-12);
    assert_eq!(c.bending[0].tip_uy_mm, r0.tip_uy_mm);
    assert_eq!(c.bending[1], rec.bending[1]);
    assert_eq!(c.force, rec.force);
    assert!(c.bending_source.contains("5 mm FE"));
}

#[test]
fn a_file_round_trips_and_a_foreign_one_is_refused() {
    let dir = std::env::temp_dir().join(format!("approx_error_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let a = ApproximationError::new(
        "m",
        "r",
        vec![
            sample("a", &[(Output::TipUz, 1.0)]),
            sample("b", &[(Output::TipUz, 2.0)]),
        ],
    )
    .unwrap();
    let p = dir.join("e.json");
    a.write(&p).unwrap();
    assert_eq!(ApproximationError::read(&p).unwrap(), a);
    let text = std::fs::read_to_string(&p)
        .unwrap()
        .replace("\"version\": 1", "\"version\": 7");
    std::fs::write(&p, text).unwrap();
    let e = ApproximationError::read(&p).unwrap_err().to_string();
    assert!(e.contains("version 7"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
