//! Follower pressure (issue item 5): inflation of a thick-walled, nearly incompressible
//! neo-Hookean cylinder in plane strain against the analytic pressure–stretch relation.
//!
//! Quarter model `A ≤ R ≤ B`, `0 ≤ Θ ≤ π/2`, one element layer with `u_z = 0`, symmetry
//! `u_y = 0` on `y = 0` and `u_x = 0` on `x = 0`, pressure `p` on the inner face (a follower
//! load). The elements are meshed in `(R, Θ, Z)` and mapped node by node, so their edges are
//! curved (quadratic interpolation of the circles).
//!
//! Incompressible plane strain: `r² = R² + a² − A²`, `λ_θ = r/R`, `λ_r = 1/λ_θ`; equilibrium
//! `dσ_r/dr = (σ_θ − σ_r)/r` with `σ_θ − σ_r = μ (λ_θ² − λ_θ⁻²)`, `σ_r(a) = −p`, `σ_r(b) = 0`:
//!
//! ```text
//!   p = ∫_a^b μ (λ_θ² − λ_θ⁻²) / r dr
//!     = μ [ ln(λ_a/λ_b) + (λ_b⁻² − λ_a⁻²)/2 ],      λ_a = a/A,  λ_b = b/B = √(1 + (λ_a² − 1) A²/B²)
//! ```
//!
//! (with `x = r²`, `λ_θ² = x/(x − c)`, `c = a² − A²`, the integrand is
//! `½ (1/(x − c) − 1/x + c/x²) dx`, whose primitive is `−ln λ_θ − ½ (1 − λ_θ⁻²)`).
//! The closed form is checked against Simpson's rule on the integral. The FE inner radius `a` at
//! each applied pressure gives `p_analytic(a/A)`, compared with the applied `p`, and the
//! FE inner displacement `a − A` is compared with the analytic one at the applied pressure.

use super::{fix, nodes_on, plane_strain_layer, uniform, Check};
use surrogate::fe::assembly::{FeModel, LoadFactor, LoadLevel};
use surrogate::fe::material::Material;
use surrogate::fe::solver::{solve_path, SolverSettings};

/// Case name.
pub const CASE: &str = "cylinder_inflation";
/// Inner and outer reference radii (mm).
pub const RADII: (f64, f64) = (1.0, 2.0);
/// Shear modulus (MPa).
pub const MU: f64 = 1.0;
/// Bulk modulus ratio `κ / μ`.
pub const BULK_RATIO: f64 = 1e4;
/// Inner stretches `a/A` at which the analytic pressures are applied.
pub const STRETCHES: [f64; 4] = [1.25, 1.5, 1.75, 2.0];
/// Asserted bound (pressure–stretch relation and inner displacement) at [`ASSERTED`]: the
/// issue asks for 1 %; the errors are ~10⁻⁴ (the compressibility `μ/κ` of the FE material
/// against the incompressible solution), so 10⁻³ still leaves a margin of 4.
pub const TOL: f64 = 1e-3;
/// Meshes `(radial, circumferential)` of the study.
pub const LEVELS: [(usize, usize); 4] = [(1, 2), (2, 4), (4, 8), (8, 16)];
/// The mesh at which the tolerance is asserted.
pub const ASSERTED: (usize, usize) = (4, 8);

/// Analytic pressure at inner stretch `λ_a` (closed form, module docs).
pub fn pressure(la: f64) -> f64 {
    let (a0, b0) = RADII;
    let lb = (1.0 + (la * la - 1.0) * (a0 / b0).powi(2)).sqrt();
    MU * ((la / lb).ln() + 0.5 * (lb.powi(-2) - la.powi(-2)))
}

/// The pressure integral by composite Simpson's rule (`n` even intervals).
pub fn pressure_by_quadrature(la: f64, n: usize) -> f64 {
    let (a0, b0) = RADII;
    let a = la * a0;
    let c = a * a - a0 * a0;
    let b = (b0 * b0 + c).sqrt();
    let f = |r: f64| {
        let l2 = r * r / (r * r - c);
        MU * (l2 - 1.0 / l2) / r
    };
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    h / 3.0 * (f(a) + inner + f(b))
}

/// Mean deformed inner radius at each pressure of [`STRETCHES`] on a `nr × nt` mesh.
pub fn inner_radii(nr: usize, nt: usize) -> Vec<f64> {
    inner_radii_with(nr, nt, SolverSettings::default().predictor).0
}

/// As [`inner_radii`], with the solver's predictor on or off; also the Newton iterations.
pub fn inner_radii_with(nr: usize, nt: usize, predictor: bool) -> (Vec<f64>, usize) {
    let (a0, b0) = RADII;
    let half_pi = std::f64::consts::FRAC_PI_2;
    let (mut gm, mut cons) = plane_strain_layer(uniform(a0, b0, nr), uniform(0.0, half_pi, nt));
    gm.map_nodes(|[r, t, z]| [r * t.cos(), r * t.sin(), z]);
    cons.extend(fix(&gm.nodes_on_plane(1, 0.0), &[1], 0.0));
    cons.extend(fix(&gm.nodes_on_plane(1, half_pi), &[0], 0.0));
    let inner_faces: Vec<_> = gm
        .boundary_faces(|k| k.is_none())
        .into_iter()
        .filter(|(f, _)| f.axis == 0 && !f.positive)
        .map(|(f, _)| (f, 1.0))
        .collect();
    let material = Material::from_spec(&format!("neo_hookean:{MU}"), BULK_RATIO).expect("mu > 0");
    let model = FeModel::new(gm.mesh.clone(), material, &cons, &inner_faces, &[])
        .expect("valid cylinder mesh");
    let levels: Vec<LoadLevel> = STRETCHES
        .iter()
        .map(|&l| LoadLevel::ZERO.with(LoadFactor::PRESSURE, pressure(l)))
        .collect();
    let settings = SolverSettings {
        initial_pressure_increment: 0.05,
        max_pressure_increment: 0.2,
        predictor,
        ..Default::default()
    };
    let inner = nodes_on(&gm, &[(0, a0), (2, 0.0)]);
    let x = &model.mesh.nodes;
    let mut iterations = 0;
    let mut radii = Vec::new();
    solve_path(&model, settings, &levels, |_, state, report| {
        iterations += report.newton_iterations;
        let u = &state.u_full;
        let r: f64 = inner
            .iter()
            .map(|&n| (x[n][0] + u[3 * n]).hypot(x[n][1] + u[3 * n + 1]))
            .sum();
        radii.push(r / inner.len() as f64);
    })
    .unwrap_or_else(|e| panic!("{CASE}: solver failed: {e}"));
    (radii, iterations)
}

/// The checks on a `nr × nt` mesh (asserted at [`ASSERTED`]).
pub fn run(nr: usize, nt: usize) -> Vec<Check> {
    let a0 = RADII.0;
    let tol = ((nr, nt) == ASSERTED).then_some(TOL);
    let refinement = format!("{nr}x{nt}");
    let mut checks = Vec::new();
    for (&l, a) in STRETCHES.iter().zip(inner_radii(nr, nt)) {
        let p = pressure(l);
        let mut by_pressure = Check::relative(
            CASE,
            &refinement,
            &format!("p(a_FE/A) vs applied p={p:.4}"),
            pressure(a / a0),
            p,
        );
        let mut by_radius = Check::relative(
            CASE,
            &refinement,
            &format!("a-A at p={p:.4} (a/A={l})"),
            a - a0,
            (l - 1.0) * a0,
        );
        by_pressure.tolerance = tol;
        by_radius.tolerance = tol;
        checks.extend([by_pressure, by_radius]);
    }
    checks
}

/// Every mesh.
pub fn study() -> Vec<Check> {
    LEVELS.iter().flat_map(|&(nr, nt)| run(nr, nt)).collect()
}
