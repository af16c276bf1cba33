//! Residuals and their Jacobian through the surrogate, with buffers reused across evaluations.

use super::observations::ObservationSet;
use crate::calibrate::params::ParamSpace;
use crate::calibrate::CalibrateError;
use crate::case::Query;
use crate::rom::{Jacobian, Prediction, Surrogate};

/// Buffers for evaluating residuals (reused across evaluations: no allocation per call).
#[derive(Clone, Debug)]
pub struct Evaluator<'a> {
    model: &'a Surrogate,
    set: &'a ObservationSet,
    space: ParamSpace,
    pred: Vec<Prediction>,
    jac: Vec<Jacobian>,
    /// `√wᵢ / σᵢ` per observation.
    scale: Vec<f64>,
    /// The surrogate quantities the observations read.
    quantities: std::ops::Range<usize>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator of `set` through `model`, with parameters in `space`.
    pub fn new(model: &'a Surrogate, set: &'a ObservationSet, space: ParamSpace) -> Self {
        let k = set.configs.len();
        Evaluator {
            model,
            set,
            space,
            pred: (0..k).map(|_| model.new_prediction()).collect(),
            jac: vec![Jacobian::default(); k],
            scale: set
                .obs
                .iter()
                .map(|o| o.weight.sqrt() / o.sigma())
                .collect(),
            quantities: {
                let q = set.obs.iter().map(|o| o.output.quantity());
                let lo = q.clone().min().unwrap_or(0);
                let hi = q.max().map_or(22, |v| v + 1);
                lo..hi
            },
        }
    }

    /// The surrogate.
    pub fn model(&self) -> &'a Surrogate {
        self.model
    }

    /// The parameter space.
    pub fn space(&self) -> &ParamSpace {
        &self.space
    }

    /// The observations.
    pub fn set(&self) -> &ObservationSet {
        self.set
    }

    /// Residuals `r` (and, if `jac` is given, `∂r/∂u` row by row) at unit-box point `u`.
    ///
    /// # Errors
    /// A query the surrogate rejects (cannot happen inside the space's box).
    pub fn residuals(
        &mut self,
        u: &[f64; 4],
        r: &mut [f64],
        jac: Option<&mut [[f64; 4]]>,
    ) -> Result<(), CalibrateError> {
        let p = self.space.ogden(u)?;
        let with_jac = jac.is_some();
        for (k, c) in self.set.configs.iter().enumerate() {
            let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, p);
            if with_jac {
                self.model.gradient_range_into(
                    &q,
                    self.quantities.clone(),
                    &mut self.pred[k],
                    &mut self.jac[k],
                )?;
            } else {
                if self.quantities.start >= crate::rom::Q_TIP_UZ {
                    // tip, angle and force only: the folded scalar path
                    self.model.predict_scalars_into(&q, &mut self.pred[k])?;
                } else {
                    self.model.predict_into(&q, &mut self.pred[k])?;
                }
            }
        }
        for (i, o) in self.set.obs.iter().enumerate() {
            let qi = o.output.quantity();
            r[i] = self.scale[i] * (self.pred[self.set.config_of[i]].values[qi] - o.value);
        }
        if let Some(jac) = jac {
            let dm = self.space.ogden_jacobian(u);
            for (i, o) in self.set.obs.iter().enumerate() {
                let qi = o.output.quantity();
                let d = self.jac[self.set.config_of[i]].of(qi).material();
                for (j, out) in jac[i].iter_mut().enumerate() {
                    let mut v = 0.0;
                    for a in 0..4 {
                        v += d[a] * dm[a][j];
                    }
                    *out = self.scale[i] * v;
                }
            }
        }
        Ok(())
    }

    /// The predictions of every observation at `u` (unscaled), in observation order.
    ///
    /// # Errors
    /// As [`Self::residuals`].
    pub fn predictions(&mut self, u: &[f64; 4]) -> Result<Vec<f64>, CalibrateError> {
        let mut r = vec![0.0; self.set.len()];
        self.residuals(u, &mut r, None)?;
        Ok(self
            .set
            .obs
            .iter()
            .enumerate()
            .map(|(i, o)| r[i] / self.scale[i] + o.value)
            .collect())
    }

    /// `χ²(u) = Σ rᵢ²`.
    ///
    /// # Errors
    /// As [`Self::residuals`].
    pub fn chi2(&mut self, u: &[f64; 4]) -> Result<f64, CalibrateError> {
        let mut r = vec![0.0; self.set.len()];
        self.residuals(u, &mut r, None)?;
        Ok(r.iter().map(|v| v * v).sum())
    }
}
