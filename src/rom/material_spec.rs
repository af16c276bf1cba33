//! A material given as the calibration report that found it.
//!
//! Wherever a material spec is taken (`--material` of every command, the `material` column of
//! a query CSV), a path ending in `.json` names a calibration report, `report.json` of
//! `surrogate calibrate --out DIR`, and stands for its calibrated set `calibration.best`
//! (`mu1_mpa, alpha1, mu2_mpa, alpha2`) at full precision:
//!
//! ```text
//! surrogate predict --n 11 --t 2.0 --pressure 1.5 --material calibration/report.json
//! ```
//!
//! [`expand`] turns such a spec into the four numbers `mu1,alpha1,mu2,alpha2`, written in
//! shortest round-trip form (the set exactly as the report stores it); any other spec (a
//! literature name, four numbers, `neo_hookean:MU`) is returned as given, for
//! [`crate::fe::material::Material::from_spec`].

use std::path::Path;

use super::RomError;
use crate::case::OgdenSet;
use crate::schema;

/// What a spec naming a report file ends with (case-insensitive).
const REPORT_SUFFIX: &str = ".json";

/// Whether `spec` names a calibration report file (a path ending in `.json`).
pub fn is_report(spec: &str) -> bool {
    let spec = spec.trim();
    spec.len() > REPORT_SUFFIX.len()
        && spec[spec.len() - REPORT_SUFFIX.len()..].eq_ignore_ascii_case(REPORT_SUFFIX)
}

/// The calibrated Ogden set of a calibration report
/// (`calibration.best` of `report.json`).
///
/// # Errors
/// The file cannot be read, is not JSON, or has no calibrated set of four finite numbers;
/// each message names the file and what it should hold.
pub fn report_material(path: &Path) -> Result<OgdenSet, RomError> {
    let shown = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| RomError::Io {
        path: shown.clone(),
        source,
    })?;
    let expected = "a calibration report (`report.json` of `surrogate calibrate --out DIR`) \
                    with the calibrated set calibration.best {mu1_mpa, alpha1, mu2_mpa, alpha2}";
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| RomError::invalid("material", &shown, &format!("{expected}; {e}")))?;
    let best = &value["calibration"]["best"];
    let mut set = [0.0; 4];
    for (slot, column) in set.iter_mut().zip(schema::OGDEN_COLUMNS) {
        *slot = best[column.name]
            .as_f64()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                RomError::invalid(
                    "material",
                    &shown,
                    &format!("{expected}; calibration.best.{} is missing", column.name),
                )
            })?;
    }
    Ok(OgdenSet::from_array(set))
}

/// `spec` with a calibration report file replaced by its calibrated set as
/// `mu1,alpha1,mu2,alpha2` (shortest round-trip digits: the set exactly); any other spec as
/// given.
///
/// ```
/// use surrogate::rom::material_spec::expand;
/// assert_eq!(expand("ogden_002").unwrap(), "ogden_002");
/// let set = expand("fe_reference/calibration/surrogate/report.json").unwrap();
/// assert_eq!(set, "0.03821164173136228,5.99612765572898,-5.194862363697796,-1.996454844367204");
/// ```
///
/// # Errors
/// See [`report_material`].
pub fn expand(spec: &str) -> Result<String, RomError> {
    if !is_report(spec) {
        return Ok(spec.to_string());
    }
    let set = report_material(Path::new(spec.trim()))?;
    Ok(set.as_array().map(|v| v.to_string()).join(","))
}
