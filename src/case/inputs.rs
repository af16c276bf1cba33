//! The inputs of a case: its design and Ogden material ([`CaseInputs`], a case of a snapshot
//! set), and the same at a pressure ([`Query`], where a surrogate is evaluated).

/// Design and material of a case (everything but the pressure).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CaseInputs {
    /// Number of bellows `N`.
    pub n_bellows: u32,
    /// Wall thickness `T`, mm.
    pub wall_thickness_mm: f64,
    /// Ogden `μ₁`, MPa.
    pub mu1_mpa: f64,
    /// Ogden `α₁`.
    pub alpha1: f64,
    /// Ogden `μ₂`, MPa.
    pub mu2_mpa: f64,
    /// Ogden `α₂`.
    pub alpha2: f64,
}

/// A surrogate query (the public inputs; the material as the four Ogden parameters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Query {
    /// Number of bellows.
    pub n: u32,
    /// Wall thickness, mm.
    pub t_mm: f64,
    /// Gauge pressure, bar.
    pub p_bar: f64,
    /// Ogden `μ₁`, MPa.
    pub mu1: f64,
    /// Ogden `α₁`.
    pub alpha1: f64,
    /// Ogden `μ₂`, MPa.
    pub mu2: f64,
    /// Ogden `α₂`.
    pub alpha2: f64,
}

impl Query {
    /// A query from the design, the pressure and the Ogden parameters `[μ₁, α₁, μ₂, α₂]`.
    pub fn new(n: u32, t_mm: f64, p_bar: f64, material: [f64; 4]) -> Self {
        Query {
            n,
            t_mm,
            p_bar,
            mu1: material[0],
            alpha1: material[1],
            mu2: material[2],
            alpha2: material[3],
        }
    }

    /// The query of a case at pressure `p_bar`.
    pub fn from_case(c: &CaseInputs, p_bar: f64) -> Self {
        Query {
            n: c.n_bellows,
            t_mm: c.wall_thickness_mm,
            p_bar,
            mu1: c.mu1_mpa,
            alpha1: c.alpha1,
            mu2: c.mu2_mpa,
            alpha2: c.alpha2,
        }
    }

    /// The design and material of the query, as a case of the snapshot set.
    pub fn case(&self) -> CaseInputs {
        CaseInputs {
            n_bellows: self.n,
            wall_thickness_mm: self.t_mm,
            mu1_mpa: self.mu1,
            alpha1: self.alpha1,
            mu2_mpa: self.mu2,
            alpha2: self.alpha2,
        }
    }

    /// The inputs as `[N, T, P, μ₁, α₁, μ₂, α₂]`.
    pub fn as_array(&self) -> [f64; 7] {
        [
            self.n as f64,
            self.t_mm,
            self.p_bar,
            self.mu1,
            self.alpha1,
            self.mu2,
            self.alpha2,
        ]
    }
}
