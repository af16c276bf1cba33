//! The search's loop does not allocate: more starts, more evaluations, the same allocations.
use surrogate::design::{search, DesignBounds, DesignSearch};

use crate::common::{angle_and_force, shipped, CALIBRATED};

/// Counts heap allocations of the current thread: the other tests of this binary run on other
/// threads and are not counted.
struct Counting;

thread_local! {
    static ALLOCS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

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
fn more_starts_do_not_allocate_more() {
    let model = shipped();
    let targets = angle_and_force(40.0, 1.3);
    let bounds = DesignBounds::of_model(model);
    let run = |starts: usize| {
        let settings = DesignSearch {
            starts,
            ..Default::default()
        };
        let before = allocs();
        let report = search(model, CALIBRATED, &targets, &bounds, &settings).unwrap();
        let e = report.evaluations;
        (allocs() - before, e.scan + e.gradient)
    };
    run(2); // builds the model's derived tables
    let (few, few_evals) = run(3);
    let (many, many_evals) = run(30);
    assert!(many_evals > 2 * few_evals, "{few_evals} {many_evals}");
    assert_eq!(few, many, "allocations with 3 and 30 starts");
}
