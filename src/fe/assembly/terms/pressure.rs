//! Follower pressure on the cavity faces: `−p n da` on the deformed faces of each element's
//! pressurised faces ([`crate::fe::loads::pressure_face`]), with its load-stiffness tangent.
//! Its potential is `−p ΔV_cavity`, written as `p Σ (1/3)∫(x − o)·n da` about the model's
//! [`FeModel::pressure_origin`].

// Index loops mirror the local (node, component) layout.
#![allow(clippy::needless_range_loop)]

use super::term::{ElementContext, ElementTerm, LocalSystem};
use crate::fe::assembly::load::LoadFactor;
use crate::fe::assembly::model::FeModel;
use crate::fe::element::ElementError;
use crate::fe::loads;

/// The cavity pressure on the faces listed in [`FeModel::pressure_faces`].
pub struct Pressure;

impl ElementTerm<FeModel> for Pressure {
    fn name(&self) -> &'static str {
        "pressure"
    }

    fn load_factor(&self) -> Option<LoadFactor> {
        Some(LoadFactor::PRESSURE)
    }

    fn add(
        &self,
        model: &FeModel,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError> {
        for pf in &model.pressure_faces[cx.element] {
            let xf: [[f64; 3]; 9] = pf.local.map(|l| cx.position(l));
            let mut rf = [0.0; 27];
            let mut kf = [0.0; 729];
            let p = cx.level[LoadFactor::PRESSURE] * pf.scale;
            loads::pressure_face(p, &xf, &mut rf, cx.with_tangent.then_some(&mut kf));
            if cx.with_energy {
                let o = model.pressure_origin;
                let rel = xf.map(|x| [x[0] - o[0], x[1] - o[1], x[2] - o[2]]);
                local.energy += p * loads::face_volume(&rel);
            }
            for (a, &la) in pf.local.iter().enumerate() {
                for i in 0..3 {
                    local.external[3 * la + i] += rf[3 * a + i];
                }
            }
            local.add_face(&pf.local, &rf, cx.with_tangent.then_some(&kf));
        }
        Ok(())
    }
}
