//! The unit tests of `src/calibrate/extend/material_box.rs`.

use surrogate::calibrate::extend::{allocate, MaterialBox, PhysicalLimits};
use surrogate::calibrate::fit::ActiveBound;
use surrogate::calibrate::optimise::Bound;
use surrogate::case::material::COORD_NAMES;

fn unit_box() -> MaterialBox {
    MaterialBox {
        mu0_mpa: [2.0, 4.0],
        term1_share: [0.3, 0.7],
        alpha1: [2.0, 4.0],
        alpha2: [-1.5, -0.5],
    }
}

fn pressed(coordinate: usize, side: Bound) -> ActiveBound {
    ActiveBound {
        coordinate,
        name: COORD_NAMES[coordinate].into(),
        side,
        value: 0.0,
    }
}

#[test]
fn a_pressed_bound_moves_by_the_step_in_its_sampling_coordinate_and_stops_at_the_limit() {
    let b = unit_box();
    let limits = PhysicalLimits {
        alpha1: [1.5, 20.0],
        ..PhysicalLimits::default()
    };
    let (n, moves) = b.extended(
        &[pressed(0, Bound::Upper), pressed(2, Bound::Lower)],
        0.5,
        &limits,
    );
    // μ0: ln 4 + 0.5 ln 2 → 4·√2
    assert!((n.mu0_mpa[1] - 4.0 * 2f64.sqrt()).abs() < 1e-12);
    assert_eq!(n.mu0_mpa[0], 2.0);
    // α1: 2 − 0.5·2 = 1, clipped at 1.5
    assert_eq!(n.alpha1, [1.5, 4.0]);
    assert_eq!(moves[1].moved_to, Some(1.5));
    assert_eq!(n.term1_share, b.term1_share);
    // at the limit now: not moved again, and said so
    let (m, moves) = n.extended(&[pressed(2, Bound::Lower)], 0.5, &limits);
    assert_eq!(m, n);
    assert_eq!(moves[0].moved_to, None);
    assert!(
        moves[0].describe().contains("physical limit 1.5"),
        "{}",
        moves[0].describe()
    );
}

#[test]
fn slabs_fill_the_new_box_outside_the_old_one_without_overlap() {
    let old = unit_box();
    let new = MaterialBox {
        mu0_mpa: [2.0, 8.0],
        alpha1: [1.0, 4.0],
        ..old
    };
    let slabs = new.slabs(&old);
    assert_eq!(slabs.len(), 2);
    // μ0 upper: ln 4 … ln 8 of ln 2 … ln 8 (½), every other coordinate in full
    assert_eq!(slabs[0].0.mu0_mpa, [4.0, 8.0]);
    assert_eq!(slabs[0].0.alpha1, [1.0, 4.0]);
    // α1 lower, with μ0 held to the old range (the corner belongs to the first slab)
    assert_eq!(slabs[1].0.alpha1, [1.0, 2.0]);
    assert_eq!(slabs[1].0.mu0_mpa, [2.0, 4.0]);
    let total: f64 = slabs.iter().map(|s| s.1).sum();
    // the volume outside the old box: 1 − ½·⅔
    assert!((total - (1.0 - 0.5 * 2.0 / 3.0)).abs() < 1e-12, "{total}");
    assert!(old.slabs(&old).is_empty());
}

#[test]
fn cases_are_shared_by_volume_after_the_floor() {
    assert_eq!(allocate(36, &[0.5, 0.25], 3), vec![23, 13]);
    assert_eq!(allocate(36, &[1.0], 3), vec![36]);
    assert_eq!(allocate(7, &[0.2, 0.2, 0.2], 2), vec![3, 2, 2]);
    assert_eq!(allocate(10, &[0.1, 0.3], 0).iter().sum::<usize>(), 10);
}
