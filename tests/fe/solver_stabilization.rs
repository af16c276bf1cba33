//! Stabilised continuation through an instability ([`SolverSettings::stabilization`]): a
//! clamped shallow arch under a dead distributed load snaps through at a limit point, where
//! plain load control stops. With the viscous term the solver crosses over to the inverted
//! branch, and every reported state is an undamped equilibrium.

use crate::common::{fix, node_at, plane_strain_layer, uniform};
use surrogate::fe::assembly::{FeModel, LoadFactor, LoadLevel};
use surrogate::fe::material::Material;
use surrogate::fe::solver::{solve_path, SolverError, SolverSettings, StepReport};

const SPAN: f64 = 100.0;
const THICKNESS: f64 = 2.0;
const RISE: f64 = 10.0;
const ELEMENTS: usize = 20;

fn arch() -> (FeModel, usize) {
    let (mut gm, mut cons) =
        plane_strain_layer(uniform(0.0, SPAN, ELEMENTS), uniform(0.0, THICKNESS, 1));
    let mid = node_at(&gm, [SPAN / 2.0, THICKNESS, 0.0]);
    for node in &mut gm.mesh.nodes {
        node[1] += RISE * (std::f64::consts::PI * node[0] / SPAN).sin();
    }
    for x in [0.0, SPAN] {
        cons.extend(fix(&gm.nodes_on_plane(0, x), &[0, 1], 0.0));
    }
    let material = Material::from_spec("neo_hookean:1", 2.6 / (3.0 * 0.4)).expect("mu > 0");
    let mut model = FeModel::new(gm.mesh.clone(), material, &cons, &[], &[]).expect("valid arch");
    for (face, _) in gm.boundary_faces(|k| k.is_none()) {
        if face.axis == 1 && face.positive {
            model.add_dead_traction(&face, [0.0, -1.0, 0.0]);
        }
    }
    (model, mid)
}

fn ramp(q: f64, steps: usize) -> Vec<LoadLevel> {
    (1..=steps)
        .map(|k| LoadLevel::ZERO.with(LoadFactor::TRACTION, q * k as f64 / steps as f64))
        .collect()
}

struct Path {
    /// (load factor, mid-span vertical displacement, full displacements) per output level.
    states: Vec<(LoadLevel, f64, Vec<f64>)>,
    reports: Vec<StepReport>,
    error: Option<SolverError>,
}

fn run(model: &FeModel, mid: usize, stabilization: f64) -> Path {
    let settings = SolverSettings {
        stabilization,
        trace: std::env::var("TRACE").is_ok(),
        ..Default::default()
    };
    let mut states = Vec::new();
    let mut reports = Vec::new();
    let out = solve_path(model, settings, &ramp(4e-4, 8), |_, state, rep| {
        states.push((state.level, state.u_full[3 * mid + 1], state.u_full.clone()));
        reports.push(rep.clone());
    });
    Path {
        states,
        reports,
        error: out.err(),
    }
}

#[test]
fn stabilised_continuation_snaps_the_arch_through_to_undamped_equilibria() {
    let (model, mid) = arch();
    // plain load control stops at the first instability (between q = 1.5e-4 and 2e-4)
    let plain = run(&model, mid, 0.0);
    assert!(
        matches!(plain.error, Some(SolverError::NotConverged { .. })),
        "{:?}",
        plain.error
    );
    assert_eq!(plain.states.len(), 3);
    let stab = run(&model, mid, surrogate::fe::solver::DEFAULT_STABILIZATION);
    assert!(stab.error.is_none(), "{:?}", stab.error);
    assert_eq!(stab.states.len(), 8);
    // before the instability nothing changes, bit for bit
    for (a, b) in plain.states.iter().zip(&stab.states) {
        assert_eq!(a.2, b.2);
    }
    assert!(stab.reports.iter().take(3).all(|r| !r.stabilized));
    assert!(stab.reports[3].stabilized);
    // the arch ends inverted: mid-span beyond the mirror image of its rise
    let last = stab.states.last().expect("8 states").1;
    assert!(last < -1.5 * RISE, "mid-span {last} mm");
    // every reported state is an undamped equilibrium
    let mut r_full = vec![0.0; 3 * model.mesh.n_nodes()];
    let mut r = vec![0.0; model.dofs.n_free];
    for (level, _, u) in &stab.states {
        let info = model
            .assemble(u, level, &mut r_full, None)
            .expect("admissible state");
        model.restrict(&r_full, &mut r);
        let rn = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        // the solver's force scale: the larger of the load and the support reactions
        let reactions = model
            .dofs
            .constrained
            .iter()
            .map(|&(d, _)| r_full[d] * r_full[d])
            .sum::<f64>()
            .sqrt();
        let scale = info.external_norm.max(reactions);
        assert!(
            rn <= 1e-6 * scale,
            "q = {}: residual {rn:e}, force scale {scale:e}",
            level.traction()
        );
    }
}
