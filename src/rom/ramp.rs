//! One design and material, any pressure: the surrogate's whole pressure ramp, reconstructed
//! once.
//!
//! The regression input is the design and the material only; pressure enters through the
//! interpolation of the reconstructed ramp (`predict::stencil`). A gripper controller (design
//! and calibrated material fixed, pressure varying) or an optimisation over pressure therefore
//! needs the regression once: [`Surrogate::ramp`] evaluates all 22 quantities at every node of
//! the pressure grid, and [`Ramp::predict_into`] is then the 4-node cubic Hermite stencil
//! alone, with exactly the arithmetic of [`Surrogate::predict_into`] (the results are
//! identical bit for bit, tested).
//!
//! ```
//! use surrogate::rom::data::SnapshotSet;
//! use surrogate::rom::synthetic::{write_csv, SyntheticConfig};
//! use surrogate::case::{OgdenSet, Query};
//! use surrogate::rom::{train, TrainConfig};
//!
//! let mut csv = Vec::new();
//! write_csv(&SyntheticConfig { n_cases: 24, ..Default::default() }, &mut csv)?;
//! let cases = SnapshotSet::from_reader(csv.as_slice(), "demo")?.into_cases()?;
//! let cfg = TrainConfig { folds: 3, ..Default::default() };
//! let model = train(&cases, "demo", 0, &cfg, &|_, _| {})?.surrogate;
//!
//! // design and material fixed (a controller), pressure varying
//! let ogden_002 = OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]);
//! let q = Query::new(11, 2.0, 0.0, ogden_002);
//! let ramp = model.ramp(&q)?;
//! let mut pred = model.new_prediction();
//! ramp.predict_into(2.3, &mut pred)?;
//! let direct = model.predict(&Query { p_bar: 2.3, ..q })?;
//! assert_eq!(pred.values, direct.values);
//! let [tip_uz, _tip_uy, _angle, _force] = ramp.predict_scalars(2.3)?;
//! assert_eq!(tip_uz, direct.tip_uz_mm());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::fast::SCALARS;
use super::surrogate::{Prediction, Surrogate};
use super::{RomError, QUANTITY_NAMES, Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::Query;
use surrogate_predict::stencil;

const NQ: usize = QUANTITY_NAMES.len();

/// The reconstructed pressure ramp of one design and material ([module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct Ramp {
    /// The design and material (its `p_bar` is not used).
    pub query: Query,
    /// The model's pressure grid, bar.
    pressures: Vec<f64>,
    /// The 22 quantities at each grid node, node-major.
    values: Vec<f64>,
}

impl Surrogate {
    /// The ramp of `q`'s design and material (`q.p_bar` is ignored).
    ///
    /// # Errors
    /// Invalid query ([`Surrogate::check_query`]).
    pub fn ramp(&self, q: &Query) -> Result<Ramp, RomError> {
        let mut pred = self.new_prediction();
        let mut values = Vec::with_capacity(self.pressures.len() * NQ);
        for &p in &self.pressures {
            // at a node the stencil is that node's value alone
            self.predict_into(&Query { p_bar: p, ..*q }, &mut pred)?;
            values.extend_from_slice(&pred.values);
        }
        Ok(Ramp {
            query: *q,
            pressures: self.pressures.clone(),
            values,
        })
    }
}

impl Ramp {
    /// The pressure grid, bar.
    pub fn pressures(&self) -> &[f64] {
        &self.pressures
    }

    /// The 22 quantities at each grid node, node-major (`values[j * 22 + q]`).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// All 22 quantities at `p_bar` (clamped to the grid, as in
    /// [`Surrogate::predict_into`]); no allocation.
    ///
    /// # Errors
    /// A non-finite pressure.
    pub fn predict_into(&self, p_bar: f64, pred: &mut Prediction) -> Result<(), RomError> {
        self.interpolate(p_bar, 0..NQ, &mut pred.values)?;
        pred.has_std = false;
        Ok(())
    }

    /// Tip Uz, tip Uy (mm), angle (deg) and force (N) at `p_bar`.
    ///
    /// # Errors
    /// A non-finite pressure.
    pub fn predict_scalars(&self, p_bar: f64) -> Result<[f64; 4], RomError> {
        let mut v = [0.0; NQ];
        self.interpolate(p_bar, SCALARS, &mut v)?;
        Ok([v[Q_TIP_UZ], v[Q_TIP_UY], v[Q_ANGLE], v[Q_FORCE]])
    }

    fn interpolate(
        &self,
        p_bar: f64,
        range: std::ops::Range<usize>,
        out: &mut [f64; NQ],
    ) -> Result<(), RomError> {
        if !p_bar.is_finite() {
            return Err(RomError::invalid("p_bar", p_bar, "a finite number"));
        }
        let st = stencil(&self.pressures, p_bar);
        for qi in range {
            let mut v = 0.0;
            for s in 0..st.len {
                v += st.w[s] * self.values[(st.start + s) * NQ + qi];
            }
            out[qi] = v;
        }
        Ok(())
    }
}
