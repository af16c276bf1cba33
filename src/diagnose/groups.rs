//! Shares of χ² and group means: how the residual divides over outputs, designs, N, T, P and
//! markers, and which groups sit on one side of the recordings (the tests: the
//! [module docs](super)).

use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

use super::cells::{Cell, Family, Group};

/// The share of χ² held by a set of cells.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Share {
    /// The cells: all of one output (`family`), or one group over every output (`group`).
    pub family: Option<Family>,
    /// The group, if not a whole output.
    pub group: Option<Group>,
    /// Number of cells.
    pub cells: usize,
    /// Fraction of all cells.
    pub cell_fraction: f64,
    /// `Σ z²` of the cells.
    pub chi2: f64,
    /// Its fraction of the table's χ².
    pub share: f64,
    /// Mean `z`.
    pub mean_z: f64,
    /// `√(Σ z² / n)`.
    pub rms_z: f64,
}

/// χ² shares by output and by each grouping factor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Shares {
    /// By output (markers: one entry per component).
    pub by_output: Vec<Share>,
    /// By design `(N, T)`.
    pub by_design: Vec<Share>,
    /// By number of bellows.
    pub by_n: Vec<Share>,
    /// By wall thickness.
    pub by_t: Vec<Share>,
    /// By pressure.
    pub by_p: Vec<Share>,
    /// By marker (empty without marker recordings).
    pub by_marker: Vec<Share>,
}

/// An output's misfit against the recordings' scatter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Misfit {
    /// The output.
    pub family: Family,
    /// Whether it took part in the calibration.
    pub fitted: bool,
    /// Cells.
    pub cells: usize,
    /// `Σ z²`.
    pub chi2: f64,
    /// `√(χ² / n)`: the residual in units of the recorded scatter.
    pub rms_z: f64,
    /// `P(χ²(n) ≥ χ²)`.
    pub p_value: f64,
    /// Significant after Holm's correction.
    pub significant: bool,
}

/// One output's cells in one group: their mean and signs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupMean {
    /// The output.
    pub family: Family,
    /// The group.
    pub group: Group,
    /// Cells.
    pub cells: usize,
    /// Mean `z`.
    pub mean_z: f64,
    /// Cells with `z > 0`.
    pub positive: usize,
    /// Cells with `z < 0`.
    pub negative: usize,
    /// `Z = Σ z / √n`.
    pub z: f64,
    /// Two-sided p-value of `Z` under `N(0, 1)`.
    pub p_value: f64,
    /// Significant after Holm's correction.
    pub significant: bool,
}

impl GroupMean {
    /// Cells on the side of the mean.
    pub fn on_side(&self) -> usize {
        if self.mean_z >= 0.0 {
            self.positive
        } else {
            self.negative
        }
    }

    /// A sign pattern: at least 3 cells, and at least 80 % of them (all of them in a group
    /// of fewer than 5) on the side of the mean.
    pub fn one_sided(&self) -> bool {
        let k = self.on_side();
        self.cells >= 3 && 5 * k >= 4 * self.cells
    }
}

/// The distinct groups of each factor present in `cells`: T, N, P, design, marker.
pub fn groups_of(cells: &[Cell]) -> [Vec<Group>; 5] {
    let mut designs: Vec<(u32, f64)> = cells
        .iter()
        .map(|c| (c.n_bellows, c.wall_thickness_mm))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup_by(|a, b| a.0 == b.0 && (a.1 - b.1).abs() < 1e-9);
    let levels = |f: &dyn Fn(&Cell) -> Option<f64>| {
        let mut l: Vec<f64> = cells.iter().filter_map(f).collect();
        l.sort_by(f64::total_cmp);
        l.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        l
    };
    [
        levels(&|c| Some(c.wall_thickness_mm))
            .into_iter()
            .map(|t| Group::T {
                wall_thickness_mm: t,
            })
            .collect(),
        levels(&|c| Some(f64::from(c.n_bellows)))
            .into_iter()
            .map(|n| Group::N {
                n_bellows: n as u32,
            })
            .collect(),
        levels(&|c| Some(c.pressure_bar))
            .into_iter()
            .map(|p| Group::P { pressure_bar: p })
            .collect(),
        designs
            .into_iter()
            .map(|(n, t)| Group::Design {
                n_bellows: n,
                wall_thickness_mm: t,
            })
            .collect(),
        levels(&|c| c.marker.map(f64::from))
            .into_iter()
            .map(|k| Group::Marker { marker: k as u8 })
            .collect(),
    ]
}

fn share(cells: &[Cell], chi2: f64, family: Option<Family>, group: Option<Group>) -> Option<Share> {
    let sel: Vec<f64> = cells
        .iter()
        .filter(|c| family.is_none_or(|f| c.family == f) && group.is_none_or(|g| g.holds(c)))
        .map(|c| c.standardised)
        .collect();
    if sel.is_empty() {
        return None;
    }
    let n = sel.len() as f64;
    let c2: f64 = sel.iter().map(|z| z * z).sum();
    Some(Share {
        family,
        group,
        cells: sel.len(),
        cell_fraction: n / cells.len() as f64,
        chi2: c2,
        share: c2 / chi2.max(1e-300),
        mean_z: sel.iter().sum::<f64>() / n,
        rms_z: (c2 / n).sqrt(),
    })
}

/// The χ² shares of the table.
pub fn shares(cells: &[Cell], chi2: f64) -> Shares {
    let [ts, ns, ps, designs, markers] = groups_of(cells);
    let by = |gs: Vec<Group>| -> Vec<Share> {
        gs.into_iter()
            .filter_map(|g| share(cells, chi2, None, Some(g)))
            .collect()
    };
    Shares {
        by_output: Family::ALL
            .iter()
            .filter_map(|&f| share(cells, chi2, Some(f), None))
            .collect(),
        by_design: by(designs),
        by_n: by(ns),
        by_t: by(ts),
        by_p: by(ps),
        by_marker: by(markers),
    }
}

/// The misfit of each output present (p-values unadjusted).
pub fn misfits(cells: &[Cell]) -> Vec<Misfit> {
    Family::ALL
        .iter()
        .filter_map(|&f| {
            let sel: Vec<&Cell> = cells.iter().filter(|c| c.family == f).collect();
            if sel.is_empty() {
                return None;
            }
            let chi2: f64 = sel.iter().map(|c| c.standardised.powi(2)).sum();
            let n = sel.len();
            let p_value = ChiSquared::new(n as f64).map_or(f64::NAN, |d| 1.0 - d.cdf(chi2));
            Some(Misfit {
                family: f,
                fitted: sel.iter().any(|c| c.fitted),
                cells: n,
                chi2,
                rms_z: (chi2 / n as f64).sqrt(),
                p_value,
                significant: false,
            })
        })
        .collect()
}

/// The mean of every output in every group with at least 2 cells (p-values unadjusted).
pub fn group_means(cells: &[Cell]) -> Vec<GroupMean> {
    let normal = Normal::standard();
    let all_groups = groups_of(cells);
    let mut out = Vec::new();
    for f in Family::ALL {
        for gs in &all_groups {
            for &g in gs {
                let sel: Vec<f64> = cells
                    .iter()
                    .filter(|c| c.family == f && g.holds(c))
                    .map(|c| c.standardised)
                    .collect();
                if sel.len() < 2 {
                    continue;
                }
                let n = sel.len() as f64;
                let z = sel.iter().sum::<f64>() / n.sqrt();
                out.push(GroupMean {
                    family: f,
                    group: g,
                    cells: sel.len(),
                    mean_z: sel.iter().sum::<f64>() / n,
                    positive: sel.iter().filter(|v| **v > 0.0).count(),
                    negative: sel.iter().filter(|v| **v < 0.0).count(),
                    z,
                    p_value: 2.0 * (1.0 - normal.cdf(z.abs())),
                    significant: false,
                });
            }
        }
    }
    out
}

/// Holm's step-down procedure: which of `p` are significant at family-wise level `alpha`.
pub fn holm(p: &[f64], alpha: f64) -> Vec<bool> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut out = vec![false; m];
    for (j, &i) in order.iter().enumerate() {
        if p[i].is_finite() && p[i] <= alpha / (m - j) as f64 {
            out[i] = true;
        } else {
            break;
        }
    }
    out
}
