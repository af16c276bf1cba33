//! Dead loads: gravity (a body force per reference volume, [`FeModel::set_body_force`]) and
//! dead tractions ([`FeModel::add_dead_traction`]), as load vectors scaled by the load
//! level's factors. Their potential is `−f · u`.

use crate::fe::assembly::load::LoadLevel;
use crate::fe::assembly::model::FeModel;

/// Subtracts the dead loads at `level` from `r_full` (all dofs), adds their potential
/// (`−f · u`) to `energy` if given, and returns the squared norm of the external forces on the
/// free dofs (dead loads minus the pressure forces in `pressure_forces`).
pub fn add(
    model: &FeModel,
    u: &[f64],
    level: &LoadLevel,
    pressure_forces: &[f64],
    mut energy: Option<&mut f64>,
    r_full: &mut [f64],
) -> f64 {
    let mut ext2 = 0.0;
    for d in 0..r_full.len() {
        let dead = level.gravity() * model.f_gravity[d] + level.traction() * model.f_traction[d];
        r_full[d] -= dead;
        if let Some(en) = energy.as_deref_mut() {
            *en -= dead * u[d];
        }
        if model.dofs.eq(d).is_some() {
            let f = dead - pressure_forces[d];
            ext2 += f * f;
        }
    }
    ext2
}
