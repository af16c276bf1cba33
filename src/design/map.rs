//! Maps for figures: outputs over a grid of `N`, `T` and `P`, NaN where the wall is not
//! buildable.

use std::io::Write;

use serde::{Deserialize, Serialize};

use super::problem::{buildable_t_max, check_material, check_pressure, check_t, geometry};
use super::target::Output;
use super::DesignError;
use crate::case::{OgdenSet, Query};
use crate::rom::Surrogate;
use crate::schema;

/// The predicted outputs over a grid of `(N, T, P)` ([`map`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignMap {
    /// The material (in the file: `[μ₁ MPa, α₁, μ₂ MPa, α₂]`).
    #[serde(with = "crate::case::material::array")]
    pub material: OgdenSet,
    /// The outputs.
    pub outputs: Vec<Output>,
    /// The pressures, bar.
    pub pressures: Vec<f64>,
    /// The numbers of bellows.
    pub n_values: Vec<u32>,
    /// The wall thicknesses, mm.
    pub t_mm: Vec<f64>,
    /// The numbers of bellows among `n_values` the model was trained on.
    pub trained_n: Vec<u32>,
    /// The largest buildable wall of each of `n_values`, mm (`−∞`: none).
    pub t_max_buildable_mm: Vec<f64>,
    /// The geometry preset buildability was judged with.
    pub geometry: String,
    /// The values, `[output][pressure][n][t]` ([`DesignMap::value`]); NaN where not buildable.
    pub values: Vec<f64>,
}

impl DesignMap {
    /// The value of output `o` at pressure `p`, `N = n_values[n]`, `T = t_mm[t]` (indices);
    /// NaN where that wall is not buildable.
    ///
    /// # Panics
    /// An index out of range.
    pub fn value(&self, o: usize, p: usize, n: usize, t: usize) -> f64 {
        assert!(o < self.outputs.len() && p < self.pressures.len());
        assert!(n < self.n_values.len() && t < self.t_mm.len());
        let (np, nn, nt) = (self.pressures.len(), self.n_values.len(), self.t_mm.len());
        self.values[((o * np + p) * nn + n) * nt + t]
    }

    /// Whether the wall `t_mm[t]` is buildable with `n_values[n]` bellows.
    ///
    /// # Panics
    /// An index out of range.
    pub fn buildable(&self, n: usize, t: usize) -> bool {
        self.t_mm[t] <= self.t_max_buildable_mm[n]
    }

    /// Writes the map as CSV: one row per `(N, T, P)`, columns `n_bellows`,
    /// `wall_thickness_mm`, `pressure_bar`, `buildable`, then one per output (empty where not
    /// buildable).
    ///
    /// # Errors
    /// Write failures.
    pub fn write_csv<W: Write>(&self, out: W) -> std::io::Result<()> {
        let mut w = std::io::BufWriter::new(out);
        let mut header = vec![
            schema::N_BELLOWS.name,
            schema::WALL_THICKNESS.name,
            schema::PRESSURE.name,
            "buildable",
        ];
        header.extend(self.outputs.iter().map(|o| o.name()));
        writeln!(w, "{}", header.join(","))?;
        for (n_i, n) in self.n_values.iter().enumerate() {
            for (t_i, t) in self.t_mm.iter().enumerate() {
                for (p_i, p) in self.pressures.iter().enumerate() {
                    let ok = self.buildable(n_i, t_i);
                    write!(w, "{n},{t},{p},{ok}")?;
                    for o_i in 0..self.outputs.len() {
                        let v = self.value(o_i, p_i, n_i, t_i);
                        if v.is_finite() {
                            write!(w, ",{v}")?;
                        } else {
                            write!(w, ",")?;
                        }
                    }
                    writeln!(w)?;
                }
            }
        }
        w.flush()
    }
}

/// Checks the grid: each list non-empty, every `N` one the model predicts, every `T` and `P`
/// inside the model's ranges.
fn check_grid(
    model: &Surrogate,
    outputs: &[Output],
    pressures: &[f64],
    n_values: &[u32],
    t_grid: &[f64],
) -> Result<Vec<f64>, DesignError> {
    for (field, len) in [
        ("outputs", outputs.len()),
        ("pressures", pressures.len()),
        ("n_values", n_values.len()),
        ("t_grid", t_grid.len()),
    ] {
        if len == 0 {
            return Err(DesignError::invalid(field, "[]", "at least one value"));
        }
    }
    for (i, &p) in pressures.iter().enumerate() {
        check_pressure(model, &format!("pressures[{i}]"), p)?;
    }
    for (i, n) in n_values.iter().enumerate() {
        if !model.n_allowed.contains(n) {
            return Err(DesignError::invalid(
                format!("n_values[{i}]"),
                n,
                format!("an N the model predicts {:?}", model.n_allowed),
            ));
        }
    }
    t_grid
        .iter()
        .enumerate()
        .map(|(i, &t)| check_t(model, &format!("t_grid[{i}]"), t))
        .collect()
}

/// The predicted value of each of `outputs` at every `(N, T, P)` of the grid, NaN where `T`
/// is beyond the buildable wall of `N` (with the geometry the model was trained on; see the
/// [module docs](super)).
///
/// ```
/// use surrogate::case::OgdenSet;
/// use surrogate::design::{map, Output};
/// use surrogate::rom::Surrogate;
///
/// let model = Surrogate::load(std::path::Path::new("models/actuator.json"))?;
/// // the set calibrated through the shipped model (`fe_reference/identification/shipped_surrogate/`)
/// let material = OgdenSet::from_array([0.2108, 18.1271, -1.2232, -1.9958]);
/// let m = map(&model, material, &[Output::AngleDeg], &[2.0], &[9, 13], &[1.4, 2.0, 2.6])?;
/// // a thinner wall bends more
/// assert!(m.value(0, 0, 0, 0) > m.value(0, 0, 0, 2));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`DesignError::Invalid`]: an empty list, an `N` the model does not predict, a `T` or `P`
/// outside the model's ranges, a material the model refuses or outside its domain.
pub fn map(
    model: &Surrogate,
    material: OgdenSet,
    outputs: &[Output],
    pressures: &[f64],
    n_values: &[u32],
    t_grid: &[f64],
) -> Result<DesignMap, DesignError> {
    let t_mm = check_grid(model, outputs, pressures, n_values, t_grid)?;
    let material = check_material(model, material)?;
    let geometry = geometry(model);
    let t_max: Vec<f64> = n_values
        .iter()
        .map(|&n| buildable_t_max(&geometry, n))
        .collect();
    let (np, nn, nt) = (pressures.len(), n_values.len(), t_mm.len());
    let mut values = vec![f64::NAN; outputs.len() * np * nn * nt];
    let mut pred = model.new_prediction();
    for (n_i, &n) in n_values.iter().enumerate() {
        for (t_i, &t) in t_mm.iter().enumerate().filter(|(_, &t)| t <= t_max[n_i]) {
            for (p_i, &p) in pressures.iter().enumerate() {
                model.predict_scalars_into(&Query::new(n, t, p, material), &mut pred)?;
                for (o_i, o) in outputs.iter().enumerate() {
                    values[((o_i * np + p_i) * nn + n_i) * nt + t_i] = pred.values[o.index()];
                }
            }
        }
    }
    Ok(DesignMap {
        material,
        outputs: outputs.to_vec(),
        pressures: pressures.to_vec(),
        n_values: n_values.to_vec(),
        t_mm,
        trained_n: trained_n(model, n_values),
        t_max_buildable_mm: t_max,
        geometry: geometry.name,
        values,
    })
}

/// The numbers of bellows among `n_values` the model was trained on (an ordinal model
/// predicts more: [`Surrogate::n_trained`]).
fn trained_n(model: &Surrogate, n_values: &[u32]) -> Vec<u32> {
    n_values
        .iter()
        .copied()
        .filter(|n| model.n_trained().contains(n))
        .collect()
}
