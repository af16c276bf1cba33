//! The unit tests of `src/fe/warm_start/transfer.rs`.

use surrogate::fe::assembly::LoadLevel;
use surrogate::fe::geometry::Design;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::mesh::{feature_positions, ActuatorMesh};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::warm_start::*;

fn design(n: usize, t: f64) -> Design {
    DesignParams::new(n, t).validate().unwrap()
}

fn mesh(d: &Design) -> ActuatorMesh {
    ActuatorMesh::new(d, &MeshOptions::level(MeshLevel::Coarse))
}

fn state(u: Vec<f64>, shifts: Vec<f64>) -> ConvergedState {
    ConvergedState {
        pressure_bar: 1.0,
        level: LoadLevel::default(),
        u,
        shifts,
        plate_y: Some(-3.5),
        reported: true,
    }
}

/// The affine field `c + G X` at every node of `mesh`.
fn affine(points: impl Iterator<Item = [f64; 3]>) -> Vec<f64> {
    let c = [0.3, -1.2, 0.7];
    let g = [
        [0.01, -0.02, 0.003],
        [0.05, 0.004, -0.01],
        [-0.006, 0.02, 0.015],
    ];
    points
        .flat_map(|x| {
            std::array::from_fn::<f64, 3, _>(|i| c[i] + (0..3).map(|j| g[i][j] * x[j]).sum::<f64>())
        })
        .collect()
}

#[test]
fn the_same_design_gives_the_state_back() {
    let d = design(9, 2.0);
    let m = mesh(&d);
    let n = m.mesh().n_nodes();
    let u: Vec<f64> = (0..3 * n)
        .map(|i| ((i * 7919) % 1013) as f64 * 1e-3 - 0.5)
        .collect();
    let shifts = vec![0.01, -0.02, 0.03];
    let st = state(u.clone(), shifts.clone());
    let out = transfer(&st, &m, &d, &m, &d).unwrap();
    assert_eq!(out.u, u);
    assert_eq!(out.shifts, shifts);
    assert_eq!(out.plate_y, st.plate_y);
    assert_eq!(out.pressure_bar, st.pressure_bar);
}

#[test]
fn an_affine_field_arrives_exactly() {
    let mut topologies = [false; 2];
    for (ta, tb) in [(2.0, 2.2), (2.0, 2.3), (2.4, 1.9), (2.0, 2.05), (1.6, 2.8)] {
        let (da, db) = (design(9, ta), design(9, tb));
        let (ma, mb) = (mesh(&da), mesh(&db));
        let u_a = affine(ma.mesh().nodes.iter().copied());
        let st = state(u_a, vec![1.0; 18]);
        let out = transfer(&st, &ma, &da, &mb, &db).unwrap();
        let psi = material_map(&da, &db).unwrap();
        let expected = affine(mb.mesh().nodes.iter().map(|&x| psi(x)));
        assert_eq!(out.u.len(), 3 * mb.mesh().n_nodes());
        let err = out
            .u
            .iter()
            .zip(&expected)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "T {ta} -> {tb}: largest error {err:e}");
        let same = ma.mesh().elements == mb.mesh().elements;
        assert_eq!(out.shifts.is_empty(), !same, "T {ta} -> {tb}");
        topologies[usize::from(same)] = true;
    }
    assert_eq!(
        topologies, [true; 2],
        "both kinds of pair: same and other topology"
    );
}

#[test]
fn the_material_map_takes_features_to_features() {
    let (da, db) = (design(11, 2.0), design(11, 2.6));
    let psi = material_map(&da, &db).unwrap();
    let (fa, fb) = (feature_positions(&da), feature_positions(&db));
    for a in 0..3 {
        for (&xa, &xb) in fa[a].iter().zip(&fb[a]) {
            let mut x = [0.0; 3];
            x[a] = xb;
            assert!((psi(x)[a] - xa).abs() < 1e-12);
        }
    }
}

#[test]
fn another_number_of_bellows_is_refused() {
    let (da, db) = (design(9, 2.0), design(11, 2.0));
    let (ma, mb) = (mesh(&da), mesh(&db));
    let st = state(vec![0.0; 3 * ma.mesh().n_nodes()], Vec::new());
    assert_eq!(
        transfer(&st, &ma, &da, &mb, &db).unwrap_err(),
        TransferError::Bellows { from: 9, to: 11 }
    );
}

#[test]
fn a_state_of_another_mesh_is_refused() {
    let (da, db) = (design(9, 2.0), design(9, 2.2));
    let (ma, mb) = (mesh(&da), mesh(&db));
    let states = [
        state(vec![0.0; 3 * ma.mesh().n_nodes()], Vec::new()),
        state(vec![0.0; 6], Vec::new()),
    ];
    let err = WarmStart::transferred(&states, (&ma, &da), (&mb, &db)).unwrap_err();
    assert_eq!(
        err,
        TransferError::Length {
            state: 1,
            len: 6,
            expected: 3 * ma.mesh().n_nodes()
        }
    );
}

#[test]
fn a_warm_start_of_transferred_states_guesses_on_the_new_mesh() {
    let (da, db) = (design(9, 2.0), design(9, 2.3));
    let (ma, mb) = (mesh(&da), mesh(&db));
    let u_a = affine(ma.mesh().nodes.iter().copied());
    let mut zero = state(u_a.clone(), Vec::new());
    zero.pressure_bar = 0.0;
    let states = [zero, state(u_a, Vec::new())];
    let warm = WarmStart::transferred(&states, (&ma, &da), (&mb, &db)).unwrap();
    let guesses = warm.guesses(&[1.0, 2.0]);
    assert_eq!(guesses.len(), 3);
    let g = guesses[1].as_ref().unwrap();
    assert_eq!(g.u_full.len(), 3 * mb.mesh().n_nodes());
    assert!(guesses[2].is_none());
}
