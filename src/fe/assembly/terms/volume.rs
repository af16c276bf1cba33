//! The hyperelastic volume term: internal forces and tangent of one Q2 hexahedron with the
//! mixed (u, θ, π) formulation condensed per element ([`crate::fe::element`]), any material
//! of [`crate::fe::material`]. It opens every element's local system.

use super::term::{ElementContext, ElementTerm, LocalSystem};
use crate::fe::assembly::model::FeModel;
use crate::fe::element::{self, ElementError};

/// Strain energy of the material: `∫ W(F) dV`.
pub struct Volume;

impl ElementTerm<FeModel> for Volume {
    fn name(&self) -> &'static str {
        "volume"
    }

    fn add(
        &self,
        model: &FeModel,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError> {
        local.work.tangent_pressure = cx.mixed;
        local.energy = element::residual_tangent(
            cx.element,
            &model.geometry[cx.element],
            &cx.ue,
            &model.material,
            cx.with_tangent,
            &mut local.work,
        )?;
        // a printed part stiffer or softer than the material: every term of its strain
        // energy scaled (the mixed pressure given to the tangent is the material's own, so
        // the scaled tangent stays consistent)
        let s = model.stiffness[cx.element];
        if s != 1.0 {
            local.energy *= s;
            local.work.r.iter_mut().for_each(|v| *v *= s);
            if cx.with_tangent {
                local.work.k.iter_mut().for_each(|v| *v *= s);
            }
        }
        Ok(())
    }
}
