//! The `*_into` hot paths do not allocate (counting global allocator).
use surrogate::case::Query;
use surrogate::rom::Jacobian;

use crate::rom_common;

/// Counts heap allocations of the current thread: the other tests of this binary run on other
/// threads and are not counted.
struct Counting;

thread_local! {
    static ALLOCS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Heap allocations made so far by the current thread.
fn allocs() -> usize {
    ALLOCS.with(|n| n.get())
}

// SAFETY: forwards to the system allocator; the counter is a const-initialised thread-local
// `Cell`, which does not allocate.
unsafe impl std::alloc::GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|n| n.set(n.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}

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
        mu1: 1.13,
        alpha1: 3.11,
        mu2: -13.17,
        alpha2: -0.6,
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
