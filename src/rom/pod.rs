//! Proper orthogonal decomposition of centred, scaled snapshot blocks.
//!
//! For a block of quantities `Q` on the pressure grid (`dim = n_p·|Q|` entries, entry
//! `e = j·|Q| + slot`), the snapshots `y_c` of the training cases give the mean `ȳ`, one scale
//! per quantity group `s_g` (RMS of `y − ȳ` over the group's entries: all marker Uz share one
//! scale, all marker Uy another, each scalar its own) and the thin SVD of
//! `Ỹ = [(y_c − ȳ)/s]_c = U Σ Vᵀ`. The basis keeps the first `r` left singular vectors, `r` the
//! smallest count with discarded energy `Σ_{k>r} σ_k² / Σ_k σ_k² ≤ tol` (and `r ≤ max_modes`).
//! Coefficients are `a = Φᵀ(y − ȳ)/s`, the reconstruction is `ȳ + s ⊙ Φa`.

use serde::{Deserialize, Serialize};

use super::data::CaseRamp;
use super::svd::thin_svd;
use super::{RomError, N_MARKER_COMPONENTS};

/// A POD basis of one block of quantities.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PodBasis {
    /// Quantity indices (into [`super::QUANTITY_NAMES`]) of the block.
    pub quantities: Vec<usize>,
    /// Number of pressure nodes.
    pub n_pressures: usize,
    /// Mean snapshot, `dim` entries.
    pub mean: Vec<f64>,
    /// Scale of each entry, `dim` entries.
    pub scale: Vec<f64>,
    /// Number of kept modes `r`.
    pub n_modes: usize,
    /// Modes, row-major `dim × r`.
    pub modes: Vec<f64>,
    /// All singular values of the scaled snapshot matrix (for the energy report).
    pub singular_values: Vec<f64>,
}

/// Scale group of a quantity: marker Uz, marker Uy, then one per scalar.
fn scale_group(q: usize) -> usize {
    if q < N_MARKER_COMPONENTS {
        q % 2
    } else {
        q - N_MARKER_COMPONENTS + 2
    }
}

impl PodBasis {
    /// Number of entries of a block snapshot.
    pub fn dim(&self) -> usize {
        self.n_pressures * self.quantities.len()
    }

    /// The block snapshot of a case: `values[j][Q[slot]]` at entry `j·|Q| + slot`.
    pub fn snapshot_of(quantities: &[usize], case: &CaseRamp) -> Vec<f64> {
        case.values
            .iter()
            .flat_map(|v| quantities.iter().map(move |&q| v[q]))
            .collect()
    }

    /// Fits the basis to the training cases.
    ///
    /// # Errors
    /// Fewer than 2 cases, or an SVD failure.
    pub fn fit(
        cases: &[CaseRamp],
        quantities: &[usize],
        tol: f64,
        max_modes: usize,
    ) -> Result<Self, RomError> {
        let n = cases.len();
        if n < 2 {
            return Err(RomError::InsufficientData(format!(
                "POD needs at least 2 cases, got {n}"
            )));
        }
        let n_p = cases[0].values.len();
        let nq = quantities.len();
        let dim = n_p * nq;
        let snaps: Vec<Vec<f64>> = cases
            .iter()
            .map(|c| Self::snapshot_of(quantities, c))
            .collect();
        let mut mean = vec![0.0; dim];
        for s in &snaps {
            for (m, v) in mean.iter_mut().zip(s) {
                *m += v / n as f64;
            }
        }
        let mut group_ss = [0.0f64; 6];
        let mut group_n = [0usize; 6];
        for s in &snaps {
            for (e, v) in s.iter().enumerate() {
                let g = scale_group(quantities[e % nq]);
                group_ss[g] += (v - mean[e]).powi(2);
                group_n[g] += 1;
            }
        }
        let group_scale: Vec<f64> = (0..6)
            .map(|g| {
                let rms = (group_ss[g] / group_n[g].max(1) as f64).sqrt();
                if rms > 1e-12 {
                    rms
                } else {
                    1.0
                }
            })
            .collect();
        let scale: Vec<f64> = (0..dim)
            .map(|e| group_scale[scale_group(quantities[e % nq])])
            .collect();
        let mat = faer::Mat::<f64>::from_fn(dim, n, |e, c| (snaps[c][e] - mean[e]) / scale[e]);
        let svd = thin_svd(mat.as_ref()).map_err(|e| RomError::Numerical {
            stage: "POD thin SVD".into(),
            message: format!("{e:?}"),
        })?;
        let (u, sv) = (svd.u, svd.s);
        let r = modes_to_keep(&sv, tol, max_modes);
        let mut modes = vec![0.0; dim * r];
        for e in 0..dim {
            for k in 0..r {
                modes[e * r + k] = u[(e, k)];
            }
        }
        Ok(PodBasis {
            quantities: quantities.to_vec(),
            n_pressures: n_p,
            mean,
            scale,
            n_modes: r,
            modes,
            singular_values: sv,
        })
    }

    /// Projection coefficients `a = Φᵀ(y − ȳ)/s` of a block snapshot.
    pub fn project_into(&self, y: &[f64], coef: &mut [f64]) {
        let r = self.n_modes;
        coef[..r].iter_mut().for_each(|c| *c = 0.0);
        for (e, &v) in y.iter().enumerate() {
            let yt = (v - self.mean[e]) / self.scale[e];
            let row = &self.modes[e * r..(e + 1) * r];
            for k in 0..r {
                coef[k] += row[k] * yt;
            }
        }
    }

    /// Gappy projection of a snapshot observed only where `observed[e]`:
    /// `a = argmin Σ_{e observed} (ỹ_e − Φ_e·a)² + λ Σ_k a_k²/v_k`, with `v_k = σ_k²/n_train` the
    /// spread of mode `k` over the training cases and `λ = 10⁻⁴`, so that unobservable modes
    /// fall back to the mean instead of blowing up.
    ///
    /// # Errors
    /// A singular system (cannot happen with `λ > 0` and non-zero singular values).
    pub fn gappy_project_into(
        &self,
        y: &[f64],
        observed: &[bool],
        n_train: usize,
        coef: &mut [f64],
    ) -> Result<(), RomError> {
        let r = self.n_modes;
        let mut a = vec![0.0; r * r];
        let mut b = vec![0.0; r];
        for (e, &v) in y.iter().enumerate() {
            if !observed[e] {
                continue;
            }
            let yt = (v - self.mean[e]) / self.scale[e];
            let row = &self.modes[e * r..(e + 1) * r];
            for i in 0..r {
                b[i] += row[i] * yt;
                for j in 0..=i {
                    a[i * r + j] += row[i] * row[j];
                }
            }
        }
        for k in 0..r {
            let v = (self.singular_values[k].powi(2) / n_train.max(1) as f64).max(1e-300);
            a[k * r + k] += 1e-4 / v;
            for j in 0..k {
                a[j * r + k] = a[k * r + j];
            }
        }
        super::regression::cholesky_in_place(&mut a, r).map_err(|i| RomError::Numerical {
            stage: "gappy POD".into(),
            message: format!("singular system (pivot {i})"),
        })?;
        super::regression::solve_lower(&a, r, &mut b);
        super::regression::solve_lower_t(&a, r, &mut b);
        coef[..r].copy_from_slice(&b);
        Ok(())
    }

    /// Reconstruction `ȳ + s ⊙ Φa` of the whole block snapshot.
    pub fn reconstruct_into(&self, coef: &[f64], out: &mut [f64]) {
        for (e, o) in out.iter_mut().enumerate().take(self.dim()) {
            *o = self.entry(e, coef);
        }
    }

    /// One reconstructed entry `ȳ_e + s_e Σ_k Φ_ek a_k`.
    #[inline]
    pub fn entry(&self, e: usize, coef: &[f64]) -> f64 {
        let r = self.n_modes;
        let row = &self.modes[e * r..(e + 1) * r];
        let mut v = 0.0;
        for k in 0..r {
            v += row[k] * coef[k];
        }
        self.mean[e] + self.scale[e] * v
    }

    /// Fraction of the snapshot energy discarded by the kept modes.
    pub fn discarded_energy(&self) -> f64 {
        let total: f64 = self.singular_values.iter().map(|s| s * s).sum();
        let kept: f64 = self.singular_values[..self.n_modes]
            .iter()
            .map(|s| s * s)
            .sum();
        if total > 0.0 {
            ((total - kept) / total).max(0.0)
        } else {
            0.0
        }
    }
}

/// Smallest `r ≥ 1` with discarded energy `≤ tol`, capped at `max_modes`.
pub fn modes_to_keep(sv: &[f64], tol: f64, max_modes: usize) -> usize {
    let total: f64 = sv.iter().map(|s| s * s).sum();
    let cap = max_modes.min(sv.len()).max(1);
    if total <= 0.0 {
        return 1;
    }
    let mut kept = 0.0;
    for (k, s) in sv.iter().enumerate().take(cap) {
        kept += s * s;
        if (total - kept) / total <= tol {
            return k + 1;
        }
    }
    cap
}
