//! The unit tests of `src/fe/ordering.rs`.

use surrogate::fe::assembly::Constraint;
use surrogate::fe::assembly::{DofMap, Pattern};
use surrogate::fe::mesh::{GridMesh, TensorGrid};
use surrogate::fe::ordering::*;

/// A row of `k` Q2 hexes along z: a chain graph.
fn chain(k: usize) -> (Pattern, DofMap) {
    let lines = [
        vec![0.0, 1.0],
        vec![0.0, 1.0],
        (0..=k).map(|i| i as f64).collect(),
    ];
    let mesh = GridMesh::new(TensorGrid { lines }, |_| true, |s| s).mesh;
    let constraints: Vec<_> = (0..3)
        .map(|comp| Constraint {
            node: 0,
            comp,
            value: 0.0,
        })
        .collect();
    let dofs = DofMap::new(mesh.n_nodes(), &constraints);
    (Pattern::new(&mesh, &dofs, &[]), dofs)
}

#[test]
fn nested_dissection_is_a_permutation_keeping_node_blocks() {
    let (pattern, dofs) = chain(6);
    let perm = nested_dissection(&pattern, &dofs).expect("METIS ordering");
    assert_eq!(perm.len(), dofs.n_free);
    let mut seen = vec![false; dofs.n_free];
    for &p in &perm {
        assert!(!seen[p], "equation {p} twice");
        seen[p] = true;
    }
    // node 0 is fully constrained; every other node's three equations are consecutive
    for block in perm.chunks(3) {
        assert_eq!(block[1], block[0] + 1);
        assert_eq!(block[2], block[0] + 2);
    }
    // deterministic
    assert_eq!(Some(perm), nested_dissection(&pattern, &dofs));
}

/// METIS's random state is global: orderings computed on several threads at once must
/// still all equal the one computed alone (the test suite and the campaign runner both
/// build solvers in parallel).
#[test]
fn orderings_computed_concurrently_are_identical() {
    let fe = super::assembly_model::clamped_block(4);
    let alone = nested_dissection(&fe.pattern, &fe.dofs).expect("METIS ordering");
    let results: Vec<Vec<Vec<usize>>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|_| {
                s.spawn(|| {
                    (0..6)
                        .map(|_| nested_dissection(&fe.pattern, &fe.dofs).expect("METIS"))
                        .collect()
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("thread"))
            .collect()
    });
    for (t, perms) in results.iter().enumerate() {
        for (i, p) in perms.iter().enumerate() {
            assert!(*p == alone, "thread {t}, call {i}: another ordering");
        }
    }
}
