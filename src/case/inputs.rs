//! The inputs of a case: its design and Ogden material ([`CaseInputs`], a case of a snapshot
//! set), and the same at a pressure ([`Query`], where a surrogate is evaluated).

use serde::{Deserialize, Serialize};

use super::OgdenSet;

/// Design and material of a case (everything but the pressure).
///
/// Its serde shape is flat, the columns of a snapshot file:
/// `n_bellows, wall_thickness_mm, mu1_mpa, alpha1, mu2_mpa, alpha2`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "FlatCaseInputs", into = "FlatCaseInputs")]
pub struct CaseInputs {
    /// Number of bellows `N`.
    pub n_bellows: u32,
    /// Wall thickness `T`, mm.
    pub wall_thickness_mm: f64,
    /// The Ogden material.
    pub material: OgdenSet,
}

/// The flat serde shape of [`CaseInputs`] (a `#[serde(flatten)]` field would not go through
/// the `csv` crate).
#[derive(Serialize, Deserialize)]
struct FlatCaseInputs {
    n_bellows: u32,
    wall_thickness_mm: f64,
    mu1_mpa: f64,
    alpha1: f64,
    mu2_mpa: f64,
    alpha2: f64,
}

impl From<FlatCaseInputs> for CaseInputs {
    fn from(f: FlatCaseInputs) -> Self {
        CaseInputs {
            n_bellows: f.n_bellows,
            wall_thickness_mm: f.wall_thickness_mm,
            material: OgdenSet::from_array([f.mu1_mpa, f.alpha1, f.mu2_mpa, f.alpha2]),
        }
    }
}

impl From<CaseInputs> for FlatCaseInputs {
    fn from(c: CaseInputs) -> Self {
        let [mu1_mpa, alpha1, mu2_mpa, alpha2] = c.material.as_array();
        FlatCaseInputs {
            n_bellows: c.n_bellows,
            wall_thickness_mm: c.wall_thickness_mm,
            mu1_mpa,
            alpha1,
            mu2_mpa,
            alpha2,
        }
    }
}

/// A surrogate query: the design, the gauge pressure and the Ogden material. The field names
/// are the embedded predictor's inputs (`n, t_mm, p_bar`, then the material; see
/// [`Self::as_array`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Query {
    /// Number of bellows `N`.
    pub n: u32,
    /// Wall thickness `T`, mm.
    pub t_mm: f64,
    /// Gauge pressure `P`, bar.
    pub p_bar: f64,
    /// The Ogden material.
    pub material: OgdenSet,
}

impl Query {
    /// A query from the design `(N, T)`, the pressure (bar) and the material.
    pub fn new(n: u32, t_mm: f64, p_bar: f64, material: OgdenSet) -> Self {
        Query {
            n,
            t_mm,
            p_bar,
            material,
        }
    }

    /// The query of a case at pressure `p_bar`.
    pub fn from_case(c: &CaseInputs, p_bar: f64) -> Self {
        Query::new(c.n_bellows, c.wall_thickness_mm, p_bar, c.material)
    }

    /// The design and material of the query, as a case of the snapshot set.
    pub fn case(&self) -> CaseInputs {
        CaseInputs {
            n_bellows: self.n,
            wall_thickness_mm: self.t_mm,
            material: self.material,
        }
    }

    /// The inputs as `[N, T, P, μ₁, α₁, μ₂, α₂]` (the embedded predictor's input).
    pub fn as_array(&self) -> [f64; 7] {
        let m = &self.material;
        [
            self.n as f64,
            self.t_mm,
            self.p_bar,
            m.mu1_mpa,
            m.alpha1,
            m.mu2_mpa,
            m.alpha2,
        ]
    }
}
