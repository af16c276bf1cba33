//! The `*_into` hot paths do not allocate (counting global allocator).
use surrogate::case::{OgdenSet, Query};
use surrogate::rom::Jacobian;

use crate::counting_alloc::{allocs, Counting};
use crate::rom_common;

/// Counts the allocations of this binary's threads (`tests/shared/counting_alloc.rs`).
#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn predict_into_std_and_gradient_do_not_allocate() {
    let before = allocs();
    let boxed = std::hint::black_box(Box::new(1.0_f64));
    assert!(allocs() > before && *boxed == 1.0, "the counter counts");
    for m in [rom_common::small_model(None), rom_common::grouped_model()] {
        predict_paths_do_not_allocate(&m);
    }
}

fn predict_paths_do_not_allocate(m: &surrogate::rom::Surrogate) {
    let mut pred = m.new_prediction();
    let mut jac = Jacobian::default();
    let q = Query {
        n: 11,
        t_mm: 2.0,
        p_bar: 2.0,
        material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    };
    m.predict_into(&q, &mut pred).unwrap();
    let before = allocs();
    for i in 0..100 {
        let qi = Query {
            p_bar: 0.03 * i as f64,
            ..q
        };
        m.predict_into(&qi, &mut pred).unwrap();
        m.predict_scalars_into(&qi, &mut pred).unwrap();
        m.predict_with_std_into(&qi, &mut pred).unwrap();
        m.gradient_into(&qi, &mut pred, &mut jac).unwrap();
    }
    assert_eq!(allocs() - before, 0);
    // a prepared ramp (design and material fixed) neither
    let ramp = m.ramp(&q).unwrap();
    let before = allocs();
    for i in 0..100 {
        ramp.predict_into(0.03 * i as f64, &mut pred).unwrap();
        ramp.predict_scalars(0.03 * i as f64).unwrap();
    }
    assert_eq!(allocs() - before, 0);
}
