//! Element and global tangents against finite differences (STYLE: every derivative checked).

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::fe::assembly::{Constraint, FeModel, LoadFactor, LoadLevel};
use surrogate::fe::element::{residual_tangent, ElementGeometry, ElementWork, DOFS};
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{GridMesh, TensorGrid};

fn materials() -> Vec<(&'static str, Material)> {
    vec![
        (
            "neo_hookean",
            Material::from_spec("neo_hookean:1.0", 100.0).unwrap(),
        ),
        (
            "ogden_002",
            Material::from_spec("ogden_002", 1000.0).unwrap(),
        ),
        (
            "mooney_rivlin_5",
            Material::from_spec("mooney_rivlin_5", 1000.0).unwrap(),
        ),
    ]
}

/// A distorted reference element and a random displacement.
fn element_setup(seed: u64) -> ([[f64; 3]; 27], [[f64; 3]; 27]) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let x: [[f64; 3]; 27] = std::array::from_fn(|a| {
        let p = [(a % 3) as f64, ((a / 3) % 3) as f64, (a / 9) as f64];
        [
            1.2 * p[0] + 0.1 * p[1] + rng.gen_range(-0.05..0.05),
            0.8 * p[1] + rng.gen_range(-0.05..0.05),
            0.5 * p[2] + 0.05 * p[0] + rng.gen_range(-0.05..0.05),
        ]
    });
    let u: [[f64; 3]; 27] = std::array::from_fn(|_| {
        [
            rng.gen_range(-0.08..0.08),
            rng.gen_range(-0.08..0.08),
            rng.gen_range(-0.05..0.05),
        ]
    });
    (x, u)
}

#[test]
fn element_residual_is_energy_gradient_and_tangent_is_residual_jacobian() {
    for (name, mat) in materials() {
        let (x, u) = element_setup(7);
        let geo = ElementGeometry::new(0, &x).unwrap();
        let mut w = ElementWork::default();
        w.with_energy = true;
        residual_tangent(0, &geo, &u, &mat, true, &mut w).unwrap();
        let r0 = w.r.clone();
        let k0 = w.k.clone();
        let h = 1e-6;
        let mut max_k_err: f64 = 0.0;
        let mut max_r_err: f64 = 0.0;
        let kscale = k0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let rscale = r0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for c in 0..DOFS {
            let (mut up, mut um) = (u, u);
            up[c / 3][c % 3] += h;
            um[c / 3][c % 3] -= h;
            let ep = residual_tangent(0, &geo, &up, &mat, false, &mut w).unwrap();
            let rp = w.r.clone();
            let em = residual_tangent(0, &geo, &um, &mat, false, &mut w).unwrap();
            let rm = w.r.clone();
            max_r_err = max_r_err.max(((ep - em) / (2.0 * h) - r0[c]).abs() / rscale);
            for r in 0..DOFS {
                let fd = (rp[r] - rm[r]) / (2.0 * h);
                max_k_err = max_k_err.max((fd - k0[r * DOFS + c]).abs() / kscale);
            }
        }
        assert!(
            max_r_err < 1e-6,
            "{name}: residual vs energy FD error {max_r_err:e}"
        );
        assert!(
            max_k_err < 1e-6,
            "{name}: tangent vs residual FD error {max_k_err:e}"
        );
    }
}

#[test]
fn global_tangent_with_pressure_matches_finite_differences() {
    // a 2x2x2 block of elements with a pressurised top face and a clamped bottom
    let grid = TensorGrid {
        lines: [
            vec![0.0, 1.0, 2.0],
            vec![0.0, 1.0, 2.0],
            vec![0.0, 1.5, 3.0],
        ],
    };
    let gm = GridMesh::new(grid, |_| true, |s| s);
    let clamp = gm.nodes_on_plane(2, 0.0);
    let mut cons = Vec::new();
    for &n in &clamp {
        for comp in 0..3 {
            cons.push(Constraint {
                node: n,
                comp,
                value: 0.0,
            });
        }
    }
    let faces: Vec<_> = gm
        .boundary_faces(|k| k.is_none())
        .into_iter()
        .filter(|(f, _)| f.axis == 0 || f.axis == 2 && f.positive)
        .map(|(f, _)| (f, 1.0))
        .collect();
    for (name, mat) in materials() {
        let model = FeModel::new(gm.mesh.clone(), mat, &cons, &faces, &[]).unwrap();
        let n = 3 * model.mesh.n_nodes();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let mut u: Vec<f64> = (0..n).map(|_| rng.gen_range(-0.05..0.05)).collect();
        for &(d, _) in &model.dofs.constrained {
            u[d] = 0.0;
        }
        let level = LoadLevel::ZERO.with(LoadFactor::PRESSURE, 0.3);
        let mut r = vec![0.0; n];
        let mut k = vec![0.0; model.pattern.nnz()];
        model.assemble(&u, &level, &mut r, Some(&mut k)).unwrap();
        let kscale = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let h = 1e-6;
        let mut err: f64 = 0.0;
        for d in 0..n {
            let Some(col) = model.dofs.eq(d) else {
                continue;
            };
            let (mut up, mut um) = (u.clone(), u.clone());
            up[d] += h;
            um[d] -= h;
            let mut rp = vec![0.0; n];
            let mut rm = vec![0.0; n];
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
        assert!(err < 1e-6, "{name}: global tangent FD error {err:e}");
    }
}

/// The mixed iteration's pressure `π_lin(u, du)` is the linearisation of the consistent
/// projected pressure: `π_lin(u, 0) = π(u)` and `∂π_lin/∂du · du = dπ(u + ε du)/dε`.
#[test]
fn linearised_pressure_is_the_derivative_of_the_projected_pressure() {
    use surrogate::fe::element::linearised_pressure;
    let mat = Material::from_spec("ogden_002", 1000.0).unwrap();
    let (x, u) = element_setup(11);
    let (_, du) = element_setup(12);
    let geo = ElementGeometry::new(0, &x).unwrap();
    let zero = [[0.0; 3]; 27];
    let shifted = |s: f64| -> [[f64; 3]; 27] {
        std::array::from_fn(|a| std::array::from_fn(|i| u[a][i] + s * du[a][i]))
    };
    let scaled = |s: f64| -> [[f64; 3]; 27] { std::array::from_fn(|a| du[a].map(|v| s * v)) };
    let p0 = linearised_pressure(0, &geo, &u, &zero, &mat).unwrap();
    let eps = 1e-6;
    let lin = linearised_pressure(0, &geo, &u, &scaled(eps), &mat).unwrap();
    let plus = linearised_pressure(0, &geo, &shifted(eps), &zero, &mat).unwrap();
    let minus = linearised_pressure(0, &geo, &shifted(-eps), &zero, &mat).unwrap();
    let scale = p0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for l in 0..4 {
        let analytic = (lin[l] - p0[l]) / eps;
        let fd = (plus[l] - minus[l]) / (2.0 * eps);
        assert!(
            (analytic - fd).abs() <= 1e-6 * fd.abs().max(scale),
            "coefficient {l}: analytic {analytic:.9e} vs FD {fd:.9e}"
        );
    }
    // the consistent pressure enters the residual: with the linearised pressure at du = 0 as
    // tangent pressure the element tangent is the exact one
    let mut w = ElementWork::default();
    residual_tangent(0, &geo, &u, &mat, true, &mut w).unwrap();
    let exact = w.k.clone();
    w.tangent_pressure = Some(p0);
    residual_tangent(0, &geo, &u, &mat, true, &mut w).unwrap();
    let kmax = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (a, b) in exact.iter().zip(&w.k) {
        assert!((a - b).abs() <= 1e-12 * kmax);
    }
}
