//! Consistency of a surrogate read from a model file: every table of the sizes the others
//! give, before any prediction indexes them.

use super::surrogate::Surrogate;
use super::QUANTITY_NAMES;
use surrogate_predict::N_FEATURES;

impl Surrogate {
    /// Internal consistency of a (loaded) model.
    ///
    /// # Errors
    /// A message naming the inconsistent part.
    pub fn check_consistency(&self) -> Result<(), String> {
        let d = self.features.dim();
        let f = &self.features;
        if f.center.len() != d
            || f.inv_half.len() != d
            || f.index.windows(2).any(|w| w[0] >= w[1])
            || f.index.iter().any(|&i| i >= N_FEATURES)
        {
            return Err(format!(
                "feature scaling: {} active features of {N_FEATURES}, {} centres, {} widths; \
                 expected increasing indices below {N_FEATURES}, one centre and width each",
                d,
                f.center.len(),
                f.inv_half.len()
            ));
        }
        self.check_regressors()?;
        let m = self.n_coefs();
        if self.pressures.len() < 2 || self.pressures.windows(2).any(|w| w[0] >= w[1]) {
            return Err("pressure grid must have ≥ 2 increasing values".into());
        }
        if self.output_block.len() != 22
            || self.std_scale.len() != 22
            || self.output_slot.len() != 22
            || self.inputs.len() != 7
        {
            return Err("output or input tables do not have 22 outputs / 7 inputs".into());
        }
        for b in &self.blocks {
            let p = &b.pod;
            let dim = p.dim();
            if p.n_pressures != self.pressures.len()
                || p.mean.len() != dim
                || p.scale.len() != dim
                || dim.checked_mul(p.n_modes) != Some(p.modes.len())
                || b.coef_offset
                    .checked_add(p.n_modes)
                    .is_none_or(|end| end > m)
            {
                return Err(format!("block {} has inconsistent sizes", b.name));
            }
        }
        for q in 0..22 {
            let b = self
                .blocks
                .get(self.output_block[q])
                .ok_or("output block index out of range")?;
            if b.pod.quantities.get(self.output_slot[q]) != Some(&q) {
                return Err(format!(
                    "output {} is not mapped to its block",
                    QUANTITY_NAMES[q]
                ));
            }
        }
        Ok(())
    }

    /// The regressors: at least one, all with the model's features and one output count, their
    /// own tables consistent ([`Regressor::check`]), and every block's among them.
    ///
    /// [`Regressor::check`]: super::regression::Regressor::check
    fn check_regressors(&self) -> Result<(), String> {
        let (d, m) = (self.features.dim(), self.n_coefs());
        if self.regressors.is_empty() {
            return Err("no regressor".into());
        }
        if self
            .regressors
            .iter()
            .any(|r| r.n_inputs() != d || r.n_outputs() != m)
        {
            let dims: Vec<String> = self
                .regressors
                .iter()
                .map(|r| format!("{} {}x{}", r.name(), r.n_inputs(), r.n_outputs()))
                .collect();
            return Err(format!(
                "regressor dimensions ({}) do not match {d} features and one output count",
                dims.join(", ")
            ));
        }
        let blocks: Vec<std::ops::Range<usize>> = self
            .blocks
            .iter()
            .map(|b| b.coef_offset..b.coef_offset.saturating_add(b.pod.n_modes))
            .collect();
        for r in self.regressors.iter() {
            r.check(&blocks)?;
        }
        for b in &self.blocks {
            if self.regressors.position(&b.regressor).is_none() {
                return Err(format!(
                    "block {} uses regressor `{}`, which the model does not hold (it holds {}; a \
                     regressor outside the built-ins is read only where it is registered)",
                    b.name,
                    b.regressor,
                    self.regressors.names().join(", ")
                ));
            }
        }
        Ok(())
    }
}
