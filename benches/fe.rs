//! Hot paths of the FE model (criterion): one element's residual + tangent, the PSD projection
//! of one element tangent, one full assembly of the coarse actuator, and one sparse
//! factorisation + solve.
//!
//! ```sh
//! cargo bench --bench fe
//! ```
//! The full-ramp benchmark (wall time per mesh level) is `surrogate simulate --bench`.

use criterion::{criterion_group, criterion_main, Criterion};
use surrogate::fe::assembly::projection::project_psd;
use surrogate::fe::assembly::{LoadFactor, LoadLevel};
use surrogate::fe::element::{residual_tangent, ElementWork, DOFS};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{ActuatorModel, ContactSettings, Mode};
use surrogate::fe::solver::{LinearSolver, Ordering};

fn fe(c: &mut Criterion) {
    let design = DesignParams::new(11, 2.0).validate().expect("valid design");
    let material = Material::from_spec("ogden_002", 1000.0).expect("literature set");
    let model = ActuatorModel::new(
        &design,
        &material,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
    )
    .expect("mesh");
    let fe = &model.fe;
    let n = 3 * fe.mesh.n_nodes();
    // a mildly deformed state: 1 % shear of the reference coordinates
    let u: Vec<f64> = (0..n)
        .map(|d| {
            if d % 3 == 2 {
                0.01 * fe.mesh.nodes[d / 3][1]
            } else {
                0.0
            }
        })
        .collect();
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.1)
        .with(LoadFactor::GRAVITY, 1.0);

    let e = fe.mesh.n_elements() / 2;
    let ue: [[f64; 3]; 27] =
        fe.mesh.elements[e].map(|nd| [u[3 * nd], u[3 * nd + 1], u[3 * nd + 2]]);
    let mut work = ElementWork::default();
    c.bench_function("element residual + tangent (Q2/P1, Ogden 002)", |b| {
        b.iter(|| {
            residual_tangent(e, &fe.geometry[e], &ue, &fe.material, true, &mut work)
                .expect("admissible")
        })
    });

    // the minimisation solver's fallback: an element tangent made indefinite (its diagonal
    // lowered by a tenth of its mean) projected onto the PSD cone (eigen-decomposition path)
    residual_tangent(e, &fe.geometry[e], &ue, &fe.material, true, &mut work).expect("admissible");
    let mean_diag = (0..DOFS).map(|i| work.k[i * DOFS + i]).sum::<f64>() / DOFS as f64;
    let mut indefinite = work.k.clone();
    for i in 0..DOFS {
        indefinite[i * DOFS + i] -= 0.1 * mean_diag;
    }
    c.bench_function(
        "PSD projection of an indefinite element tangent (81 × 81)",
        |b| {
            b.iter(|| {
                let mut m = indefinite.clone();
                assert!(project_psd::<DOFS>(&mut m));
                m
            })
        },
    );

    let mut r = vec![0.0; n];
    let mut k = vec![0.0; fe.pattern.nnz()];
    let mut group = c.benchmark_group("coarse actuator (24k dofs)");
    group.sample_size(10);
    group.bench_function("assembly with tangent", |b| {
        b.iter(|| {
            fe.assemble(&u, &level, &mut r, Some(&mut k))
                .expect("admissible")
        })
    });
    group.bench_function("residual only", |b| {
        b.iter(|| fe.assemble(&u, &level, &mut r, None).expect("admissible"))
    });
    fe.assemble(&u, &level, &mut r, Some(&mut k))
        .expect("admissible");
    let mut solver = LinearSolver::new(fe).expect("symbolic analysis");
    let mut rhs = vec![0.0; fe.dofs.n_free];
    fe.restrict(&r, &mut rhs);
    group.bench_function("LDLT factorisation + solve", |b| {
        b.iter(|| {
            let mut x = rhs.clone();
            solver.solve(&k, &mut x).expect("factorisable");
            x
        })
    });
    group.finish();
}

/// One LDLᵀ factorisation + solve of the standard-mesh actuator in force mode (contact pairs
/// and plate in the pattern) with each fill-reducing ordering.
fn orderings(c: &mut Criterion) {
    let design = DesignParams::new(11, 2.0).validate().expect("valid design");
    let material = Material::from_spec("ogden_002", 1000.0).expect("literature set");
    let model = ActuatorModel::new(
        &design,
        &material,
        &MeshOptions::level(MeshLevel::Standard),
        Mode::Force,
        &ContactSettings::default(),
    )
    .expect("mesh");
    let fe = &model.fe;
    let u = vec![0.0; 3 * fe.mesh.n_nodes()];
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.01)
        .with(LoadFactor::GRAVITY, 1.0);
    let mut r = vec![0.0; u.len()];
    let mut k = vec![0.0; fe.pattern.nnz()];
    fe.assemble(&u, &level, &mut r, Some(&mut k))
        .expect("admissible");
    let mut rhs = vec![0.0; fe.dofs.n_free];
    fe.restrict(&r, &mut rhs);
    let mut group = c.benchmark_group("standard actuator, force mode (101k dofs)");
    group.sample_size(10);
    for ordering in [Ordering::MinimumDegree, Ordering::NestedDissection] {
        let mut solver =
            LinearSolver::with_ordering(fe, Some(ordering)).expect("symbolic analysis");
        let name = format!(
            "LDLT factorisation + solve, {ordering:?}, nnz(L) = {}",
            solver.nnz_l()
        );
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut x = rhs.clone();
                solver.solve(&k, &mut x).expect("factorisable");
                x
            })
        });
    }
    group.finish();
}

criterion_group!(benches, fe, orderings);
criterion_main!(benches);
