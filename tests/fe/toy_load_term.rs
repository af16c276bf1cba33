//! A load term with its own load factor, added from outside the crate: one element term
//! ([`PointLoads`], this file) plus one factor registration and one
//! [`FeModel::add_element_term`] call where the model is built. The solver ramps the new
//! factor as it ramps the built-in ones.
//!
//! The case: a plane-strain cantilever under a small tip load, which [`PointLoads`] applies as
//! the nodal forces of a uniform shear traction on the tip face, scaled by the factor
//! `tip load`. Checked against the same nodal forces as a dead traction ramped along the
//! built-in traction factor, against the Euler–Bernoulli tip deflection `P L³ / (3 E' I)`,
//! and by the residual of the converged state with the factor on and off.

use crate::common::{fix, node_at, plane_strain_layer, uniform};
use surrogate::fe::assembly::{
    ElementContext, ElementTerm, FactorInfo, FeModel, LoadFactor, LoadLevel, LocalSystem,
};
use surrogate::fe::element::ElementError;
use surrogate::fe::material::Material;
use surrogate::fe::solver::{solve_path, SolverSettings, StepReport};

const LENGTH: f64 = 100.0;
const THICKNESS: f64 = 2.0;
const MU: f64 = 1.0;
const NU: f64 = 0.3;
/// `P L² / (E' I)`: small enough for the linear beam.
const LOAD: f64 = 0.01;
const STEPS: usize = 3;

/// The new factor.
const TIP_LOAD: FactorInfo = FactorInfo {
    name: "tip load",
    description: "point loads at the cantilever's tip (N)",
    bounds_increment: false,
};

/// Point loads `λ f` at nodes, `λ` the level's value of `factor`: each load is given to one
/// element of its node (its local node index), so that it is counted once.
struct PointLoads {
    factor: LoadFactor,
    /// (element, local node, force).
    loads: Vec<(usize, usize, [f64; 3])>,
}

impl PointLoads {
    /// The loads of the nodal force vector `f` (all dofs) of `model`'s mesh.
    fn from_nodal_forces(factor: LoadFactor, model: &FeModel, f: &[f64]) -> Self {
        let mut loads = Vec::new();
        for (node, force) in f.chunks_exact(3).enumerate() {
            if force.iter().all(|&v| v == 0.0) {
                continue;
            }
            let (element, local) = model
                .mesh
                .elements
                .iter()
                .enumerate()
                .find_map(|(e, conn)| conn.iter().position(|&n| n == node).map(|l| (e, l)))
                .expect("every node is in an element");
            loads.push((element, local, [force[0], force[1], force[2]]));
        }
        Self { factor, loads }
    }
}

impl ElementTerm<FeModel> for PointLoads {
    fn name(&self) -> &'static str {
        "point loads"
    }

    fn load_factor(&self) -> Option<LoadFactor> {
        Some(self.factor)
    }

    fn add(
        &self,
        _model: &FeModel,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError> {
        let lambda = cx.level[self.factor];
        for &(element, l, force) in &self.loads {
            if element != cx.element {
                continue;
            }
            for (i, &component) in force.iter().enumerate() {
                let f = lambda * component;
                // residual = internal − external; `external` holds the loads with the
                // residual's sign, as the follower pressure's
                local.work.r[3 * l + i] -= f;
                local.external[3 * l + i] -= f;
                if cx.with_energy {
                    local.energy -= f * cx.ue[l][i];
                }
            }
        }
        Ok(())
    }
}

/// The cantilever with the tip load as a dead traction (built-in factor `traction`), its tip
/// node and the load `P` (N).
fn cantilever() -> (FeModel, usize, f64) {
    let (gm, mut cons) = plane_strain_layer(uniform(0.0, LENGTH, 20), uniform(0.0, THICKNESS, 2));
    cons.extend(fix(&gm.nodes_on_plane(0, 0.0), &[0, 1], 0.0));
    let e = 2.0 * MU * (1.0 + NU);
    let kappa = e / (3.0 * (1.0 - 2.0 * NU));
    let material = Material::from_spec(&format!("neo_hookean:{MU}"), kappa / MU).expect("mu > 0");
    let mut model = FeModel::new(gm.mesh.clone(), material, &cons, &[], &[]).expect("beam mesh");
    let ei = e / (1.0 - NU * NU) * THICKNESS.powi(3) / 12.0;
    let force = LOAD * ei / (LENGTH * LENGTH);
    for (face, _) in gm.boundary_faces(|k| k.is_none()) {
        if face.axis == 0 && face.positive {
            model.add_dead_traction(&face, [0.0, -force / THICKNESS, 0.0]);
        }
    }
    let tip = node_at(&gm, [LENGTH, 0.5 * THICKNESS, 0.0]);
    (model, tip, force)
}

/// The displacements and reports along `k/STEPS · full`, k = 1..=STEPS.
fn ramp(model: &FeModel, full: LoadLevel) -> (Vec<Vec<f64>>, Vec<StepReport>) {
    let levels: Vec<LoadLevel> = (1..=STEPS)
        .map(|k| LoadLevel::ZERO.lerp(&full, k as f64 / STEPS as f64))
        .collect();
    let mut states = Vec::new();
    let reports = solve_path(model, SolverSettings::default(), &levels, |_, state, _| {
        states.push(state.u_full.clone())
    })
    .expect("the small tip load converges");
    (states, reports)
}

#[test]
fn a_load_term_with_its_own_factor_is_ramped_by_the_solver() {
    let tip_load = LoadFactor::register(TIP_LOAD).expect("a free slot");
    let (reference, tip, force) = cantilever();
    // the same nodal forces, moved from the dead traction to the new term
    let mut model = cantilever().0;
    let term = PointLoads::from_nodal_forces(tip_load, &model, &model.f_traction);
    model.f_traction.iter_mut().for_each(|v| *v = 0.0);
    model.add_element_term(Box::new(term));
    assert!(model.load_factors().contains(&tip_load));
    assert!(!reference.load_factors().contains(&tip_load));

    let full = LoadLevel::ZERO.with(tip_load, 1.0);
    let (states, reports) = ramp(&model, full);
    let (expected, _) = ramp(&reference, LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0));

    // the factor reaches 1 along its own path; the others stay 0
    for (k, rep) in reports.iter().enumerate() {
        assert!(rep.converged);
        assert_eq!(rep.level[tip_load], (k + 1) as f64 / STEPS as f64);
        assert_eq!(rep.level.changing(&LoadLevel::ZERO).count(), 1);
    }
    assert_eq!(reports[STEPS - 1].level, full);
    let json = serde_json::to_string(&reports[STEPS - 1].level).unwrap();
    assert!(json.contains(r#""tip load":1.0"#), "{json}");

    // the same equilibria as the dead traction
    for (u, v) in states.iter().zip(&expected) {
        let scale = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = u
            .iter()
            .zip(v)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff <= 1e-6 * scale, "{diff:e} of {scale:e}");
    }

    // the linear beam: δ = P L³ / (3 E' I), and δ at a third of the load is a third of it
    let e_plane = 2.0 * MU * (1.0 + NU) / (1.0 - NU * NU);
    let beam = force * LENGTH.powi(3) / (3.0 * e_plane * THICKNESS.powi(3) / 12.0);
    let deflection = |u: &[f64]| -u[3 * tip + 1];
    let d = deflection(&states[STEPS - 1]);
    assert!((d - beam).abs() <= 0.02 * beam, "{d} mm vs {beam} mm");
    let third = deflection(&states[0]);
    assert!((3.0 * third - d).abs() <= 1e-3 * d, "{third} mm vs {d} mm");

    // at the converged state the residual vanishes with the factor on; with it off, the
    // internal forces are the point loads
    let u = &states[STEPS - 1];
    let residual = |level: &LoadLevel| {
        let mut r = vec![0.0; u.len()];
        model.assemble(u, level, &mut r, None).expect("admissible");
        r
    };
    let (on, off) = (residual(&full), residual(&LoadLevel::ZERO));
    for d in 0..u.len() {
        if model.dofs.eq(d).is_some() {
            let f = reference.f_traction[d];
            assert!(on[d].abs() <= 1e-6 * force, "dof {d}: {}", on[d]);
            assert!(
                (off[d] - f).abs() <= 1e-6 * force,
                "dof {d}: {} vs {f}",
                off[d]
            );
        }
    }
}
