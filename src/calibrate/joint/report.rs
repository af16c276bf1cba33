//! The identification's report: the estimates, every sweep, the configurations at the
//! optimum, the held-out prediction; in words (Markdown) and on disk.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::correction::MeshCorrection;
use super::settings::{JointStop, ModelSigma};
use super::unknown::JointPoint;
use crate::calibrate::objective::Exclusion;
use crate::fe::effects::Effect;

/// One FE sweep of the identification.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointSweep {
    /// The point.
    pub point: JointPoint,
    /// `χ²` there (`inf` when the FE failed).
    pub chi2: f64,
    /// Mean tip bending error over the recorded configurations (mm).
    pub mean_be_mm: f64,
    /// Mean |F_FE − F| (N).
    pub mean_abs_force_error_n: f64,
    /// Whether the step to it was taken.
    pub accepted: bool,
    /// The damping `λ` of the step that led here (0 for the start).
    pub lambda: f64,
    /// `χ²` predicted by the linearisation for this step.
    pub predicted_chi2: f64,
    /// The FE's message where a ramp failed.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub error: String,
}

/// One recorded configuration at the optimum.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointRow {
    /// N.
    pub n_bellows: usize,
    /// T (mm).
    pub wall_thickness_mm: f64,
    /// P (bar).
    pub pressure_bar: f64,
    /// One of the reference study's nine (T and P together: 1.6/1, 2.0/2, 2.4/3).
    pub paper_nine: bool,
    /// Recorded, FE tip Uz (mm).
    pub uz_mm: [f64; 2],
    /// Recorded, FE tip Uy (mm).
    pub uy_mm: [f64; 2],
    /// Recorded, FE angle (deg).
    pub angle_deg: [f64; 2],
    /// Recorded, FE blocked force (N).
    pub force_n: [f64; 2],
    /// Tip bending error (mm).
    pub be_mm: f64,
    /// The tip was left out of the fit ([`super::JointSettings::exclude`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub tip_excluded: bool,
    /// The force was left out of the fit.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub force_excluded: bool,
}

/// An unknown at the optimum.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointEstimate {
    /// Its name.
    pub name: String,
    /// Start value.
    pub start: f64,
    /// Value at the optimum.
    pub value: f64,
    /// Standard error from `(JᵀJ)⁻¹` (NaN where `JᵀJ` is singular).
    pub std_error: f64,
    /// Bounds.
    pub bounds: (f64, f64),
    /// Whether it sits on a bound (within 1e-6 of the range).
    pub on_bound: bool,
}

/// The identification's report.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JointReport {
    /// The FE mesh level.
    pub mesh: String,
    /// The model-form floor of the noise model.
    #[serde(default)]
    pub model_sigma: ModelSigma,
    /// The unknowns at the optimum.
    pub estimates: Vec<JointEstimate>,
    /// Correlations of the unknowns (row-major, in the order of `estimates`).
    pub correlations: Vec<Vec<f64>>,
    /// The optimum.
    pub optimum: JointPoint,
    /// Every sweep, in order.
    pub sweeps: Vec<JointSweep>,
    /// How it stopped.
    pub stop: JointStop,
    /// Each recorded configuration at the optimum.
    pub rows: Vec<JointRow>,
    /// Mean BE over all configurations (mm).
    pub mean_be_mm: f64,
    /// Mean BE over the reference study's nine (mm).
    pub mean_be_paper_nine_mm: f64,
    /// RMS angle error (deg).
    pub rms_angle_error_deg: f64,
    /// Mean |force error| (N).
    pub mean_abs_force_error_n: f64,
    /// Mean force error, FE − recorded (N).
    pub mean_force_error_n: f64,
    /// Designs held out: every way of leaving 3 of the designs out, linearised around the FE
    /// optimum ([`HeldOut`]).
    pub held_out: HeldOut,
    /// The rows left out of the fit, and why. The means above are over the rows fitted.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub excluded: Vec<Exclusion>,
    /// Mean tip BE over every recorded configuration, the excluded ones included (mm); `None`
    /// when nothing was excluded (then it is `mean_be_mm`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_be_all_mm: Option<f64>,
    /// The same over the reference study's nine (mm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_be_paper_nine_all_mm: Option<f64>,
    /// The mesh correction the FE values carry ([`super::JointSettings::correction`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correction: Option<MeshCorrection>,
}

/// Prediction of designs the fit did not see, linearised around the FE optimum: for every
/// way of holding out `k` of the recorded designs, the unknowns are refitted (bounded
/// Levenberg–Marquardt on `r + J·(θ − θ*)`) on the other designs' residuals and the held-out
/// designs' tips predicted with the refit (`y + σ·(r + J·δ)`). A linear refit from the
/// optimum of all designs: it says how much the optimum leans on each design, not how a
/// full FE refit from the start would end.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct HeldOut {
    /// Designs held out per split.
    pub k: usize,
    /// Splits (every combination).
    pub splits: usize,
    /// Mean over the splits of the held-out configurations' mean tip BE (mm).
    pub mean_be_mm: f64,
    /// The worst split's mean held-out BE (mm) and its designs `(N, T)`.
    pub worst_be_mm: f64,
    /// The worst split's designs.
    pub worst: Vec<(usize, f64)>,
    /// Mean held-out |force error| (N).
    pub mean_abs_force_error_n: f64,
    /// The same tip BE at the optimum of all designs (no refit), for comparison (mm).
    pub in_sample_be_mm: f64,
}

impl JointReport {
    /// The report in words (Markdown).
    pub fn summary(&self) -> String {
        let mut s = String::new();
        s.push_str(&format!(
            "# Joint identification of the material and the unstated dimensions\n\n\
             FE-direct Levenberg–Marquardt on the {} mesh: {} sweeps, stopped: {:?}. \
             Model-form floor of the noise model: {} mm on a tip coordinate, {} N on the \
             force.\n\n\
             | | value |\n|---|---|\n\
             | mean tip BE, all {} configurations fitted | {:.2} mm |\n\
             | mean tip BE, the reference study's nine | {:.2} mm |\n\
             | rms angle error | {:.2}° |\n\
             | mean abs. blocked-force error | {:.3} N |\n\
             | mean blocked-force error (FE − recorded) | {:+.3} N |\n\n",
            self.mesh,
            self.sweeps.len(),
            self.stop,
            self.model_sigma.tip_mm,
            self.model_sigma.force_n,
            self.rows.iter().filter(|r| !r.tip_excluded).count(),
            self.mean_be_mm,
            self.mean_be_paper_nine_mm,
            self.rms_angle_error_deg,
            self.mean_abs_force_error_n,
            self.mean_force_error_n
        ));
        s.push_str(&self.correction_and_exclusions());
        let h = &self.held_out;
        s.push_str(&format!(
            "Designs held out ({} of the designs at a time, all {} ways; linearised refit \
             around the FE optimum): mean held-out tip BE {:.2} mm (the same configurations \
             at the optimum of all designs: {:.2} mm), worst split {:.2} mm ({}), mean \
             held-out |force error| {:.3} N.\n\n",
            h.k,
            h.splits,
            h.mean_be_mm,
            h.in_sample_be_mm,
            h.worst_be_mm,
            h.worst
                .iter()
                .map(|(n, t)| format!("N = {n}, T = {t}"))
                .collect::<Vec<_>>()
                .join("; "),
            h.mean_abs_force_error_n
        ));
        s.push_str("| unknown | start | value | std. error | bounds | on a bound |\n|---|---|---|---|---|---|\n");
        for e in &self.estimates {
            s.push_str(&format!(
                "| {} | {:.6} | {:.6} | {:.3e} | [{}, {}] | {} |\n",
                e.name,
                e.start,
                e.value,
                e.std_error,
                e.bounds.0,
                e.bounds.1,
                if e.on_bound {
                    "**yes**: the range truncates the optimum"
                } else {
                    "no"
                }
            ));
        }
        s.push_str("\n## Sweeps\n\n| # | χ² | predicted χ² | λ | mean BE (mm) | mean abs. F error (N) | taken |\n|---|---|---|---|---|---|---|\n");
        for (i, w) in self.sweeps.iter().enumerate() {
            s.push_str(&format!(
                "| {} | {:.1} | {:.1} | {:.2e} | {:.2} | {:.3} | {} |\n",
                i + 1,
                w.chi2,
                w.predicted_chi2,
                w.lambda,
                w.mean_be_mm,
                w.mean_abs_force_error_n,
                if w.accepted { "yes" } else { "no" }
            ));
        }
        s.push_str("\n## Configurations at the optimum\n\n| N | T | P | nine | Uz rec/FE | Uy rec/FE | angle rec/FE | F rec/FE | BE |\n|---|---|---|---|---|---|---|---|---|\n");
        for r in &self.rows {
            let mark = |excluded: bool| if excluded { " (left out)" } else { "" };
            s.push_str(&format!(
                "| {} | {} | {} | {} | {:.1} / {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.3} / {:.3}{} | {:.2}{} |\n",
                r.n_bellows,
                r.wall_thickness_mm,
                r.pressure_bar,
                if r.paper_nine { "yes" } else { "" },
                r.uz_mm[0],
                r.uz_mm[1],
                r.uy_mm[0],
                r.uy_mm[1],
                r.angle_deg[0],
                r.angle_deg[1],
                r.force_n[0],
                r.force_n[1],
                mark(r.force_excluded),
                r.be_mm,
                mark(r.tip_excluded),
            ));
        }
        s
    }

    /// The paragraphs on the mesh correction and on the rows left out, if any.
    fn correction_and_exclusions(&self) -> String {
        let mut s = String::new();
        if let Some(c) = &self.correction {
            s.push_str(&format!(
                "**Mesh-corrected**: every FE value in this report is the {} mesh's plus the \
                 difference between two meshes at a reference point ({} − {}: on average {:.2} mm \
                 on the tip, {:.3} N on the force). The numbers estimate the finer mesh; \
                 verify them on it.\n\n",
                self.mesh,
                c.fine,
                c.coarse,
                c.mean_tip_mm(),
                c.mean_abs_force_n()
            ));
        }
        if !self.excluded.is_empty() {
            s.push_str(&format!(
                "Left out of the fit ({} rows; the means above are over the rows fitted; \
                 their FE values are in the table below, marked): mean tip BE with them, all \
                 configurations {:.2} mm, the reference study's nine {:.2} mm.\n\n",
                self.excluded.len(),
                self.mean_be_all_mm.unwrap_or(f64::NAN),
                self.mean_be_paper_nine_all_mm.unwrap_or(f64::NAN),
            ));
            for e in &self.excluded {
                let what = match e.recording {
                    crate::calibrate::objective::Recording::Bending => "bending",
                    crate::calibrate::objective::Recording::Force => "force",
                    crate::calibrate::objective::Recording::Both => "bending and force",
                };
                s.push_str(&format!("- {} ({what}): {}\n", e.config.label(), e.reason));
            }
            s.push('\n');
        }
        s
    }

    /// Writes `report.json` and `summary.md` into `dir`, atomically.
    ///
    /// # Errors
    /// An unwritable directory.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        let json = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::io::write_atomic(&dir.join("report.json"), json.as_bytes())?;
        let text = format!(
            "{}\n## Verify on the standard mesh\n\n```sh\n{}\n```\n",
            self.summary(),
            self.verification_command(dir)
        );
        crate::io::write_atomic(&dir.join("summary.md"), text.as_bytes())
    }

    /// The command that runs the FE at the optimum on the standard mesh over every recorded
    /// design, in both rigs (`surrogate validate`), with the identified geometry written by
    /// `surrogate identify` into `dir/geometry.json`.
    pub fn verification_command(&self, dir: &Path) -> String {
        let [m1, a1, m2, a2] = self.optimum.ogden.as_array();
        let mut c = format!(
            "cargo run --release -- validate --mesh standard --geometry {}/geometry.json \\\n    \
             --material={m1},{a1},{m2},{a2}",
            dir.display()
        );
        let mut effects: Vec<(Effect, f64)> = self.optimum.effects.iter().collect();
        effects.sort_by_key(|(e, _)| e.name());
        for (e, v) in effects {
            c.push_str(&format!(" --effect={}={v}", e.name()));
        }
        c.push_str(&format!(" \\\n    --out {}/standard.csv", dir.display()));
        c
    }
}
