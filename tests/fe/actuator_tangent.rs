//! Directional finite-difference check of the assembled actuator tangent (with pressure and
//! gravity), the symmetry of the tangent, and the linear solve.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::fe::assembly::{LoadFactor, LoadLevel};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{ActuatorModel, ContactSettings, Mode};

/// y = K x with K given by its lower triangle.
fn sym_matvec(col_ptr: &[usize], row_idx: &[usize], k: &[f64], x: &[f64], y: &mut [f64]) {
    y.iter_mut().for_each(|v| *v = 0.0);
    for c in 0..col_ptr.len() - 1 {
        for p in col_ptr[c]..col_ptr[c + 1] {
            let r = row_idx[p];
            y[r] += k[p] * x[c];
            if r != c {
                y[c] += k[p] * x[r];
            }
        }
    }
}

/// Largest error of `K v` against the central difference of the residual along `v` at the
/// free state `free`, relative to max |K v|.
fn directional_fd_error(
    fe: &surrogate::fe::assembly::FeModel,
    free: &[f64],
    level: &LoadLevel,
    v: &[f64],
) -> f64 {
    let n = 3 * fe.mesh.n_nodes();
    let nf = fe.dofs.n_free;
    let mut u = vec![0.0; n];
    fe.expand(free, level, &mut u);
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; fe.pattern.nnz()];
    fe.assemble(&u, level, &mut r, Some(&mut k)).unwrap();
    let mut kv = vec![0.0; nf];
    sym_matvec(&fe.pattern.col_ptr, &fe.pattern.row_idx, &k, v, &mut kv);
    let h = 1e-6;
    let shifted = |s: f64| {
        let f: Vec<f64> = free.iter().zip(v).map(|(a, b)| a + s * b).collect();
        let mut uu = vec![0.0; n];
        fe.expand(&f, level, &mut uu);
        let mut rr = vec![0.0; n];
        fe.assemble(&uu, level, &mut rr, None).unwrap();
        let mut out = vec![0.0; nf];
        fe.restrict(&rr, &mut out);
        out
    };
    let (rp, rm) = (shifted(h), shifted(-h));
    let scale = kv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let err = kv
        .iter()
        .zip(rp.iter().zip(&rm))
        .map(|(a, (p, m))| (a - (p - m) / (2.0 * h)).abs())
        .fold(0.0f64, f64::max);
    err / scale
}

/// The compliant clamp's foundation (springs on the support face instead of the Dirichlet
/// constraint) keeps the tangent exact: with gravity only, and under pressure, where the duct's
/// open end at the support now moves (its load stiffness is then slightly unsymmetric, which the
/// symmetric storage averages; the tolerance says how much).
#[test]
fn tangent_with_a_compliant_clamp_matches_finite_differences() {
    use surrogate::fe::effects::{Effect, Effects};
    let design = DesignParams::new(9, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let effects = Effects::neutral()
        .with(Effect::ClampCompliance, 0.2)
        .unwrap()
        .with(Effect::ClampShearCompliance, 0.1)
        .unwrap();
    let model = ActuatorModel::with_effects(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
        &effects,
    )
    .unwrap();
    let rigid = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
    )
    .unwrap();
    // the support's z and x, y directions are free now (x stays fixed on the symmetry plane)
    assert!(model.fe.dofs.n_free > rigid.fe.dofs.n_free);
    assert_eq!(model.fe.element_term_names().last(), Some(&"foundation"));
    let fe = &model.fe;
    let nf = fe.dofs.n_free;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    for (pressure, tol) in [(0.0, 1e-6), (0.1, 1e-3)] {
        let level = LoadLevel::ZERO
            .with(LoadFactor::PRESSURE, pressure)
            .with(LoadFactor::GRAVITY, 1.0);
        let free: Vec<f64> = (0..nf).map(|_| rng.gen_range(-0.02..=0.02)).collect();
        let v: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
        let rel = directional_fd_error(fe, &free, &level, &v);
        assert!(
            rel < tol,
            "pressure {pressure}: directional FD error {rel:e}"
        );
    }
}

#[test]
fn actuator_tangent_matches_directional_finite_differences() {
    let design = DesignParams::new(9, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let model = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
    )
    .unwrap();
    let fe = &model.fe;
    let nf = fe.dofs.n_free;
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.1)
        .with(LoadFactor::GRAVITY, 1.0);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    for amplitude in [0.0, 0.02] {
        let mut free: Vec<f64> = (0..nf)
            .map(|_| rng.gen_range(-amplitude..=amplitude))
            .collect();
        if amplitude == 0.0 {
            free.iter_mut().for_each(|v| *v = 0.0);
        }
        let v: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
        let rel = directional_fd_error(fe, &free, &level, &v);
        assert!(
            rel < 1e-6,
            "amplitude {amplitude}: directional FD error {rel:e}"
        );
    }
}

#[test]
fn linear_solver_solves_the_actuator_tangent() {
    use surrogate::fe::solver::LinearSolver;
    let design = DesignParams::new(9, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let model = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
    )
    .unwrap();
    let fe = &model.fe;
    let n = 3 * fe.mesh.n_nodes();
    let nf = fe.dofs.n_free;
    let level = LoadLevel::default();
    let u = vec![0.0; n];
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; fe.pattern.nnz()];
    fe.assemble(&u, &level, &mut r, Some(&mut k)).unwrap();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let b: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let mut x = b.clone();
    let mut ls = LinearSolver::new(fe).unwrap();
    ls.solve(&k, &mut x).unwrap();
    let mut kx = vec![0.0; nf];
    sym_matvec(&fe.pattern.col_ptr, &fe.pattern.row_idx, &k, &x, &mut kx);
    let err = kx
        .iter()
        .zip(&b)
        .map(|(a, c)| (a - c).abs())
        .fold(0.0f64, f64::max);
    // relative to the right-hand side (entries of order 1); K has condition ~κ/μ0 · (L/h)²
    assert!(err < 1e-6, "linear solve residual {err:e}");
}

#[test]
fn actuator_residual_is_the_gradient_of_the_total_potential() {
    let design = DesignParams::new(9, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let model = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
    )
    .unwrap();
    let fe = &model.fe;
    let n = 3 * fe.mesh.n_nodes();
    let nf = fe.dofs.n_free;
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.2)
        .with(LoadFactor::GRAVITY, 1.0);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(17);
    let free: Vec<f64> = (0..nf).map(|_| rng.gen_range(-0.02..0.02)).collect();
    let v: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let energy = |s: f64| {
        let f: Vec<f64> = free.iter().zip(&v).map(|(a, b)| a + s * b).collect();
        let mut u = vec![0.0; n];
        fe.expand(&f, &level, &mut u);
        let mut r = vec![0.0; n];
        let info = fe.assemble_with_energy(&u, &level, &mut r, None).unwrap();
        let mut rf = vec![0.0; nf];
        fe.restrict(&r, &mut rf);
        (info.energy, rf)
    };
    let (_, r0) = energy(0.0);
    let h = 1e-5;
    let fd = (energy(h).0 - energy(-h).0) / (2.0 * h);
    let exact: f64 = r0.iter().zip(&v).map(|(a, b)| a * b).sum();
    assert!(
        (fd - exact).abs() <= 1e-6 * exact.abs().max(1e-3),
        "dΠ/ds: FD {fd} vs r·v {exact}"
    );
}

/// Global tangent with bellow-to-bellow contact active: neighbouring walls are pushed into the
/// barrier (gap ≈ 0.3 mm < δ = 0.5 mm) by a smooth axial wave, then perturbed at random.
#[test]
fn actuator_tangent_with_contact_active_matches_finite_differences() {
    tangent_with_contact(false);
}

/// The same with the closest-point gap between the walls.
#[test]
fn actuator_tangent_with_closest_point_contact_matches_finite_differences() {
    tangent_with_contact(true);
}

fn tangent_with_contact(closest_point: bool) {
    let design = DesignParams::new(9, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let contact = ContactSettings {
        enabled: true,
        stiffness: 20.0,
        smoothing: 0.5,
        closest_point,
    };
    let model = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &contact,
    )
    .unwrap();
    let fe = &model.fe;
    assert!(!fe.pairs.is_empty());
    let n = 3 * fe.mesh.n_nodes();
    let nf = fe.dofs.n_free;
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.1)
        .with(LoadFactor::GRAVITY, 1.0);
    let p = design.free_length() / 9.0;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let mut u = vec![0.0; n];
    for (node, x) in fe.mesh.nodes.iter().enumerate() {
        let theta = 2.0 * std::f64::consts::PI * x[2] / p;
        u[3 * node + 2] = -1.1 * theta.sin() * (x[2] / 10.0).min(1.0);
    }
    let mut free = vec![0.0; nf];
    fe.restrict(&u, &mut free);
    free.iter_mut()
        .for_each(|f| *f += rng.gen_range(-0.01..=0.01));
    fe.expand(&free, &level, &mut u);
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; fe.pattern.nnz()];
    let info = fe.assemble(&u, &level, &mut r, Some(&mut k)).unwrap();
    assert!(
        info.pair_force > 0.0 && info.pair_min_gap < 0.5,
        "contact must be active: force {}, gap {}",
        info.pair_force,
        info.pair_min_gap
    );
    let v: Vec<f64> = (0..nf).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let rel = directional_fd_error(fe, &free, &level, &v);
    assert!(
        rel < 1e-6,
        "closest point {closest_point}: directional FD error {rel:e}"
    );
}
