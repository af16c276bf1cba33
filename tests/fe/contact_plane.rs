//! Rigid-plane contact: global equilibrium of a block pressed on a plate, penetration, and the
//! tangent with contact active against finite differences.

use surrogate::fe::assembly::{Constraint, FeModel, LoadFactor, LoadLevel};
use surrogate::fe::contact::RigidPlane;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{GridMesh, TensorGrid};
use surrogate::fe::solver::{solve_path, SolverSettings};

/// A 2 × 1 × 2 mm block (2 × 1 × 2 elements) standing on a plate at y = 0 (inside the barrier's
/// smoothing width, so the block is never free-floating), symmetry planes x = 0 and z = 0, a dead
/// downward traction on its top face, its bottom face in contact search.
fn block(traction: f64, stiffness: f64) -> FeModel {
    let grid = TensorGrid {
        lines: [vec![0.0, 1.0, 2.0], vec![0.0, 1.0], vec![0.0, 1.0, 2.0]],
    };
    let gm = GridMesh::new(grid, |_| true, |s| s);
    let mut cons = Vec::new();
    for n in gm.nodes_on_plane(0, 0.0) {
        cons.push(Constraint {
            node: n,
            comp: 0,
            value: 0.0,
        });
    }
    for n in gm.nodes_on_plane(2, 0.0) {
        cons.push(Constraint {
            node: n,
            comp: 2,
            value: 0.0,
        });
    }
    let faces = gm.boundary_faces(|k| k.is_none());
    let top: Vec<_> = faces
        .iter()
        .filter(|(f, _)| f.axis == 1 && f.positive)
        .map(|(f, _)| *f)
        .collect();
    let bottom: Vec<_> = faces
        .iter()
        .filter(|(f, _)| f.axis == 1 && !f.positive)
        .map(|(f, _)| *f)
        .collect();
    let mat = Material::from_spec("neo_hookean:1.0", 100.0).unwrap();
    let mut model = FeModel::new(gm.mesh.clone(), mat, &cons, &[], &[]).unwrap();
    for f in &top {
        model.add_dead_traction(f, [0.0, -traction, 0.0]);
    }
    let smoothing = 0.01;
    let plane = RigidPlane::new([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], stiffness, smoothing).unwrap();
    model.add_plane_contact(plane, &bottom).unwrap();
    model
}

#[test]
fn plate_reaction_equals_applied_load_and_penetration_is_small() {
    let traction = 0.5; // MPa on a 2 × 2 mm top face: 2 N
    for stiffness in [100.0, 1000.0] {
        let model = block(traction, stiffness);
        let levels = [LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0)];
        let mut u = Vec::new();
        // no Dirichlet support in y: the plate alone carries the block
        let settings = SolverSettings {
            initial_fraction: 0.2,
            ..SolverSettings::default()
        };
        solve_path(&model, settings, &levels, |_, st, _| u = st.u_full.clone()).unwrap();
        let mut r = vec![0.0; u.len()];
        let info = model.assemble(&u, &levels[0], &mut r, None).unwrap();
        let applied = traction * 4.0;
        let rel = (info.plane_forces[0] - applied).abs() / applied;
        assert!(
            rel < 1e-6,
            "ε = {stiffness}: plate reaction {} vs applied {applied}",
            info.plane_forces[0]
        );
        // contact pressure 0.5 MPa: penetration at most about p/ε (none while the smoothing
        // zone carries it)
        let pen = -info.plane_min_gaps[0];
        assert!(
            pen < 2.0 * traction / stiffness,
            "ε = {stiffness}: penetration {pen}"
        );
    }
}

#[test]
fn tangent_with_active_contact_matches_finite_differences() {
    let model = block(0.5, 300.0);
    let n = 3 * model.mesh.n_nodes();
    // a state pushed into the plate, unevenly
    let mut u: Vec<f64> = (0..n)
        .map(|d| {
            if d % 3 == 1 {
                -0.02 - 0.005 * ((d / 3) as f64).sin()
            } else {
                0.003 * ((d as f64) * 0.7).cos()
            }
        })
        .collect();
    for &(d, _) in &model.dofs.constrained {
        u[d] = 0.0;
    }
    let level = LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0);
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; model.pattern.nnz()];
    let info = model.assemble(&u, &level, &mut r, Some(&mut k)).unwrap();
    assert!(info.plane_forces[0] > 0.0, "contact is active");
    let kscale = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let h = 1e-7;
    let mut err: f64 = 0.0;
    for d in 0..n {
        let Some(col) = model.dofs.eq(d) else {
            continue;
        };
        let (mut up, mut um) = (u.clone(), u.clone());
        up[d] += h;
        um[d] -= h;
        let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
        model.assemble(&up, &level, &mut rp, None).unwrap();
        model.assemble(&um, &level, &mut rm, None).unwrap();
        for rd in 0..n {
            let Some(row) = model.dofs.eq(rd) else {
                continue;
            };
            if row < col {
                continue;
            }
            let fd = (rp[rd] - rm[rd]) / (2.0 * h);
            let kv = model.pattern.position(row, col).map_or(0.0, |p| k[p]);
            err = err.max((fd - kv).abs() / kscale);
        }
    }
    assert!(err < 1e-6, "tangent FD error {err:e}");
}

#[test]
fn frictionless_plate_leaves_no_tangential_reaction() {
    let model = block(0.5, 300.0);
    let n = 3 * model.mesh.n_nodes();
    let mut u = vec![0.0; n];
    for d in (1..n).step_by(3) {
        u[d] = -0.02;
    }
    for d in (0..n).step_by(3) {
        u[d] = 0.01 * (d as f64 * 0.1).sin();
    }
    for &(d, _) in &model.dofs.constrained {
        u[d] = 0.0;
    }
    // contact residual alone: difference of the residual with and without the plate
    let level = LoadLevel::default();
    let mut r = vec![0.0; n];
    model.assemble(&u, &level, &mut r, None).unwrap();
    let mut plain = block(0.5, 300.0);
    plain.planes.clear();
    plain.contact_faces.iter_mut().for_each(|v| v.clear());
    let mut r0 = vec![0.0; n];
    plain.assemble(&u, &level, &mut r0, None).unwrap();
    let (mut fx, mut fy, mut fz) = (0.0, 0.0, 0.0);
    for node in 0..n / 3 {
        fx += r[3 * node] - r0[3 * node];
        fy += r[3 * node + 1] - r0[3 * node + 1];
        fz += r[3 * node + 2] - r0[3 * node + 2];
    }
    assert!(fy.abs() > 1e-3, "contact active");
    assert!(
        fx.abs() < 1e-12 * fy.abs() && fz.abs() < 1e-12 * fy.abs(),
        "tangential {fx} {fz}"
    );
}

#[test]
fn augmented_lagrangian_makes_the_block_touch_whatever_the_penalty() {
    let traction = 0.5;
    let mut heights = Vec::new();
    let mut heights_plain = Vec::new();
    for stiffness in [20.0, 200.0] {
        let model = block(traction, stiffness);
        let levels = [LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0)];
        let run = |augmented_updates: usize| {
            let settings = SolverSettings {
                initial_fraction: 0.2,
                augmented_updates,
                ..SolverSettings::default()
            };
            let mut out = None;
            solve_path(&model, settings, &levels, |_, st, rep| {
                out = Some((
                    st.u_full.clone(),
                    rep.augmented_updates,
                    rep.augmented_failed,
                ))
            })
            .unwrap();
            out.unwrap()
        };
        // plain penalty: the bottom sits at δ/2 − p/ε = 0.005 − 0.025 = −0.02 mm for ε = 20
        let (u_plain, _, _) = run(0);
        let (u, updates, failed) = run(20);
        assert!(
            updates >= 1 && !failed,
            "ε = {stiffness}: {updates} updates"
        );
        let mut r = vec![0.0; u.len()];
        let info = model.assemble(&u, &levels[0], &mut r, None).unwrap();
        let applied = traction * 4.0;
        assert!(
            (info.plane_forces[0] - applied).abs() < 1e-6 * applied,
            "ε = {stiffness}: plate reaction {} vs applied {applied}",
            info.plane_forces[0]
        );
        let info_plain = model.assemble(&u_plain, &levels[0], &mut r, None);
        let gap_plain = info_plain.unwrap().plane_min_gaps[0];
        let gap = info.plane_min_gaps[0];
        assert!(
            gap.abs() < 2e-3 && gap.abs() < 0.2 * gap_plain.abs(),
            "ε = {stiffness}: gap {gap} (plain penalty {gap_plain})"
        );
        // the top corner's height: the quantity a user reads
        let top = u.len() - 2;
        heights.push(u[top]);
        heights_plain.push(u_plain[top]);
    }
    assert!(
        (heights_plain[0] - heights_plain[1]).abs() > 1e-2,
        "plain penalty: {heights_plain:?}"
    );
    // a 10× stiffer penalty changes the result by far less than the plain penalty's offset
    assert!(
        (heights[0] - heights[1]).abs() < 2e-3,
        "top displacement {} vs {}",
        heights[0],
        heights[1]
    );
}

#[test]
fn reusing_the_factor_in_uzawa_resolves_gives_the_same_solution() {
    let model = block(0.5, 20.0);
    let levels = [LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0)];
    let run = |reuse_factor: bool| {
        let settings = SolverSettings {
            initial_fraction: 0.2,
            augmented_updates: 20,
            reuse_factor,
            ..SolverSettings::default()
        };
        let mut out = None;
        solve_path(&model, settings, &levels, |_, st, rep| {
            out = Some((st.u_full.clone(), rep.clone()))
        })
        .unwrap();
        out.unwrap()
    };
    let (u0, rep0) = run(false);
    let (u1, rep1) = run(true);
    assert!(rep0.augmented_updates >= 1 && rep1.augmented_updates >= 1);
    assert!(!rep1.augmented_failed);
    // every iteration factorises without reuse; with it, the re-solves mostly do not
    assert_eq!(rep0.factorizations, rep0.newton_iterations);
    assert!(
        rep1.factorizations < rep0.factorizations,
        "{} vs {} factorisations",
        rep1.factorizations,
        rep0.factorizations
    );
    // the same equilibrium and contact state: both stop when no multiplier changes by more
    // than ε · 1e-3 mm
    let diff = u0
        .iter()
        .zip(&u1)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff < 2e-3, "largest displacement difference {diff} mm");
    let mut r = vec![0.0; u1.len()];
    let info = model.assemble(&u1, &levels[0], &mut r, None).unwrap();
    let applied = 0.5 * 4.0;
    assert!((info.plane_forces[0] - applied).abs() < 1e-6 * applied);
}
