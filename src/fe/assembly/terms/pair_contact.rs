//! Deformable–deformable contact between facing bellow walls: a smoothed penalty on the gap
//! between the two faces of each pair ([`crate::fe::contact::pair_face`]), with
//! augmented-Lagrangian shifts, or the log barrier of [`super::barrier`] where the model
//! carries one ([`FeModel::barrier`]). A pair couples 18 nodes of two elements that may share a
//! colour, so pairs are evaluated in parallel and added serially, in pair order.

use rayon::prelude::*;

use crate::fe::assembly::model::{load_shifts, FeModel};
use crate::fe::assembly::scatter::GlobalSystem;
use crate::fe::contact::{self, PAIR_DOFS};

/// Transmitted normal force (N) and smallest gap (mm) of the face pairs.
#[derive(Clone, Copy, Debug)]
pub struct PairOutputs {
    /// Total normal force.
    pub force: f64,
    /// Smallest gap at a quadrature point.
    pub min_gap: f64,
}

/// Adds the face pairs' contact at the full displacement `u` to `global`, and their penalty
/// energy to `energy` if given.
pub fn add(
    model: &FeModel,
    u: &[f64],
    mut energy: Option<&mut f64>,
    global: &mut GlobalSystem<'_>,
) -> PairOutputs {
    let mut out = PairOutputs {
        force: 0.0,
        min_gap: f64::INFINITY,
    };
    if model.pairs.is_empty() {
        return out;
    }
    let with_k = global.tangent.is_some();
    let pos = |n: usize| {
        let x = model.mesh.nodes[n];
        [x[0] + u[3 * n], x[1] + u[3 * n + 1], x[2] + u[3 * n + 2]]
    };
    type PairLocal = (f64, f64, f64, Option<Box<([f64; PAIR_DOFS], Vec<f64>)>>);
    let results: Vec<PairLocal> = model
        .pairs
        .par_iter()
        .zip(&model.pair_shifts)
        .map(|(p, shift)| {
            let x0b = p.back.map(|n| model.mesh.nodes[n]);
            let xb = p.back.map(pos);
            let xf = p.front.map(pos);
            let mut r = [0.0; PAIR_DOFS];
            let mut k = with_k.then(|| Box::new([0.0; PAIR_DOFS * PAIR_DOFS]));
            let set = &model.pair_settings;
            let (e, f, g) = match &model.barrier {
                // the log barrier: no gap shifts
                Some(b) => contact::pair_face_with(
                    |g| b.eval(g),
                    set,
                    p.orientation,
                    &x0b,
                    &xb,
                    &xf,
                    &[0.0; 9],
                    &mut r,
                    k.as_deref_mut(),
                ),
                None => contact::pair_face(
                    set,
                    p.orientation,
                    &x0b,
                    &xb,
                    &xf,
                    &load_shifts(shift),
                    &mut r,
                    k.as_deref_mut(),
                ),
            };
            let active = r.iter().any(|v| *v != 0.0)
                || k.as_ref().is_some_and(|k| k.iter().any(|v| *v != 0.0));
            let local = active.then(|| Box::new((r, k.map_or(Vec::new(), |k| k.to_vec()))));
            (e, f, g, local)
        })
        .collect();
    let mut nodes = [0usize; PAIR_DOFS / 3];
    for (i, (p, (e, f, g, local))) in model.pairs.iter().zip(results).enumerate() {
        if let Some(en) = energy.as_deref_mut() {
            *en += e;
        }
        out.force += f;
        out.min_gap = out.min_gap.min(g);
        let Some(local) = local else { continue };
        let (r, k) = &*local;
        for (slot, &n) in nodes.iter_mut().zip(p.back.iter().chain(&p.front)) {
            *slot = n;
        }
        global.add_local(&nodes, r, &model.pair_maps[i], with_k.then_some(&k[..]));
    }
    out
}
