//! Patch test (issue item 3): a distorted mesh whose boundary nodes all follow a linear
//! displacement field `u = s A X` (load factor `s`) must reproduce that field exactly in the
//! interior, with a uniform stress `P(I + s A)` at every quadrature point.
//!
//! The Q2 isoparametric map contains every linear function of `X`, whatever the (curved,
//! distorted) element shapes; a homogeneous `F` is an equilibrium state of every element
//! (`∫ P ∇N_a dV` sums to zero at interior nodes), and the projected dilatation `θ = P₁[J]` of
//! a constant `J` is `J` itself. So the only error is the solver's: the tolerance `10⁻¹⁰` (on
//! `max |u − s A X| / max |s A X|`) is the Newton precision, and the stress must be uniform to
//! the same order (`10⁻⁸`, stress being a derivative).

use super::{block, fix, ramp, solve, Check};
use nalgebra::Matrix3;
use surrogate::fe::assembly::{FeModel, LoadFactor, LoadLevel};
use surrogate::fe::material::Material;
use surrogate::fe::mesh::GridMesh;
use surrogate::fe::solver::SolverSettings;

/// Case name.
pub const CASE: &str = "patch_test";
/// Asserted bound on the displacement error.
pub const TOL_DISPLACEMENT: f64 = 1e-10;
/// Asserted bound on the stress non-uniformity.
pub const TOL_STRESS: f64 = 1e-8;
/// The gradient direction; scaled by [`SCALES`].
pub const A: [[f64; 3]; 3] = [[0.5, 0.2, -0.1], [0.1, -0.3, 0.25], [-0.2, 0.15, 0.4]];
/// Small and moderately large gradients.
pub const SCALES: [f64; 2] = [1e-3, 0.6];
/// Elements per direction of the studied meshes.
pub const LEVELS: [usize; 2] = [2, 3];

/// The distorted mesh of `n³` elements of the unit cube: non-uniform grid, interior nodes
/// moved by a smooth bump and the whole block sheared and bent (curved element edges).
pub fn distorted_mesh(n: usize) -> GridMesh<bool> {
    let line: Vec<f64> = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            t + 0.15 * (std::f64::consts::PI * t).sin() * (t - 0.5)
        })
        .collect();
    let mut gm = block([line.clone(), line.clone(), line]);
    let pi = std::f64::consts::PI;
    gm.map_nodes(|[x, y, z]| {
        let b = 0.12 * (pi * x).sin() * (pi * y).sin() * (pi * z).sin();
        [
            x + 0.25 * y * y + b,
            y + 0.1 * x * z - 0.7 * b,
            z + 0.2 * x * y + 0.5 * b,
        ]
    });
    gm
}

/// Runs the patch test on `n³` elements with gradient `scale · A`.
pub fn run(n: usize, scale: f64) -> Vec<Check> {
    let gm = distorted_mesh(n);
    let material = Material::from_spec("ogden_002", 1000.0).expect("literature set");
    let a = Matrix3::from_fn(|i, j| scale * A[i][j]);
    let x = &gm.mesh.nodes;
    let exact = |node: usize| a * nalgebra::Vector3::from(x[node]);
    let boundary: Vec<usize> = (0..x.len())
        .filter(|&node| {
            (0..3).any(|axis| {
                let g = gm.node_grid[node][axis];
                g == 0 || g == 2 * n
            })
        })
        .collect();
    let mut cons = Vec::new();
    for &node in &boundary {
        let u = exact(node);
        for comp in 0..3 {
            cons.extend(fix(&[node], &[comp], u[comp]));
        }
    }
    let interior = x.len() - boundary.len();
    assert!(interior > 0, "patch without interior nodes");
    let model = FeModel::new(gm.mesh.clone(), material.clone(), &cons, &[], &[])
        .expect("distorted mesh is valid");
    let full = LoadLevel::ZERO.with(LoadFactor::PRESCRIBED, 1.0);
    let settings = SolverSettings {
        rtol: 1e-12,
        line_search: true,
        ..Default::default()
    };
    let levels = ramp(full, 2);
    let states = solve(CASE, &model, settings, &levels);
    let refinement = format!("{n}^3,|A|={scale}");
    let mut checks = Vec::new();
    for (level, u) in levels.iter().zip(&states) {
        let s = level.prescribed();
        let mut err: f64 = 0.0;
        let mut size: f64 = 0.0;
        for node in 0..x.len() {
            let e = exact(node) * s;
            size = size.max(e.amax());
            for comp in 0..3 {
                err = err.max((u[3 * node + comp] - e[comp]).abs());
            }
        }
        let f_exact = Matrix3::identity() + a * s;
        let p_exact = material.stress(&f_exact);
        let mut stress_err: f64 = 0.0;
        for (conn, geo) in model.mesh.elements.iter().zip(&model.geometry) {
            for dndx in geo.dndx.iter() {
                let mut f = Matrix3::identity();
                for (node, dn) in conn.iter().zip(dndx) {
                    for i in 0..3 {
                        for j in 0..3 {
                            f[(i, j)] += u[3 * node + i] * dn[j];
                        }
                    }
                }
                stress_err = stress_err.max((material.stress(&f) - p_exact).amax());
            }
        }
        let quantity = format!("s={s}: max|u-sAX|/max|sAX|");
        checks.push(
            Check::scaled(CASE, &refinement, &quantity, err, 0.0, size)
                .with_tolerance(TOL_DISPLACEMENT),
        );
        let quantity = format!("s={s}: max|P-P(I+sA)|/max|P|");
        checks.push(
            Check::scaled(
                CASE,
                &refinement,
                &quantity,
                stress_err,
                0.0,
                p_exact.amax(),
            )
            .with_tolerance(TOL_STRESS),
        );
    }
    checks
}

/// Both gradients on every mesh.
pub fn study() -> Vec<Check> {
    LEVELS
        .iter()
        .flat_map(|&n| SCALES.iter().flat_map(move |&s| run(n, s)))
        .collect()
}
