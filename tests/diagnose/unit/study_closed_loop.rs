//! The unit tests of `src/diagnose/study/closed_loop.rs`.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::calibrate::objective::Output;
use surrogate::calibrate::Recordings;
use surrogate::diagnose::measurements::{Measurement, MeasurementKind};
use surrogate::diagnose::study::{add_record, draw, last_value};
use surrogate::fe::simulate::StepResult;

fn item(output: Output, p: f64) -> Measurement {
    Measurement {
        kind: MeasurementKind::Marker,
        n_bellows: 11,
        wall_thickness_mm: 2.0,
        pressure_bar: p,
        output,
        sigma: 0.5,
        sigma_from: String::new(),
    }
}

#[test]
fn random_draws_are_distinct_reproducible_and_bounded() {
    let options: Vec<Measurement> = (1..=8).map(|k| item(Output::MarkerUz(k), 1.0)).collect();
    let a = draw(&options, 3, 7);
    assert_eq!(a, draw(&options, 3, 7));
    assert_eq!(a.len(), 3);
    assert!(a
        .iter()
        .enumerate()
        .all(|(i, x)| a[..i].iter().all(|y| y != x)));
    assert_ne!(a, draw(&options, 3, 8));
    assert_eq!(draw(&options, 20, 7).len(), 8);
}

#[test]
fn a_marker_is_recorded_once_with_both_components() {
    let step = StepResult {
        pressure_bar: 1.0,
        tip_uz_mm: 0.0,
        tip_uy_mm: 0.0,
        angle_deg: 0.0,
        markers: (1..=9).map(|k| [k as f64, -(k as f64)]).collect(),
        newton_iterations: 0,
        warm_start: false,
        substeps: 0,
        cutbacks: 0,
        residual: 0.0,
        converged: true,
        min_gap_mm: 0.0,
        min_gap_at: String::new(),
        force_n: None,
        contact_force_n: 0.0,
        clamp_force_n: 0.0,
        min_contact_gap_mm: 0.0,
    };
    let mut rec = Recordings::shipped().unwrap();
    rec.markers.clear();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
    let m = item(Output::MarkerUy(4), 1.0);
    assert!(add_record(&mut rec, &[], &m, &step, &mut rng).unwrap());
    let r = &rec.markers[0];
    assert_eq!((r.marker, r.std_mm), (4, 0.5));
    assert!((r.uz_mm - 4.0).abs() < 5.0 * 0.5 && (r.uy_mm + 4.0).abs() < 5.0 * 0.5);
    assert_eq!(last_value(&rec, &m), Some(r.uy_mm));
    // the other component of the same marker is already recorded
    let again = item(Output::MarkerUz(4), 1.0);
    assert!(!add_record(&mut rec, &[], &again, &step, &mut rng).unwrap());
    assert_eq!(rec.markers.len(), 1);
}
