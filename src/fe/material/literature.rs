//! Literature parameter sets, parsed from `training_data/literature_materials.csv`.
//!
//! Columns: `name, model, source, mu1_mpa, alpha1, mu2_mpa, alpha2, c10_mpa, c01_mpa, c20_mpa,
//! c11_mpa, c02_mpa, d1_per_mpa, initial_shear_modulus_mpa`. `model` is `ogden2`,
//! `mooney_rivlin5` or `neo_hookean` (shear modulus in `mu1_mpa`). The stated
//! `initial_shear_modulus_mpa` is checked against the law's `μ0` (relative 10⁻³).
//! `d1_per_mpa` (ANSYS incompressibility, 0 = incompressible) is not used: the bulk modulus
//! is chosen by the caller ([`Material::new`](super::Material::new)).

use serde::Deserialize;

use super::{MaterialError, MaterialLaw, MooneyRivlin5, NeoHookean, Ogden2};

/// The shipped CSV.
const LITERATURE_CSV: &str = include_str!("../../../training_data/literature_materials.csv");

/// Relative tolerance between the stated and the computed initial shear modulus.
const MU0_TOL: f64 = 1e-3;

/// One CSV row.
#[derive(Debug, Deserialize)]
struct Row {
    name: String,
    model: String,
    mu1_mpa: Option<f64>,
    alpha1: Option<f64>,
    mu2_mpa: Option<f64>,
    alpha2: Option<f64>,
    c10_mpa: Option<f64>,
    c01_mpa: Option<f64>,
    c20_mpa: Option<f64>,
    c11_mpa: Option<f64>,
    c02_mpa: Option<f64>,
    initial_shear_modulus_mpa: Option<f64>,
}

/// Error for CSV row `line` (1-based data row).
fn row_error(line: usize, reason: String) -> MaterialError {
    MaterialError::Parse {
        spec: format!("literature_materials.csv data row {line}"),
        reason,
    }
}

/// A required column of a row.
fn need(line: usize, column: &str, value: Option<f64>) -> Result<f64, MaterialError> {
    value.ok_or_else(|| row_error(line, format!("column {column} is empty")))
}

impl Row {
    /// The law described by this row.
    fn law(&self, line: usize) -> Result<MaterialLaw, MaterialError> {
        let law = match self.model.trim() {
            "ogden2" => MaterialLaw::Ogden(Ogden2::new(
                need(line, "mu1_mpa", self.mu1_mpa)?,
                need(line, "alpha1", self.alpha1)?,
                need(line, "mu2_mpa", self.mu2_mpa)?,
                need(line, "alpha2", self.alpha2)?,
            )?),
            "mooney_rivlin5" => MaterialLaw::MooneyRivlin(MooneyRivlin5::new(
                need(line, "c10_mpa", self.c10_mpa)?,
                need(line, "c01_mpa", self.c01_mpa)?,
                need(line, "c20_mpa", self.c20_mpa)?,
                need(line, "c11_mpa", self.c11_mpa)?,
                need(line, "c02_mpa", self.c02_mpa)?,
            )?),
            "neo_hookean" => {
                MaterialLaw::NeoHookean(NeoHookean::new(need(line, "mu1_mpa", self.mu1_mpa)?)?)
            }
            other => {
                return Err(row_error(
                    line,
                    format!("model {other:?}: expected ogden2, mooney_rivlin5 or neo_hookean"),
                ))
            }
        };
        if let Some(stated) = self.initial_shear_modulus_mpa {
            let mu0 = law.initial_shear_modulus();
            if (mu0 - stated).abs() > MU0_TOL * stated.abs() {
                return Err(row_error(
                    line,
                    format!("initial_shear_modulus_mpa = {stated} but the parameters give {mu0}"),
                ));
            }
        }
        Ok(law)
    }
}

/// The literature sets `(name, law)` in file order.
///
/// # Errors
/// [`MaterialError::Parse`] if a row cannot be read, [`MaterialError::Inadmissible`] if its
/// parameters are not admissible.
pub fn literature_sets() -> Result<Vec<(String, MaterialLaw)>, MaterialError> {
    let mut reader = csv::Reader::from_reader(LITERATURE_CSV.as_bytes());
    reader
        .deserialize::<Row>()
        .enumerate()
        .map(|(i, row)| {
            let row = row.map_err(|e| row_error(i + 1, e.to_string()))?;
            let law = row.law(i + 1)?;
            Ok((row.name.trim().to_owned(), law))
        })
        .collect()
}
