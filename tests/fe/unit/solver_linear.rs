//! The unit tests of `src/fe/solver/linear.rs`.

use surrogate::fe::assembly::{LoadFactor, LoadLevel};
use surrogate::fe::solver::linear::*;

/// A 4×4×4 block of Q2 hexes clamped at z = 0, loaded by gravity and pressure-free:
/// both orderings must give the same Newton step.
#[test]
fn orderings_give_the_same_solution() {
    let mut fe = super::assembly_model::clamped_block(4);
    fe.set_body_force([0.1, -0.2, 0.3]);
    let u = vec![0.0; 3 * fe.mesh.n_nodes()];
    let level = LoadLevel::ZERO.with(LoadFactor::GRAVITY, 1.0);
    let mut r_full = vec![0.0; u.len()];
    let mut k = vec![0.0; fe.pattern.nnz()];
    fe.assemble(&u, &level, &mut r_full, Some(&mut k))
        .expect("assembly");
    let mut r = vec![0.0; fe.dofs.n_free];
    fe.restrict(&r_full, &mut r);
    let mut x = Vec::new();
    let mut sizes = Vec::new();
    for o in [Ordering::MinimumDegree, Ordering::NestedDissection] {
        let mut ls = LinearSolver::with_ordering(&fe, Some(o)).expect("symbolic");
        assert_eq!(ls.ordering, o);
        sizes.push(ls.nnz_l());
        let mut b = r.clone();
        ls.solve(&k, &mut b).expect("solve");
        x.push(b);
    }
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = norm(&x[0]);
    assert!(scale > 0.0);
    let diff: Vec<f64> = x[0].iter().zip(&x[1]).map(|(a, b)| a - b).collect();
    assert!(norm(&diff) <= 1e-10 * scale, "{} vs {scale}", norm(&diff));
    // the automatic choice keeps the smaller factor
    let auto = LinearSolver::new(&fe).expect("symbolic");
    assert_eq!(auto.nnz_l(), sizes[0].min(sizes[1]));
}
