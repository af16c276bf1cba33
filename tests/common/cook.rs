//! Cook's membrane (issue item 4): a tapered plate, clamped on the left, with a vertical dead
//! shear load on the right edge, of nearly incompressible neo-Hookean material in plane strain.
//!
//! Corners (0, 0), (48, 44), (48, 60), (0, 44) mm; `E = 240.565` MPa, `ν = 0.4999`, so
//! `μ = E / (2(1 + ν))`, `κ = E / (3(1 − 2ν))` (κ/μ ≈ 5000); total shear force 100 N per unit
//! thickness, i.e. a traction of 100/16 = 6.25 MPa on the right edge of height 16. Plane strain
//! is one element layer of thickness 1 with `u_z = 0` on every node. The measured quantity is
//! the vertical displacement of the top-right corner, against the converged reference value
//! 6.89 mm of the issue (within 2 % on a 16×16 Q2 mesh); the coarser meshes show convergence.

use super::{fix, node_at, plane_strain_layer, ramp, solve, uniform, Check};
use surrogate::fe::assembly::{FeModel, LoadFactor, LoadLevel};
use surrogate::fe::material::{Material, MaterialLaw, NeoHookean};
use surrogate::fe::solver::SolverSettings;

/// Case name.
pub const CASE: &str = "cook_membrane";
/// Young's modulus (MPa).
pub const E: f64 = 240.565;
/// Poisson ratio.
pub const NU: f64 = 0.4999;
/// Total vertical force per unit thickness (N/mm).
pub const FORCE: f64 = 100.0;
/// Reference vertical displacement of the top-right corner (mm).
pub const REFERENCE: f64 = 6.89;
/// Asserted bound at [`ASSERTED`].
pub const TOL: f64 = 0.02;
/// Elements per side of the studied meshes.
pub const LEVELS: [usize; 4] = [2, 4, 8, 16];

/// The mesh at which the tolerance is asserted.
pub const ASSERTED: usize = 16;

/// Maps the unit square (s, t) onto the membrane (bilinear), z ∈ [0, 1] unchanged.
fn membrane([s, t, z]: [f64; 3]) -> [f64; 3] {
    [48.0 * s, 44.0 * s + t * (44.0 - 28.0 * s), z]
}

/// Vertical displacement of the top-right corner of the `n × n` membrane, solved along the
/// load path from zero. 6 load levels with line search took the fewest Newton iterations
/// (53 on 16×16) of 1, 2, 4, 5, 6, 7, 8, 12, 16 levels (with and without line search). (Starting 16×16 from the
/// interpolated 8×8 solution does not work: the finer pressure projection turns the coarse
/// field's local volume changes into volumetric stresses ~κ·10⁻², and Newton stalls there.)
pub fn corner_displacement(n: usize) -> f64 {
    let (mut gm, mut cons) = plane_strain_layer(uniform(0.0, 1.0, n), uniform(0.0, 1.0, n));
    gm.map_nodes(membrane);
    let mu = E / (2.0 * (1.0 + NU));
    let kappa = E / (3.0 * (1.0 - 2.0 * NU));
    let law = MaterialLaw::NeoHookean(NeoHookean::new(mu).expect("mu > 0"));
    let material = Material::with_kappa(law, kappa).expect("kappa > 0");
    cons.extend(fix(&gm.nodes_on_plane(0, 0.0), &[0, 1], 0.0));
    let mut model =
        FeModel::new(gm.mesh.clone(), material, &cons, &[], &[]).expect("valid membrane mesh");
    for (face, _) in gm.boundary_faces(|k| k.is_none()) {
        if face.axis == 0 && face.positive {
            model.add_dead_traction(&face, [0.0, FORCE / 16.0, 0.0]);
        }
    }
    let total: f64 = model.f_traction.iter().skip(1).step_by(3).sum();
    assert!((total - FORCE).abs() < 1e-9 * FORCE, "shear load {total} N");
    let full = LoadLevel::ZERO.with(LoadFactor::TRACTION, 1.0);
    let settings = SolverSettings {
        line_search: true,
        ..Default::default()
    };
    let u = solve(CASE, &model, settings, &ramp(full, 6))
        .pop()
        .expect("one state per level");
    u[3 * node_at(&gm, [1.0, 1.0, 0.0]) + 1]
}

/// The checks on every mesh of [`LEVELS`] (asserted at [`ASSERTED`]).
pub fn study() -> Vec<Check> {
    LEVELS
        .iter()
        .map(|&n| {
            let check = Check::relative(
                CASE,
                &format!("{n}x{n}"),
                "corner u_y (mm)",
                corner_displacement(n),
                REFERENCE,
            );
            if n == ASSERTED {
                check.with_tolerance(TOL)
            } else {
                check
            }
        })
        .collect()
}
