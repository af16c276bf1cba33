//! Pressure warp of a low-fidelity set onto the high fidelity, ahead of the additive
//! discrepancy of [`super::fidelity`].
//!
//! On the actuator the coarse mesh (one element through a wall) lets the walls of neighbouring
//! bellows bulge too much: they touch at a lower pressure than on the standard mesh, and from
//! there the contact bends the actuator further (`fe_reference/convergence/levels/README.md`).
//! The high-fidelity ramp of a case then looks like its low-fidelity ramp at a lower pressure:
//!
//! ```text
//!   H(x, P) ≈ L(x, P / r(x)) + δ(x, P)
//! ```
//!
//! with a scale `r` per case, fitted on the cases run at both fidelities (least squares over
//! tip Uz, tip Uy and the angle along the whole ramp; `L` between grid pressures by the
//! surrogate's own cubic Hermite stencil, [`surrogate_predict::stencil`]) and regressed by a
//! Gaussian process on `ln r` ([`PressureWarp::scale`]), on the case's design and material or
//! on its low-fidelity response ([`WarpInputs`], chosen by leave-one-case-out error). The warped
//! low-fidelity set ([`PressureWarp::apply`]) replaces `L` in [`super::fidelity::discrepancy`]
//! and [`super::fidelity::correct`], so that the additive discrepancy only has to learn what
//! the warp leaves. A case whose ramp does not cover the whole grid is left unwarped (`r = 1`).

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};

use super::data::SnapshotSet;
use super::regression::gp::{Gp, GpParams};
use super::regression::{Data, Regressor};
use super::{RomError, Q_TIP_UZ};
use crate::case::{raw_features, CaseInputs};
use surrogate_predict::stencil;

/// Range of the pressure scale `r`.
pub const SCALE_BOUNDS: (f64, f64) = (0.7, 1.5);

/// Quantities whose misfit defines the scale of a case: tip Uz, tip Uy, angle.
const FIT_QUANTITIES: [usize; 3] = [Q_TIP_UZ, Q_TIP_UZ + 1, Q_TIP_UZ + 2];

/// What the warp was fitted to (stored in the model's correction record).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WarpInfo {
    /// The fitted scale `r` of each case run at both fidelities.
    pub fitted: Vec<(String, f64)>,
    /// Inputs of the regression of `r` (chosen by leave-one-case-out error).
    pub inputs: WarpInputs,
    /// Leave-one-case-out RMSE of the regressed `r` against the fitted one.
    pub loo_rmse: f64,
    /// Low-fidelity cases left unwarped (incomplete ramps).
    pub unwarped_cases: usize,
}

impl WarpInfo {
    /// One line: the fitted scales, the regression's inputs and its leave-one-out error.
    pub fn summary(&self) -> String {
        let r: Vec<f64> = self.fitted.iter().map(|(_, r)| *r).collect();
        format!(
            "pressure warp: scale r of the {} matched cases {:.3} .. {:.3} (mean {:.3}); r regressed on the {}, leave-one-out RMSE {:.4}",
            r.len(),
            r.iter().copied().fold(f64::INFINITY, f64::min),
            r.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            r.iter().sum::<f64>() / r.len().max(1) as f64,
            self.inputs,
            self.loo_rmse
        )
    }
}

/// Complete ramps of a set on its pressure grid.
struct Ramps {
    grid: Vec<f64>,
    cases: BTreeMap<String, (CaseInputs, Vec<[f64; 22]>)>,
    incomplete: usize,
}

/// A case's values at each grid pressure, where present.
type PartialValues = Vec<Option<[f64; 22]>>;

fn ramps(set: &SnapshotSet) -> Ramps {
    let mut grid: Vec<f64> = set.rows.iter().map(|r| r.pressure_bar).collect();
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    let index: HashMap<u64, usize> = grid
        .iter()
        .enumerate()
        .map(|(i, p)| (p.to_bits(), i))
        .collect();
    let mut partial: BTreeMap<String, (CaseInputs, PartialValues)> = BTreeMap::new();
    for r in &set.rows {
        let e = partial
            .entry(r.case_id.clone())
            .or_insert_with(|| (r.inputs, vec![None; grid.len()]));
        e.1[index[&r.pressure_bar.to_bits()]] = Some(r.values);
    }
    let mut cases = BTreeMap::new();
    let mut incomplete = 0;
    for (id, (inputs, values)) in partial {
        match values.into_iter().collect::<Option<Vec<_>>>() {
            Some(v) => {
                cases.insert(id, (inputs, v));
            }
            None => incomplete += 1,
        }
    }
    Ramps {
        grid,
        cases,
        incomplete,
    }
}

/// The ramp `values` (on `grid`) at the pressures `grid / r` (for `r < 1` the pressures past
/// the end of the grid take its last value: the low fidelity says nothing beyond it).
pub fn warp_ramp(grid: &[f64], values: &[[f64; 22]], r: f64) -> Vec<[f64; 22]> {
    grid.iter()
        .map(|&p| {
            let st = stencil(grid, p / r);
            let mut v = [0.0; 22];
            for k in 0..st.len {
                for (o, y) in v.iter_mut().zip(&values[st.start + k]) {
                    *o += st.w[k] * y;
                }
            }
            v
        })
        .collect()
}

fn misfit(grid: &[f64], low: &[[f64; 22]], high: &[[f64; 22]], r: f64) -> f64 {
    warp_ramp(grid, low, r)
        .iter()
        .zip(high)
        .map(|(l, h)| {
            FIT_QUANTITIES
                .iter()
                .map(|&q| (h[q] - l[q]).powi(2))
                .sum::<f64>()
        })
        .sum()
}

/// The scale minimising the misfit of the warped low-fidelity ramp: a scan in steps of
/// 0.0025 over [`SCALE_BOUNDS`], refined by golden-section search around the best point.
pub fn fit_scale(grid: &[f64], low: &[[f64; 22]], high: &[[f64; 22]]) -> f64 {
    let step = 0.0025;
    let n = ((SCALE_BOUNDS.1 - SCALE_BOUNDS.0) / step).round() as usize;
    let best = (0..=n)
        .map(|i| SCALE_BOUNDS.0 + i as f64 * step)
        .min_by(|&a, &b| misfit(grid, low, high, a).total_cmp(&misfit(grid, low, high, b)))
        .unwrap_or(1.0);
    let (mut a, mut b) = (
        (best - step).max(SCALE_BOUNDS.0),
        (best + step).min(SCALE_BOUNDS.1),
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..40 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if misfit(grid, low, high, c) <= misfit(grid, low, high, d) {
            b = d;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}

/// Inputs of the regression of `ln r`: the design and material features of the surrogate,
/// or the low-fidelity response itself (wall thickness, tip Uz at mid-ramp and at the end,
/// angle at the end), or both. The warp is a property of how the low fidelity deforms, so
/// the response can say more about it than the inputs; [`PressureWarp::fit`] keeps the set
/// with the smallest leave-one-case-out error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WarpInputs {
    /// `N, T, ln μ0, α1, share, α2` (the surrogate's features).
    Design,
    /// `T`, low-fidelity tip Uz at mid-ramp and at the last pressure, angle at the last.
    Response,
    /// The design features and the low-fidelity tip Uz at mid-ramp and at the end.
    Both,
}

impl std::fmt::Display for WarpInputs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            WarpInputs::Design => "design and material",
            WarpInputs::Response => "low-fidelity response",
            WarpInputs::Both => "design, material and low-fidelity response",
        })
    }
}

impl WarpInputs {
    const ALL: [WarpInputs; 3] = [WarpInputs::Design, WarpInputs::Response, WarpInputs::Both];

    fn raw(self, inputs: &CaseInputs, ramp: &[[f64; 22]]) -> Vec<f64> {
        let n = ramp.len();
        let response = [
            inputs.wall_thickness_mm,
            ramp[n / 2][Q_TIP_UZ],
            ramp[n - 1][Q_TIP_UZ],
            ramp[n - 1][Q_TIP_UZ + 2],
        ];
        match self {
            WarpInputs::Design => raw_features(inputs).to_vec(),
            WarpInputs::Response => response.to_vec(),
            // the GP takes at most 8 inputs: T is among the features, the end angle follows
            // the end tip Uz closely
            WarpInputs::Both => raw_features(inputs)
                .into_iter()
                .chain(response[1..3].iter().copied())
                .collect(),
        }
    }
}

/// Affine scaling of raw regression inputs to [−1, 1] over the low-fidelity cases (inputs
/// that do not vary are dropped).
#[derive(Debug, Clone)]
struct Scaling {
    index: Vec<usize>,
    lo: Vec<f64>,
    width: Vec<f64>,
}

impl Scaling {
    fn fit(rows: &[Vec<f64>]) -> Self {
        let mut s = Scaling {
            index: Vec::new(),
            lo: Vec::new(),
            width: Vec::new(),
        };
        for f in 0..rows.first().map_or(0, Vec::len) {
            let lo = rows.iter().map(|r| r[f]).fold(f64::INFINITY, f64::min);
            let hi = rows.iter().map(|r| r[f]).fold(f64::NEG_INFINITY, f64::max);
            if hi - lo > 1e-9 * (1.0 + lo.abs()) {
                s.index.push(f);
                s.lo.push(lo);
                s.width.push(hi - lo);
            }
        }
        s
    }

    fn apply(&self, raw: &[f64]) -> Vec<f64> {
        self.index
            .iter()
            .enumerate()
            .map(|(j, &f)| 2.0 * (raw[f] - self.lo[j]) / self.width[j] - 1.0)
            .collect()
    }
}

/// A fitted pressure warp (module docs).
#[derive(Debug, Clone)]
pub struct PressureWarp {
    inputs: WarpInputs,
    scaling: Scaling,
    gp: Gp,
    mean_ln_r: f64,
    /// Fit record.
    pub info: WarpInfo,
}

/// A GP on `ln r − mean` at the rows `rows` of `x` (`d` columns).
fn fit_gp(x: &[f64], d: usize, y: &[f64], rows: &[usize]) -> Result<(Gp, f64), RomError> {
    let mean = rows.iter().map(|&i| y[i]).sum::<f64>() / rows.len() as f64;
    let xs: Vec<f64> = rows
        .iter()
        .flat_map(|&i| x[i * d..(i + 1) * d].iter().copied())
        .collect();
    let ys: Vec<f64> = rows.iter().map(|&i| y[i] - mean).collect();
    let data = Data {
        x: &xs,
        y: &ys,
        n: rows.len(),
        d,
        m: 1,
        weights: &[],
    };
    Ok((Gp::fit(&data, &GpParams::default())?, mean))
}

impl PressureWarp {
    /// Fits the scale of every case run at both fidelities, then its regression on each set
    /// of [`WarpInputs`] (scaled over all low-fidelity cases), and keeps the set with the
    /// smallest leave-one-case-out RMSE of `r`.
    ///
    /// # Errors
    /// Fewer than 3 cases with complete ramps on the same grid at both fidelities, or a GP
    /// failure.
    pub fn fit(low: &SnapshotSet, high: &SnapshotSet) -> Result<Self, RomError> {
        let (l, h) = (ramps(low), ramps(high));
        let mut fitted = Vec::new();
        let mut matched = Vec::new();
        if h.grid == l.grid {
            for (id, (_, hv)) in &h.cases {
                if let Some((inputs, lv)) = l.cases.get(id) {
                    fitted.push((id.clone(), fit_scale(&l.grid, lv, hv)));
                    matched.push((inputs, lv));
                }
            }
        }
        if fitted.len() < 3 {
            return Err(RomError::InsufficientData(format!(
                "{} cases with complete ramps on the same pressure grid at both fidelities; the pressure warp needs at least 3",
                fitted.len()
            )));
        }
        let y: Vec<f64> = fitted.iter().map(|(_, r)| r.ln()).collect();
        let n = fitted.len();
        let mut best: Option<(f64, WarpInputs, Scaling, Vec<f64>, usize)> = None;
        for set in WarpInputs::ALL {
            let all: Vec<Vec<f64>> = l.cases.values().map(|(c, v)| set.raw(c, v)).collect();
            let scaling = Scaling::fit(&all);
            let d = scaling.index.len();
            if d == 0 {
                continue;
            }
            let x: Vec<f64> = matched
                .iter()
                .flat_map(|(c, v)| scaling.apply(&set.raw(c, v)))
                .collect();
            let mut se = 0.0;
            for i in 0..n {
                let rows: Vec<usize> = (0..n).filter(|&j| j != i).collect();
                let (gp, mean) = fit_gp(&x, d, &y, &rows)?;
                se += (predict(&gp, mean, &x[i * d..(i + 1) * d]) - fitted[i].1).powi(2);
            }
            let loo = (se / n as f64).sqrt();
            if best.as_ref().is_none_or(|b| loo < b.0) {
                best = Some((loo, set, scaling, x, d));
            }
        }
        let Some((loo_rmse, inputs, scaling, x, d)) = best else {
            return Err(RomError::InsufficientData(
                "no regression input of the pressure warp varies over the low-fidelity cases"
                    .into(),
            ));
        };
        let (gp, mean_ln_r) = fit_gp(&x, d, &y, &(0..n).collect::<Vec<_>>())?;
        Ok(PressureWarp {
            inputs,
            scaling,
            gp,
            mean_ln_r,
            info: WarpInfo {
                fitted,
                inputs,
                loo_rmse,
                unwarped_cases: l.incomplete,
            },
        })
    }

    /// The regressed scale `r` of a case with the complete low-fidelity ramp `ramp` (on the
    /// grid of the set the warp was fitted to), within [`SCALE_BOUNDS`].
    pub fn scale(&self, inputs: &CaseInputs, ramp: &[[f64; 22]]) -> f64 {
        predict(
            &self.gp,
            self.mean_ln_r,
            &self.scaling.apply(&self.inputs.raw(inputs, ramp)),
        )
    }

    /// The low-fidelity set with every complete ramp warped by its regressed scale (rows in
    /// the same order; incomplete ramps unchanged).
    pub fn apply(&self, low: &SnapshotSet) -> SnapshotSet {
        let l = ramps(low);
        let index: HashMap<u64, usize> = l
            .grid
            .iter()
            .enumerate()
            .map(|(i, p)| (p.to_bits(), i))
            .collect();
        let warped: HashMap<&str, Vec<[f64; 22]>> = l
            .cases
            .iter()
            .map(|(id, (inputs, v))| (id.as_str(), warp_ramp(&l.grid, v, self.scale(inputs, v))))
            .collect();
        let mut out = low.clone();
        for r in &mut out.rows {
            if let Some(w) = warped.get(r.case_id.as_str()) {
                r.values = w[index[&r.pressure_bar.to_bits()]];
            }
        }
        out.source = format!("{} warped in pressure", low.source);
        out
    }
}

fn predict(gp: &Gp, mean: f64, x: &[f64]) -> f64 {
    let mut out = [0.0];
    let mut scratch = vec![0.0; gp.scratch_len()];
    gp.predict_into(x, &mut out, &mut scratch);
    (mean + out[0]).exp().clamp(SCALE_BOUNDS.0, SCALE_BOUNDS.1)
}
