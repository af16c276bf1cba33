//! The coordinates of a case in which plans sample and the surrogate regresses,
//!
//! ```text
//!   z = (N, T, ln μ0, α₁, s, α₂),   μ0 = ½ (μ₁α₁ + μ₂α₂),   s = μ₁α₁ / (2 μ0),
//! ```
//!
//! and the box a set of cases spans in them ([`FeatureScaler`]), which is both the
//! regression's input scaling and the domain of a model or a plan ([`super::domain`]).

use serde::{Deserialize, Serialize};

use super::CaseInputs;
use crate::schema;
use surrogate_predict::N_FEATURES;

/// Scales the active raw features `z = (N, T, ln μ0, α₁, s, α₂)` to `[−1, 1]` over the
/// training range; constant features are inactive (dropped).
///
/// `μ0 = ½(μ₁α₁ + μ₂α₂)` is the initial shear modulus and `s = μ₁α₁ / (2μ0)` the share of the
/// first term: the response depends mostly on μ0, which is a single axis here (and the axes of
/// the sampling plan). Measured on 45 FE snapshot cases (5-fold): tip Uz RMSE 4.1 → 1.1 mm,
/// markers 1.9 → 0.6 mm, against the features `(N, T, ln μ₁α₁, α₁, ln μ₂α₂, α₂)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeatureScaler {
    /// Indices of the active features.
    pub index: Vec<usize>,
    /// Centre of each active feature.
    pub center: Vec<f64>,
    /// Inverse half-width of each active feature.
    pub inv_half: Vec<f64>,
}

/// Raw feature names.
pub const FEATURE_NAMES: [&str; N_FEATURES] = [
    schema::N_BELLOWS.name,
    schema::WALL_THICKNESS.name,
    "ln_mu0",
    schema::ALPHA1.name,
    "share1",
    schema::ALPHA2.name,
];

/// Raw features of a case (`μᵢαᵢ > 0` is assumed validated).
pub fn raw_features(c: &CaseInputs) -> [f64; N_FEATURES] {
    let m = &c.material;
    let (k1, k2) = (m.mu1_mpa * m.alpha1, m.mu2_mpa * m.alpha2);
    [
        c.n_bellows as f64,
        c.wall_thickness_mm,
        (0.5 * (k1 + k2)).ln(),
        m.alpha1,
        k1 / (k1 + k2),
        m.alpha2,
    ]
}

impl FeatureScaler {
    /// Fits the scaler to the raw features of the training cases.
    pub fn fit(z: &[[f64; N_FEATURES]]) -> Self {
        let mut s = FeatureScaler {
            index: Vec::new(),
            center: Vec::new(),
            inv_half: Vec::new(),
        };
        for f in 0..N_FEATURES {
            let lo = z.iter().map(|r| r[f]).fold(f64::INFINITY, f64::min);
            let hi = z.iter().map(|r| r[f]).fold(f64::NEG_INFINITY, f64::max);
            if hi - lo > 1e-9 * (1.0 + lo.abs()) {
                s.index.push(f);
                s.center.push(0.5 * (lo + hi));
                s.inv_half.push(2.0 / (hi - lo));
            }
        }
        s
    }

    /// Number of active features.
    pub fn dim(&self) -> usize {
        self.index.len()
    }

    /// Scaled active features into `x` (length [`Self::dim`]).
    pub fn scale_into(&self, z: &[f64; N_FEATURES], x: &mut [f64]) {
        for (j, &f) in self.index.iter().enumerate() {
            x[j] = (z[f] - self.center[j]) * self.inv_half[j];
        }
    }
}
