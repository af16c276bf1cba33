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
//! surrogate's own cubic Hermite stencil, [`crate::predict::stencil`]) and regressed on the
//! case features by a Gaussian process on `ln r` ([`PressureWarp::scale`]). The warped
//! low-fidelity set ([`PressureWarp::apply`]) replaces `L` in [`super::fidelity::discrepancy`]
//! and [`super::fidelity::correct`], so that the additive discrepancy only has to learn what
//! the warp leaves. A case whose ramp does not cover the whole grid is left unwarped (`r = 1`).

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};

use super::data::{CaseInputs, SnapshotSet};
use super::regression::gp::{Gp, GpParams};
use super::regression::{raw_features, Data, FeatureScaler, Regressor};
use super::{RomError, Q_TIP_UZ};
use crate::predict::stencil;

/// Range of the pressure scale `r`.
pub const SCALE_BOUNDS: (f64, f64) = (0.7, 1.5);

/// Quantities whose misfit defines the scale of a case: tip Uz, tip Uy, angle.
const FIT_QUANTITIES: [usize; 3] = [Q_TIP_UZ, Q_TIP_UZ + 1, Q_TIP_UZ + 2];

/// What the warp was fitted to (stored in the model's correction record).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WarpInfo {
    /// The fitted scale `r` of each case run at both fidelities.
    pub fitted: Vec<(String, f64)>,
    /// Leave-one-case-out RMSE of the regressed `r` against the fitted one.
    pub loo_rmse: f64,
    /// Low-fidelity cases left unwarped (incomplete ramps).
    pub unwarped_cases: usize,
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

/// A fitted pressure warp (module docs).
#[derive(Debug, Clone)]
pub struct PressureWarp {
    features: FeatureScaler,
    gp: Gp,
    mean_ln_r: f64,
    /// Fit record.
    pub info: WarpInfo,
}

impl PressureWarp {
    /// Fits the scale of every case run at both fidelities and its regression on the case
    /// features (scaled over all low-fidelity cases).
    ///
    /// # Errors
    /// Fewer than 3 cases with complete ramps at both fidelities, or a GP failure.
    pub fn fit(low: &SnapshotSet, high: &SnapshotSet) -> Result<Self, RomError> {
        let (l, h) = (ramps(low), ramps(high));
        let mut fitted = Vec::new();
        let mut z = Vec::new();
        for (id, (inputs, hv)) in &h.cases {
            if h.grid != l.grid {
                break;
            }
            if let Some((_, lv)) = l.cases.get(id) {
                fitted.push((id.clone(), fit_scale(&l.grid, lv, hv)));
                z.push(raw_features(inputs));
            }
        }
        if fitted.len() < 3 {
            return Err(RomError::InsufficientData(format!(
                "{} cases with complete ramps on the same pressure grid at both fidelities; the pressure warp needs at least 3",
                fitted.len()
            )));
        }
        let all: Vec<_> = l.cases.values().map(|(c, _)| raw_features(c)).collect();
        let features = FeatureScaler::fit(&all);
        let d = features.dim();
        let mut x = vec![0.0; z.len() * d];
        for (i, zi) in z.iter().enumerate() {
            features.scale_into(zi, &mut x[i * d..(i + 1) * d]);
        }
        let y: Vec<f64> = fitted.iter().map(|(_, r)| r.ln()).collect();
        let fit_gp = |rows: &[usize]| -> Result<(Gp, f64), RomError> {
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
        };
        let n = fitted.len();
        let mut se = 0.0;
        for i in 0..n {
            let rows: Vec<usize> = (0..n).filter(|&j| j != i).collect();
            let (gp, mean) = fit_gp(&rows)?;
            let r = predict(&gp, mean, &x[i * d..(i + 1) * d]);
            se += (r - fitted[i].1).powi(2);
        }
        let (gp, mean_ln_r) = fit_gp(&(0..n).collect::<Vec<_>>())?;
        Ok(PressureWarp {
            features,
            gp,
            mean_ln_r,
            info: WarpInfo {
                fitted,
                loo_rmse: (se / n as f64).sqrt(),
                unwarped_cases: l.incomplete,
            },
        })
    }

    /// The regressed scale `r` of a case, within [`SCALE_BOUNDS`].
    pub fn scale(&self, inputs: &CaseInputs) -> f64 {
        let mut x = vec![0.0; self.features.dim()];
        self.features.scale_into(&raw_features(inputs), &mut x);
        predict(&self.gp, self.mean_ln_r, &x)
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
            .map(|(id, (inputs, v))| (id.as_str(), warp_ramp(&l.grid, v, self.scale(inputs))))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warping_by_one_is_the_identity_and_the_scale_is_recovered() {
        let grid: Vec<f64> = (0..15).map(|i| 0.25 * i as f64).collect();
        // a smooth ramp with a kink-like rise, as a contact onset
        let ramp = |s: f64| -> Vec<[f64; 22]> {
            grid.iter()
                .map(|&p| {
                    let q = p / s;
                    let mut v = [0.0; 22];
                    v[Q_TIP_UZ] = 2.0 * q + 8.0 * (1.0 + ((q - 1.5) * 4.0).tanh());
                    v[Q_TIP_UZ + 1] = -5.0 * q * q;
                    v[Q_TIP_UZ + 2] = 10.0 * q + q * q * q;
                    v
                })
                .collect()
        };
        let low = ramp(1.0);
        assert_eq!(warp_ramp(&grid, &low, 1.0), low);
        let high = ramp(1.12);
        let r = fit_scale(&grid, &low, &high);
        assert!((r - 1.12).abs() < 0.01, "r = {r}");
    }
}
