//! The minimisation solver's potential (`surrogate::fe::solver::minimise`): on the coarse
//! actuator with pressure, gravity and the log-barrier contact active on the force plate, the
//! directional derivative of the total potential Π equals the residual along the direction,
//! and the tangent equals the directional derivative of the residual (central differences).

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::fe::assembly::terms::barrier::IpcBarrier;
use surrogate::fe::assembly::{FeModel, LoadFactor, LoadLevel};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{ActuatorModel, ContactSettings, Mode};

/// y = K x with K given by its lower triangle.
fn sym_matvec(fe: &FeModel, k: &[f64], x: &[f64]) -> Vec<f64> {
    let (cp, ri) = (&fe.pattern.col_ptr, &fe.pattern.row_idx);
    let mut y = vec![0.0; x.len()];
    for c in 0..cp.len() - 1 {
        for p in cp[c]..cp[c + 1] {
            let r = ri[p];
            y[r] += k[p] * x[c];
            if r != c {
                y[c] += k[p] * x[r];
            }
        }
    }
    y
}

/// The coarse N = 9, T = 2 actuator in force mode with the plate 0.05 mm below the bottom
/// face, the barrier's activation distance 0.1 mm: every plate contact point of the bottom
/// layer is inside the barrier's active zone for displacements below 0.05 mm.
fn model_with_active_barrier() -> ActuatorModel {
    let design = DesignParams::new(9, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let mut model = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Force,
        &ContactSettings::default(),
    )
    .unwrap();
    let plate = model.plate.unwrap();
    model.fe.planes[plate].point = [0.0, -0.05, 0.0];
    model.fe.barrier = Some(IpcBarrier::new(0.1, 0.2).unwrap());
    model
}

#[test]
fn potential_gradient_and_hessian_match_finite_differences_with_barrier_contact() {
    let model = model_with_active_barrier();
    let fe = &model.fe;
    let (n, nf) = (3 * fe.mesh.n_nodes(), fe.dofs.n_free);
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.1)
        .with(LoadFactor::GRAVITY, 1.0);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(22);
    let free: Vec<f64> = (0..nf).map(|_| rng.gen_range(-0.01..=0.01)).collect();
    let v: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let at = |s: f64, k: Option<&mut [f64]>| {
        let f: Vec<f64> = free.iter().zip(&v).map(|(a, b)| a + s * b).collect();
        let mut u = vec![0.0; n];
        fe.expand(&f, &level, &mut u);
        let mut r = vec![0.0; n];
        let info = fe
            .assemble_potential(&u, &level, &mut r, k, None, false)
            .unwrap();
        let mut rf = vec![0.0; nf];
        fe.restrict(&r, &mut rf);
        (info, rf)
    };
    let mut k = vec![0.0; fe.pattern.nnz()];
    let (info, r) = at(0.0, Some(&mut k));
    // the barrier is active: the plate carries a force
    let plate = model.plate.unwrap();
    assert!(
        info.plane_forces[plate] > 0.0 && info.plane_min_gaps[plate] < 0.1,
        "plate force {} N, smallest gap {} mm",
        info.plane_forces[plate],
        info.plane_min_gaps[plate]
    );
    // gradient: dΠ/ds = r · v, relative to the largest |r_i v_i| summed
    let h = 1e-6;
    let (ip, rp) = at(h, None);
    let (im, rm) = at(-h, None);
    let fd = (ip.energy - im.energy) / (2.0 * h);
    let rv: f64 = r.iter().zip(&v).map(|(a, b)| a * b).sum();
    let size: f64 = r.iter().zip(&v).map(|(a, b)| (a * b).abs()).sum();
    assert!(
        (fd - rv).abs() <= 1e-6 * size,
        "dΠ/ds {fd:e} against r·v {rv:e} (scale {size:e})"
    );
    // Hessian: K v = d r / ds
    let kv = sym_matvec(fe, &k, &v);
    let scale = kv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let err = kv
        .iter()
        .zip(rp.iter().zip(&rm))
        .map(|(a, (p, m))| (a - (p - m) / (2.0 * h)).abs())
        .fold(0.0f64, f64::max);
    assert!(
        err <= 1e-5 * scale,
        "tangent error {err:e} (scale {scale:e})"
    );
}

/// With every element tangent projected onto the PSD cone the residual and Π are unchanged,
/// and the assembled tangent is positive semi-definite along random directions.
#[test]
fn projected_tangent_keeps_the_residual_and_is_positive_semidefinite() {
    let model = model_with_active_barrier();
    let fe = &model.fe;
    let (n, nf) = (3 * fe.mesh.n_nodes(), fe.dofs.n_free);
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.2)
        .with(LoadFactor::GRAVITY, 1.0);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let free: Vec<f64> = (0..nf).map(|_| rng.gen_range(-0.02..=0.02)).collect();
    let mut u = vec![0.0; n];
    fe.expand(&free, &level, &mut u);
    let (mut r0, mut r1) = (vec![0.0; n], vec![0.0; n]);
    let mut k = vec![0.0; fe.pattern.nnz()];
    let i0 = fe
        .assemble_potential(&u, &level, &mut r0, None, None, false)
        .unwrap();
    let i1 = fe
        .assemble_potential(&u, &level, &mut r1, Some(&mut k), None, true)
        .unwrap();
    assert_eq!(r0, r1);
    assert_eq!(i0.energy, i1.energy);
    for _ in 0..5 {
        let v: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
        let kv = sym_matvec(fe, &k, &v);
        let vkv: f64 = kv.iter().zip(&v).map(|(a, b)| a * b).sum();
        assert!(vkv >= 0.0, "vᵀKv = {vkv:e}");
    }
}

/// The blocked-force ramp N = 9, T = 1.6 to 1 bar on the coarse mesh (bellows and plate in
/// contact) by both solvers: the residual Newton with augmented-Lagrangian penalty contact and
/// the minimisation with the log barrier (d̂ = 1e-3 mm). Tip and blocked force agree within
/// 0.2 % at every level (of the tip's displacement, of the force), the tolerance for
/// the standard-mesh comparison of `fe_reference/solver_minimise/`.
#[test]
fn minimisation_and_residual_newton_give_the_same_tip_and_blocked_force() {
    use surrogate::fe::material::DEFAULT_BULK_RATIO;
    use surrogate::fe::simulate::{simulate, Case};
    use surrogate::fe::solver::{MinimiseSettings, SolverKind, SolverSettings};
    let case = |kind: SolverKind| Case {
        design: DesignParams::new(9, 1.6).validate().unwrap(),
        material: Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap(),
        pressures_bar: vec![0.0, 1.0],
        gravity: true,
        mesh: MeshOptions::level(MeshLevel::Coarse),
        solver: SolverSettings {
            kind,
            ..SolverSettings::default()
        },
        mode: Mode::Force,
        contact: ContactSettings::default(),
        effects: Default::default(),
    };
    let newton = simulate(&case(SolverKind::Newton)).unwrap().steps;
    let minimise = simulate(&case(SolverKind::Minimise(MinimiseSettings::default())))
        .unwrap()
        .steps;
    for (a, b) in newton.iter().zip(&minimise) {
        assert!(a.converged && b.converged);
        let tip = a.tip_uz_mm.hypot(a.tip_uy_mm);
        let d = (a.tip_uz_mm - b.tip_uz_mm).hypot(a.tip_uy_mm - b.tip_uy_mm);
        assert!(
            d <= 2e-3 * tip,
            "{} bar: tip ({}, {}) against ({}, {}) mm",
            a.pressure_bar,
            a.tip_uz_mm,
            a.tip_uy_mm,
            b.tip_uz_mm,
            b.tip_uy_mm
        );
        let (fa, fb) = (a.force_n.unwrap(), b.force_n.unwrap());
        assert!(
            (fa - fb).abs() <= 2e-3 * fa.abs().max(1e-3),
            "{} bar: blocked force {fa} against {fb} N",
            a.pressure_bar
        );
    }
    // the contact was active: bellows touch and the plate carries the tip at 1 bar
    assert!(newton[1].force_n.unwrap() > 0.1 && minimise[1].contact_force_n > 0.0);
}
