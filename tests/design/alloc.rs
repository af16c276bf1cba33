//! The search's loop does not allocate: more starts, more evaluations, the same allocations.
use surrogate::design::{search, DesignBounds, DesignSearch};

use crate::common::{angle_and_force, shipped, CALIBRATED};
use crate::counting_alloc::{allocs, Counting};

/// Counts the allocations of this binary's threads (`tests/shared/counting_alloc.rs`).
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
