//! Large rotation (issue item 6): a slender cantilever under a vertical dead tip load against
//! the inextensible elastica.
//!
//! Beam `L × h = 100 × 2` mm (plane strain: one element layer of thickness 1, `u_z = 0`),
//! clamped at `x = 0`, a uniform dead shear traction `−P/h` on the tip face `x = L`. The
//! elastica, with `θ(s)` the rotation of the centre line and `k = P L² / EI`:
//!
//! ```text
//!   θ'' = −(k/L²) cos θ,   θ(0) = 0,   θ'(L) = 0 (no tip moment);   x' = cos θ,  y' = −sin θ
//! ```
//!
//! solved by shooting on `θ'(0)` (bisection, RK4 with 4000 steps: error far below 10⁻⁶).
//!
//! Material and stiffness: compressible neo-Hookean, `μ = 1`, `ν = 0.3` (`κ = 2μ(1+ν)/(3(1−2ν))`).
//! With `u_z = 0` the beam is in plane strain, so its small-strain bending stiffness is
//! `EI = E/(1 − ν²) · h³/12` per unit width. The elastica neglects shear and axial strain
//! (relative effects `~(h/L)² ≈ 4·10⁻⁴` and `P/(EA) ≈ k h²/(12 L²) ≈ 10⁻⁴`) and the material
//! nonlinearity: the largest bending strain is `κ(0) h/2 ≲ k h/(2L) = 3 %`, where the
//! neo-Hookean moment–curvature relation departs from the linear one by `O(ε²) ≈ 10⁻³`; the
//! root clamp also blocks the Poisson contraction over a length `~h`. All are well below the
//! 2 % tolerance on the tip deflection and shortening. `k = 3` gives a tip rotation of 56.5°
//! (elastica: δ/L = 0.3017, 0.4935, 0.6033 at k = 1, 2, 3, the classical Bisshopp–Drucker values).

use super::{fix, node_at, plane_strain_layer, ramp, uniform, Check};
use surrogate::fe::assembly::{FeModel, LoadFactor, LoadLevel};
use surrogate::fe::material::Material;
use surrogate::fe::solver::{solve_path, SolverSettings};

/// Case name.
pub const CASE: &str = "cantilever_elastica";
/// Length and thickness (mm).
pub const LENGTH: f64 = 100.0;
/// Thickness (mm).
pub const THICKNESS: f64 = 2.0;
/// Shear modulus (MPa).
pub const MU: f64 = 1.0;
/// Poisson ratio.
pub const NU: f64 = 0.3;
/// Load parameter `k = P L² / EI` at full load.
pub const LOAD: f64 = 3.0;
/// Output load levels (fractions of [`LOAD`]).
pub const STEPS: usize = 3;
/// Asserted bound at [`ASSERTED`].
pub const TOL: f64 = 0.02;
/// Meshes `(along, through)` of the study.
pub const LEVELS: [(usize, usize); 4] = [(5, 1), (10, 1), (20, 2), (40, 4)];
/// The mesh at which the tolerance is asserted.
pub const ASSERTED: (usize, usize) = (20, 2);

/// The elastica's tip: `(tip rotation (rad), deflection / L, shortening / L)` at `k = P L²/EI`.
pub fn elastica(k: f64) -> (f64, f64, f64) {
    // state (θ, θ', x, y) in s/L ∈ [0, 1], deflection y positive
    let rhs = |y: [f64; 4]| [y[1], -k * y[0].cos(), y[0].cos(), y[0].sin()];
    let shoot = |curv0: f64| {
        let n = 4000;
        let h = 1.0 / n as f64;
        let mut y = [0.0, curv0, 0.0, 0.0];
        for _ in 0..n {
            let k1 = rhs(y);
            let k2 = rhs(std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]));
            let k3 = rhs(std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]));
            let k4 = rhs(std::array::from_fn(|i| y[i] + h * k3[i]));
            y = std::array::from_fn(|i| {
                y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        y
    };
    // θ'(1) < 0 at θ'(0) = 0 and ≥ 0 at θ'(0) = k (the linear root curvature bounds it)
    let (mut lo, mut hi) = (0.0, k);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if shoot(mid)[1] < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let y = shoot(0.5 * (lo + hi));
    (y[0], y[3], 1.0 - y[2])
}

/// FE tip `(deflection, shortening)` (centre of the tip face) at every output level.
pub fn tip_displacements(nx: usize, ny: usize) -> Vec<(f64, f64)> {
    tip_displacements_with(nx, ny, SolverSettings::default().predictor).0
}

/// As [`tip_displacements`], with the solver's predictor on or off; also the Newton
/// iterations of the whole ramp.
pub fn tip_displacements_with(nx: usize, ny: usize, predictor: bool) -> (Vec<(f64, f64)>, usize) {
    let (gm, mut cons) = plane_strain_layer(uniform(0.0, LENGTH, nx), uniform(0.0, THICKNESS, ny));
    let e = 2.0 * MU * (1.0 + NU);
    let kappa = e / (3.0 * (1.0 - 2.0 * NU));
    let material = Material::from_spec(&format!("neo_hookean:{MU}"), kappa / MU).expect("mu > 0");
    let ei = e / (1.0 - NU * NU) * THICKNESS.powi(3) / 12.0;
    let force = LOAD * ei / (LENGTH * LENGTH);
    cons.extend(fix(&gm.nodes_on_plane(0, 0.0), &[0, 1], 0.0));
    let mut model =
        FeModel::new(gm.mesh.clone(), material, &cons, &[], &[]).expect("valid beam mesh");
    for (face, _) in gm.boundary_faces(|k| k.is_none()) {
        if face.axis == 0 && face.positive {
            model.add_dead_traction(&face, [0.0, -force / THICKNESS, 0.0]);
        }
    }
    let full = LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0);
    let tip = node_at(&gm, [LENGTH, 0.5 * THICKNESS, 0.0]);
    let settings = SolverSettings {
        predictor,
        ..Default::default()
    };
    let mut iterations = 0;
    let mut tips = Vec::new();
    solve_path(&model, settings, &ramp(full, STEPS), |_, state, report| {
        iterations += report.newton_iterations;
        tips.push((-state.u_full[3 * tip + 1], -state.u_full[3 * tip]));
    })
    .unwrap_or_else(|e| panic!("{CASE}: solver failed: {e}"));
    (tips, iterations)
}

/// The checks on an `nx × ny` mesh (asserted at [`ASSERTED`]).
pub fn run(nx: usize, ny: usize) -> Vec<Check> {
    let tol = ((nx, ny) == ASSERTED).then_some(TOL);
    let refinement = format!("{nx}x{ny}");
    let mut checks = Vec::new();
    for (i, (deflection, shortening)) in tip_displacements(nx, ny).into_iter().enumerate() {
        let k = LOAD * (i + 1) as f64 / STEPS as f64;
        let (rotation, d, s) = elastica(k);
        let at = format!("k={k} ({:.1} deg)", rotation.to_degrees());
        let mut c1 = Check::relative(
            CASE,
            &refinement,
            &format!("tip deflection, {at}"),
            deflection,
            d * LENGTH,
        );
        let mut c2 = Check::relative(
            CASE,
            &refinement,
            &format!("tip shortening, {at}"),
            shortening,
            s * LENGTH,
        );
        c1.tolerance = tol;
        c2.tolerance = tol;
        checks.extend([c1, c2]);
    }
    checks
}

/// Every mesh.
pub fn study() -> Vec<Check> {
    LEVELS.iter().flat_map(|&(nx, ny)| run(nx, ny)).collect()
}
