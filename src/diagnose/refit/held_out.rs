//! Every design left out in turn: both fits redone on the rest, the design predicted.

use super::outcome::{HeldOut, HeldOutDesign, Quality};
use super::problem::Problem;
use super::quality::quality;
use super::rows::Rows;
use crate::calibrate::objective::Output;
use crate::calibrate::ParamSpace;
use crate::diagnose::cells::Cell;
use crate::diagnose::DiagnoseError;
use crate::fe::effects::Effect;
use crate::rom::Surrogate;

/// Every design left out in turn, both fits redone on the rest from `x0` / `x1`.
pub(crate) fn held_out(
    rows: &Rows,
    model: &Surrogate,
    space: &ParamSpace,
    effects: &[Effect],
    x0: &[f64],
    x1: &[f64],
) -> Result<HeldOut, DiagnoseError> {
    let k = effects.len();
    let mut designs: Vec<(u32, f64)> = Vec::new();
    for c in &rows.cells {
        if !designs
            .iter()
            .any(|&(n, t)| n == c.n_bellows && t == c.wall_thickness_mm)
        {
            designs.push((c.n_bellows, c.wall_thickness_mm));
        }
    }
    let mut out = Vec::new();
    let (mut be0, mut be1, mut fo0, mut fo1) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut chi0, mut chi1) = (0.0, 0.0);
    for &(n, t) in &designs {
        let inside = |c: &Cell| c.n_bellows == n && c.wall_thickness_mm == t;
        let train = rows.subset(|c| !inside(c));
        let test = rows.subset(inside);
        if train.cells.len() < 4 + k + 2 {
            continue;
        }
        let p0 = Problem::new(&train, model, space.clone(), effects, 0);
        let p1 = Problem::new(&train, model, space.clone(), effects, k);
        let g0 = p0.fit(x0)?;
        let g1 = p1.fit(x1)?;
        let q0 = quality(
            &test.cells,
            &Problem::new(&test, model, space.clone(), effects, 0).predictions(&g0.x)?,
        );
        let q1 = quality(
            &test.cells,
            &Problem::new(&test, model, space.clone(), effects, k).predictions(&g1.x)?,
        );
        // per-configuration values, for means over every held-out configuration
        let per = |q: &Quality, be: &mut Vec<(f64, usize)>, fo: &mut Vec<(f64, usize)>| {
            let ncfg = test
                .cells
                .iter()
                .filter(|c| c.output == Output::TipUz)
                .count();
            let nforce = test
                .cells
                .iter()
                .filter(|c| c.output == Output::Force)
                .count();
            if let Some(v) = q.mean_be_mm {
                be.push((v, ncfg));
            }
            if let Some(v) = q.mean_abs_force_error_n {
                fo.push((v, nforce));
            }
        };
        per(&q0, &mut be0, &mut fo0);
        per(&q1, &mut be1, &mut fo1);
        chi0 += q0.chi2;
        chi1 += q1.chi2;
        out.push(HeldOutDesign {
            n_bellows: n,
            wall_thickness_mm: t,
            before: q0,
            after: q1,
            effects: (0..k).map(|i| rows.value(i, g1.x[4 + i])).collect(),
        });
    }
    let wmean = |v: &[(f64, usize)]| {
        let w: usize = v.iter().map(|p| p.1).sum();
        (w > 0).then(|| v.iter().map(|p| p.0 * p.1 as f64).sum::<f64>() / w as f64)
    };
    Ok(HeldOut {
        designs: out,
        mean_be_before_mm: wmean(&be0),
        mean_be_after_mm: wmean(&be1),
        mean_abs_force_error_before_n: wmean(&fo0),
        mean_abs_force_error_after_n: wmean(&fo1),
        chi2_before: chi0,
        chi2_after: chi1,
    })
}
