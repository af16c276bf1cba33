//! Material specifications as text (CLI flags, config files).
//!
//! Accepted forms (surrounding whitespace ignored):
//! * a literature name, case-insensitive: `ogden_002`, `ogden_005`, `mooney_rivlin_5`;
//! * four comma-separated Ogden parameters `mu1,alpha1,mu2,alpha2` (MPa);
//! * `neo_hookean:MU` (MPa).

use super::{literature_sets, Material, MaterialError, MaterialLaw, NeoHookean, Ogden2};

/// Prefix of the neo-Hookean form.
const NEO_HOOKEAN_PREFIX: &str = "neo_hookean:";

/// Names of the Ogden parameters in the comma form.
const OGDEN_FIELDS: [&str; 4] = ["mu1", "alpha1", "mu2", "alpha2"];

/// Parses one number of `spec`; the error names `field`.
fn number(spec: &str, field: &str, text: &str) -> Result<f64, MaterialError> {
    text.trim()
        .parse::<f64>()
        .map_err(|_| MaterialError::Parse {
            spec: spec.to_owned(),
            reason: format!("{field} = {:?} is not a number", text.trim()),
        })
}

/// Parses the law of a specification (see the module docs).
fn parse_law(spec: &str) -> Result<MaterialLaw, MaterialError> {
    let text = spec.trim();
    let lower = text.to_ascii_lowercase();
    if let Some(mu) = lower.strip_prefix(NEO_HOOKEAN_PREFIX) {
        return Ok(MaterialLaw::NeoHookean(NeoHookean::new(number(
            spec, "mu", mu,
        )?)?));
    }
    if text.contains(',') {
        let parts: Vec<&str> = text.split(',').collect();
        if parts.len() != OGDEN_FIELDS.len() {
            return Err(MaterialError::Parse {
                spec: spec.to_owned(),
                reason: format!(
                    "{} comma-separated values: expected 4 (mu1,alpha1,mu2,alpha2)",
                    parts.len()
                ),
            });
        }
        let mut v = [0.0; 4];
        for ((slot, field), part) in v.iter_mut().zip(OGDEN_FIELDS).zip(&parts) {
            *slot = number(spec, field, part)?;
        }
        return Ok(MaterialLaw::Ogden(Ogden2::new(v[0], v[1], v[2], v[3])?));
    }
    let sets = literature_sets()?;
    if let Some((_, law)) = sets
        .iter()
        .find(|(name, _)| name.to_ascii_lowercase() == lower)
    {
        return Ok(law.clone());
    }
    let names: Vec<&str> = sets.iter().map(|(n, _)| n.as_str()).collect();
    Err(MaterialError::UnknownName {
        name: text.to_owned(),
        known: format!(
            "{} (literature), \"mu1,alpha1,mu2,alpha2\" (Ogden) or \"neo_hookean:MU\"",
            names.join(", ")
        ),
    })
}

impl Material {
    /// A material from a text specification, with `κ = bulk_ratio · μ0`.
    ///
    /// Accepted: `"ogden_002" | "ogden_005" | "mooney_rivlin_5"` (literature, case-insensitive),
    /// `"mu1,alpha1,mu2,alpha2"` (Ogden) or `"neo_hookean:MU"`.
    ///
    /// ```
    /// use surrogate::fe::material::Material;
    /// let m = Material::from_spec("OGDEN_002", 1000.0)?;
    /// assert!((m.mu0() - 5.708).abs() < 1e-3);
    /// assert_eq!(m.ogden_set().map(|s| s.as_array()), Some([1.13, 3.11, -13.17, -0.6]));
    /// assert!(Material::from_spec("ogden_999", 1000.0).is_err());
    /// # Ok::<(), surrogate::fe::material::MaterialError>(())
    /// ```
    ///
    /// # Errors
    /// [`MaterialError::UnknownName`] for an unknown name, [`MaterialError::Parse`] for a
    /// malformed list or number, [`MaterialError::Inadmissible`] for inadmissible values or
    /// `bulk_ratio`.
    pub fn from_spec(spec: &str, bulk_ratio: f64) -> Result<Self, MaterialError> {
        Material::new(parse_law(spec)?, bulk_ratio)
    }
}
