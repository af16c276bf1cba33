//! The unit tests of `src/diagnose/structure.rs`.

use super::cells::UnitCell;
use surrogate::calibrate::objective::Output;
use surrogate::diagnose::cells::{Cell, Family};
use surrogate::diagnose::structure::*;

fn cell(n: u32, t: f64, p: f64, z: f64) -> Cell {
    Cell::unit(n, t, p, Output::TipUz, z)
}

#[test]
fn an_exact_additive_residual_is_recovered_term_by_term() {
    let mut cells = Vec::new();
    for n in [9, 11, 13] {
        for t in [1.6, 2.0, 2.4] {
            for p in [1.0, 2.0, 3.0] {
                // a small deterministic wiggle so that the scatter is not zero
                let w = 1e-3 * ((n as f64) * 7.0 + t * 13.0 + p * 3.0).sin();
                let z = 0.5 - 4.0 * (t - 2.0)
                    + 0.25 * (f64::from(n) - 11.0)
                    + 1.5 * (p - 2.0)
                    + 2.0 * (p - 2.0) * (t - 2.0)
                    + w;
                cells.push(cell(n, t, p, z));
            }
        }
    }
    let refs: Vec<&Cell> = cells.iter().collect();
    let s = fit(Family::TipUz, &refs).unwrap();
    let c = |t: Term| s.term(t).unwrap().coefficient;
    assert!((c(Term::Constant) - 0.5).abs() < 1e-2);
    assert!((c(Term::T) + 4.0).abs() < 1e-2);
    assert!((c(Term::N) - 0.25).abs() < 1e-2);
    assert!((c(Term::P) - 1.5).abs() < 1e-2);
    assert!((c(Term::PT) - 2.0).abs() < 1e-2);
    assert!(s.explained > 0.999 && s.dof == 22);
    assert!(s.term(Term::T).unwrap().p_value < 1e-10);
    // the value along T at the centre of the others
    assert!((s.along(Term::T, 1.6, false) - (0.5 + 1.6)).abs() < 1e-2);
}

#[test]
fn single_levels_and_confounded_terms_are_dropped_with_a_reason() {
    // one N, and T determined by P (T = 1.2 + 0.4 P): T and P confounded
    let cells: Vec<Cell> = [1.0, 2.0, 3.0, 1.0, 2.0, 3.0]
        .iter()
        .enumerate()
        .map(|(i, &p)| cell(11, 1.2 + 0.4 * p, p, i as f64))
        .collect();
    let refs: Vec<&Cell> = cells.iter().collect();
    let s = fit(Family::TipUz, &refs).unwrap();
    let dropped: Vec<Term> = s.dropped.iter().map(|d| d.term).collect();
    assert!(
        dropped.contains(&Term::N) && dropped.contains(&Term::T),
        "{dropped:?}"
    );
    assert!(s.term(Term::P).is_some() && s.term(Term::Constant).is_some());
    assert!(fit(Family::TipUz, &refs[..2]).is_none());
}
