//! Contact of element faces with rigid planes (the clamp block, the force plate): a smoothed
//! penalty on the gap at each face quadrature point, shifted by the augmented-Lagrangian
//! multipliers ([`crate::fe::contact::plane_face`]), or the log barrier of
//! [`super::barrier`] where the model carries one ([`FeModel::barrier`]). Reports each plane's
//! normal force and smallest gap.

use super::term::{ElementContext, ElementTerm, LocalSystem};
use crate::fe::assembly::model::{load_shifts, FeModel};
use crate::fe::contact;
use crate::fe::element::ElementError;

/// Contact with the model's [`FeModel::planes`] on the faces of [`FeModel::contact_faces`].
pub struct PlaneContact;

impl ElementTerm<FeModel> for PlaneContact {
    fn name(&self) -> &'static str {
        "plane contact"
    }

    fn add(
        &self,
        model: &FeModel,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError> {
        let e = cx.element;
        for ((pi, faces), shift) in model.contact_faces[e].iter().zip(&model.plane_shifts[e]) {
            let x0: [[f64; 3]; 9] = faces.map(|l| model.mesh.nodes[cx.conn[l]]);
            let xf: [[f64; 3]; 9] = std::array::from_fn(|a| {
                let l = faces[a];
                [
                    x0[a][0] + cx.ue[l][0],
                    x0[a][1] + cx.ue[l][1],
                    x0[a][2] + cx.ue[l][2],
                ]
            });
            let mut rf = [0.0; 27];
            let mut kf = [0.0; 729];
            let kf_out = cx.with_tangent.then_some(&mut kf);
            let plane = &model.planes[*pi];
            let (ce, cf, cg) = match &model.barrier {
                // the log barrier: no gap shifts
                Some(b) => contact::plane_face_with(
                    |g| b.eval(g),
                    plane,
                    &x0,
                    &xf,
                    &[0.0; 9],
                    &mut rf,
                    kf_out,
                ),
                None => contact::plane_face(plane, &x0, &xf, &load_shifts(shift), &mut rf, kf_out),
            };
            if cx.with_energy {
                local.energy += ce;
            }
            local.plane_forces[*pi] += cf;
            local.plane_gaps[*pi] = local.plane_gaps[*pi].min(cg);
            local.add_face(faces, &rf, cx.with_tangent.then_some(&kf));
        }
        Ok(())
    }
}
