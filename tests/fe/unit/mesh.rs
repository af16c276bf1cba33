//! The unit tests of `src/fe/mesh/mod.rs`.
//!
//! Tests of the meshes: options, faces, refinement levels, node and face sets, moved meshes.

use surrogate::fe::geometry::DesignParams;
use surrogate::fe::mesh::*;

#[test]
fn mesh_options_name_the_bad_override() {
    let mut o = MeshOptions::level(MeshLevel::Coarse);
    o.validate().expect("a level without override");
    o.element_size = Some(0.1);
    assert_eq!(o.validate().unwrap_err().field, "element_size");
    o.element_size = Some(2.0);
    o.wall_elements = Some(0);
    assert_eq!(o.validate().unwrap_err().field, "wall_elements");
    o.wall_elements = Some(3);
    o.validate().expect("valid overrides");
}

#[test]
fn a_moved_mesh_is_the_mesh_of_the_moved_design_when_the_element_counts_agree() {
    let opts = MeshOptions::level(MeshLevel::Coarse);
    let nominal = DesignParams::new(9, 2.0).validate().unwrap();
    let mesh = ActuatorMesh::new(&nominal, &opts);
    let same = mesh.moved(&nominal, &nominal).unwrap();
    assert_eq!(same.mesh().nodes, mesh.mesh().nodes);
    let mut p = nominal.params().clone();
    p.skin_thickness = Some(2.05);
    p.gap += 0.03;
    p.free_length -= 0.2;
    let printed = p.validate().unwrap();
    let moved = mesh.moved(&nominal, &printed).unwrap();
    let fresh = ActuatorMesh::new(&printed, &opts);
    assert_eq!(moved.mesh().elements, fresh.mesh().elements);
    for (a, b) in moved.mesh().nodes.iter().zip(&fresh.mesh().nodes) {
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-12, "{a:?} vs {b:?}");
        }
    }
    assert_eq!(moved.markers, fresh.markers);
    // another number of bellows is not a motion
    let other = DesignParams::new(11, 2.0).validate().unwrap();
    assert!(mesh.moved(&nominal, &other).is_err());
}

#[test]
fn face_nodes_are_outward() {
    // reference element node coordinates in tensor order
    let pos = |l: usize| {
        [
            (l % 3) as f64 - 1.0,
            ((l / 3) % 3) as f64 - 1.0,
            (l / 9) as f64 - 1.0,
        ]
    };
    for axis in 0..3 {
        for positive in [false, true] {
            let f = face_local_nodes(axis, positive);
            let x0 = pos(f[0]);
            let xs = pos(f[1]);
            let xt = pos(f[3]);
            let a = [xs[0] - x0[0], xs[1] - x0[1], xs[2] - x0[2]];
            let b = [xt[0] - x0[0], xt[1] - x0[1], xt[2] - x0[2]];
            let n = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            let sign = if positive { 1.0 } else { -1.0 };
            assert!(n[axis] * sign > 0.0, "axis {axis} positive {positive}");
            assert!(f.iter().all(|&l| pos(l)[axis] == sign));
        }
    }
}

#[test]
fn levels_are_one_refinement_family() {
    let d = DesignParams::new(11, 2.0).validate().unwrap();
    let elements = |o: MeshOptions| ActuatorMesh::new(&d, &o).mesh().n_elements();
    let coarse = elements(MeshOptions::level(MeshLevel::Coarse));
    let standard = elements(MeshOptions::level(MeshLevel::Standard));
    let fine = elements(MeshOptions::level(MeshLevel::Fine));
    // h 6 → 3 → 2 and 1 → 2 → 3 elements through a wall; segments shorter than h (the
    // 1 mm gaps) keep one element, so the counts grow by less than 8 and 27
    assert!(
        (4 * coarse..=8 * coarse).contains(&standard),
        "{coarse} → {standard}"
    );
    assert!(
        (2 * standard..=4 * standard).contains(&fine),
        "{standard} → {fine}"
    );
    // the wall override adds elements through the walls only
    let mut o = MeshOptions::level(MeshLevel::Coarse);
    o.wall_elements = Some(2);
    let w2 = elements(o);
    assert!(w2 > coarse && w2 < standard, "{coarse} → {w2}");
}

#[test]
fn actuator_mesh_has_all_sets() {
    let d = DesignParams::new(11, 2.0).validate().unwrap();
    let m = ActuatorMesh::new(&d, &MeshOptions::level(MeshLevel::Coarse));
    assert_eq!(m.pressure_faces.len(), 12); // 11 cavities + duct
    assert_eq!(m.gap_faces.len(), 21); // 10 gaps × 2 sides + clamp
    assert_eq!(m.markers.len(), 9);
    assert!(!m.support.is_empty() && !m.symmetry.is_empty());
    for c in &m.mesh().colors {
        let mut seen = std::collections::HashSet::new();
        for &e in c {
            for &n in &m.mesh().elements[e] {
                assert!(seen.insert(n), "colour shares node {n}");
            }
        }
    }
}
#[test]
fn fused_gaps_and_filleted_cavities_are_meshed_on_their_lines() {
    let mut p = DesignParams::new(13, 2.4);
    p.gap_floor = Some(3.0);
    p.cavity_fillet = Some(1.0);
    let d = p.validate().unwrap();
    let m = ActuatorMesh::new(&d, &MeshOptions::level(MeshLevel::Coarse));
    let nodes = &m.mesh().nodes;
    // contact faces of the gaps between bellows lie above the gaps' floor only
    let floor = d.base_thickness() + 3.0;
    for (side, faces) in &m.gap_faces {
        if *side == GapSide::Clamp {
            continue;
        }
        for f in faces {
            let lowest = f
                .nodes
                .iter()
                .map(|&n| nodes[n][1])
                .fold(f64::MAX, f64::min);
            assert!(
                lowest >= floor - 1e-9,
                "{side:?}: a face reaches y = {lowest}"
            );
        }
    }
    // the raised floor of a short cavity is a grid line: its pressurised faces start there
    let c = d.cavity(5);
    let faces = &m.pressure_faces[&PressureSurface::Cavity(5)];
    let lowest = faces
        .iter()
        .flat_map(|f| f.nodes.iter().map(|&n| nodes[n][1]))
        .fold(f64::MAX, f64::min);
    assert!((lowest - (c.lo[1] + 1.0)).abs() < 1e-9, "{lowest}");
    // without them, the gap faces reach the base
    let plain = DesignParams::new(13, 2.4).validate().unwrap();
    let m = ActuatorMesh::new(&plain, &MeshOptions::level(MeshLevel::Coarse));
    let lowest = m.gap_faces[&GapSide::Back(0)]
        .iter()
        .flat_map(|f| f.nodes.iter().map(|&n| m.mesh().nodes[n][1]))
        .fold(f64::MAX, f64::min);
    assert!((lowest - plain.base_thickness()).abs() < 1e-9);
}
