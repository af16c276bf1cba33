//! Error statistics of held-out predictions: RMSE, max |error|, R², and the split of the
//! total error `y − ŷ` into the projection part `y − Πy` and the regression part `Πy − ŷ`.

use serde::{Deserialize, Serialize};

/// Summary of errors of one output over a held-out set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ErrorStats {
    /// Number of compared values.
    pub count: usize,
    /// Root mean square error.
    pub rmse: f64,
    /// Largest absolute error.
    pub max_abs: f64,
    /// Coefficient of determination `1 − SSE/SST`.
    pub r2: f64,
    /// Range `max y − min y` of the true values.
    pub range: f64,
}

/// Streaming accumulator for [`ErrorStats`].
#[derive(Debug, Clone, Default)]
pub struct ErrorAccumulator {
    n: usize,
    sse: f64,
    max_abs: f64,
    sum_y: f64,
    sum_y2: f64,
    min_y: f64,
    max_y: f64,
}

impl ErrorAccumulator {
    /// Adds one (truth, prediction) pair.
    pub fn add(&mut self, truth: f64, pred: f64) {
        if self.n == 0 {
            self.min_y = truth;
            self.max_y = truth;
        }
        let e = truth - pred;
        self.n += 1;
        self.sse += e * e;
        self.max_abs = self.max_abs.max(e.abs());
        self.sum_y += truth;
        self.sum_y2 += truth * truth;
        self.min_y = self.min_y.min(truth);
        self.max_y = self.max_y.max(truth);
    }

    /// Merges another accumulator (for per-fold partial sums).
    pub fn merge(&mut self, o: &ErrorAccumulator) {
        if o.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = o.clone();
            return;
        }
        self.n += o.n;
        self.sse += o.sse;
        self.max_abs = self.max_abs.max(o.max_abs);
        self.sum_y += o.sum_y;
        self.sum_y2 += o.sum_y2;
        self.min_y = self.min_y.min(o.min_y);
        self.max_y = self.max_y.max(o.max_y);
    }

    /// Root mean square error so far.
    pub fn rmse(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            (self.sse / self.n as f64).sqrt()
        }
    }

    /// The statistics.
    pub fn finish(&self) -> ErrorStats {
        let n = self.n.max(1) as f64;
        let sst = self.sum_y2 - self.sum_y * self.sum_y / n;
        ErrorStats {
            count: self.n,
            rmse: self.rmse(),
            max_abs: self.max_abs,
            // a constant truth has no variance to explain: report 0 (JSON has no NaN)
            r2: if sst > 0.0 { 1.0 - self.sse / sst } else { 0.0 },
            range: self.max_y - self.min_y,
        }
    }
}

/// Held-out validation of one output as stored in the model file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutputValidation {
    /// Output name (`tip_uz_mm`, …, `markers_mm`).
    pub name: String,
    /// How it is predicted: `field/gp`, `direct/poly`, ….
    pub source: String,
    /// Errors of the prediction (projection + regression).
    pub total: ErrorStats,
    /// RMSE of the projection onto the POD basis alone.
    pub projection_rmse: f64,
    /// RMSE of the regression alone (`Πy − ŷ`).
    pub regression_rmse: f64,
    /// Calibration of the predictive standard deviation: RMS of `(y − ŷ)/σ̂` over the held-out
    /// values (≈ 1 when calibrated, > 1 when the std is too small).
    pub std_ratio: f64,
}

/// Cross-validation table stored in a model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Validation {
    /// Scheme, e.g. `5-fold by case`.
    pub scheme: String,
    /// Number of held-out cases in total.
    pub n_cases: usize,
    /// The chosen predictor of each output.
    pub outputs: Vec<OutputValidation>,
    /// Every candidate that was compared (for the record).
    pub candidates: Vec<OutputValidation>,
    /// Error of the pressure interpolation alone, on the training ramps.
    pub pressure_interpolation: Vec<InterpolationCheck>,
    /// With `N` ordinal: the errors at numbers of bellows held out of a second training
    /// ([`super::held_out_n`]), the evidence that the model interpolates in `N`. Absent:
    /// not measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub held_out_n: Option<HeldOutNReport>,
}

/// Pressure-interpolation error of one output: each interior node of every training ramp is
/// left out and interpolated from the others (local spacing doubled, so an upper bound of the
/// error between nodes of the full grid).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InterpolationCheck {
    /// Output name.
    pub name: String,
    /// Errors of the leave-one-node-out interpolation.
    pub stats: ErrorStats,
}

impl Validation {
    /// Human-readable comparison of every candidate (field vs direct, GP vs polynomial).
    pub fn candidates_table(&self) -> String {
        let mut s = format!(
            "candidates (held-out RMSE; proj + regr split):\n{:<12} {:<12} {:>9} {:>9} {:>9}\n",
            "output", "source", "rmse", "proj", "regr"
        );
        for o in &self.candidates {
            let chosen = self
                .outputs
                .iter()
                .any(|c| c.name == o.name && c.source == o.source);
            s.push_str(&format!(
                "{:<12} {:<12} {:>9.4} {:>9.4} {:>9.4}{}\n",
                o.name,
                o.source,
                o.total.rmse,
                o.projection_rmse,
                o.regression_rmse,
                if chosen { "  <- chosen" } else { "" }
            ));
        }
        s
    }

    /// Human-readable table.
    pub fn table(&self) -> String {
        let mut s = format!(
            "validation: {} ({} cases), errors at the pressure nodes\n{:<12} {:<12} {:>9} {:>9} {:>8} {:>9} {:>9} {:>9} {:>7}\n",
            self.scheme, self.n_cases, "output", "source", "rmse", "max", "R2", "proj", "regr", "range", "z_rms"
        );
        for o in &self.outputs {
            s.push_str(&format!(
                "{:<12} {:<12} {:>9.4} {:>9.4} {:>8.5} {:>9.4} {:>9.4} {:>9.3} {:>7.2}\n",
                o.name,
                o.source,
                o.total.rmse,
                o.total.max_abs,
                o.total.r2,
                o.projection_rmse,
                o.regression_rmse,
                o.total.range,
                o.std_ratio
            ));
        }
        if !self.pressure_interpolation.is_empty() {
            s.push_str("pressure interpolation (leave-one-node-out on the ramps, upper bound between nodes): rmse / max\n");
            for c in &self.pressure_interpolation {
                s.push_str(&format!(
                    "{:<12} {:>9.4} {:>9.4}\n",
                    c.name, c.stats.rmse, c.stats.max_abs
                ));
            }
        }
        s
    }
}

/// Mean absolute errors of the scalar outputs over a set of held-out cases.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct HeldOutErrors {
    /// Number of held-out cases.
    pub cases: usize,
    /// Compared (case, pressure) points.
    pub points: usize,
    /// Mean distance between predicted and FE tip positions, mm.
    pub tip_mm: f64,
    /// Mean |angle error|, degrees.
    pub angle_deg: f64,
    /// Mean |blocked-force error|, N.
    pub force_n: f64,
    /// Largest tip distance, mm.
    pub max_tip_mm: f64,
}

impl HeldOutErrors {
    /// Table rows: a header, one row per `N` (`n_values` with `per_n` in the same order) and
    /// one for `all`.
    pub(crate) fn rows_by_n(n_values: &[u32], per_n: &[Self], all: &Self) -> String {
        let mut s = String::from("  N      cases  points  tip mm  (max)   angle °  force N\n");
        let row = |label: &str, e: &Self| {
            format!(
                "  {label:<6} {:>5}  {:>6}  {:>6.3}  ({:>5.2})  {:>7.3}  {:>7.4}\n",
                e.cases, e.points, e.tip_mm, e.max_tip_mm, e.angle_deg, e.force_n
            )
        };
        for (n, e) in n_values.iter().zip(per_n) {
            s.push_str(&row(&n.to_string(), e));
        }
        s.push_str(&row("all", all));
        s
    }
}

/// The result of [`super::held_out_n::study`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeldOutNReport {
    /// The numbers of bellows held out.
    pub held_out: Vec<u32>,
    /// The numbers of bellows trained on.
    pub trained: Vec<u32>,
    /// Training cases.
    pub training_cases: usize,
    /// Errors per held-out `N`, in `held_out` order.
    pub per_n: Vec<HeldOutErrors>,
    /// Errors over every held-out case.
    pub all: HeldOutErrors,
}

impl HeldOutNReport {
    /// A text table: one row per held-out `N` and one for all.
    pub fn table(&self) -> String {
        let mut s = format!(
            "trained on N = {:?} ({} cases); mean |error| over every held-out case and pressure > 0\n",
            self.trained, self.training_cases
        );
        s.push_str(&HeldOutErrors::rows_by_n(
            &self.held_out,
            &self.per_n,
            &self.all,
        ));
        s
    }
}
