//! `anisotropy`: print anisotropy: fibre modulus along the length over μ0 (1).

use super::effect::{CaseEffect, Effect, EffectInfo, Kind, Target};
use crate::fe::material::{Fibre, Material, MaterialError};

/// `anisotropy`: print anisotropy: fibre term along the length (deposition), k = a·μ0.
pub struct Anisotropy;

const INFO: EffectInfo = EffectInfo {
    name: "anisotropy",
    meaning: "print anisotropy: fibre term along the length (deposition), k = a·μ0",
    unit: "1",
    neutral: 0.0,
    range: (-0.25, 1.0),
    kind: Kind::Tolerance,
    source: "printed sideways with PrusaSlicer, 0.4 mm nozzle, 0.15 mm layers; no anisotropy is reported",
};

#[allow(non_upper_case_globals)]
impl Effect {
    /// Print anisotropy: fibre modulus along the length over μ0 (1).
    pub const Anisotropy: Effect = Effect::builtin(13, &Anisotropy);
}

impl CaseEffect for Anisotropy {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Material
    }
    /// `material` with a fibre term along the length, `k = a·μ0`.
    ///
    /// # Errors
    /// [`MaterialError::Inadmissible`] naming `fibre` when `material` already has a fibre
    /// term (the effect would replace it silently), or when `k` is outside the fibre's
    /// admissible range for this law.
    fn print_material(&self, a: f64, material: &Material) -> Result<Material, MaterialError> {
        if let Some(f) = &material.fibre {
            return Err(MaterialError::Inadmissible {
                field: "fibre".into(),
                value: f.modulus(),
                expected: "no fibre term in a material the anisotropy effect applies to \
                           (the effect adds its own along the length)"
                    .into(),
            });
        }
        let fibre = Fibre::new(Fibre::ALONG_LENGTH, a * material.mu0())?;
        material.clone().with_fibre(fibre)
    }
}
