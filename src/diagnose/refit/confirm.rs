//! The FE confirmation of a refit: the recorded designs run with the effect(s) on at their
//! refitted values, the refit redone around the FE where the two differ.

use super::fit::fit_rows;
use super::outcome::{FeRound, Refit, RefitSettings};
use super::problem::Problem;
use super::quality::quality;
use super::rows::Rows;
use crate::calibrate::baseline::{
    run_ramps, RampSource, SweepDesign, SweepRamp, SweepSensitivities, SweepSettings,
};
use crate::calibrate::objective::Output;
use crate::calibrate::ParamSpace;
use crate::case::OgdenSet;
use crate::diagnose::cells::Cell;
use crate::diagnose::DiagnoseError;
use crate::fe::material::{Material, DEFAULT_BULK_RATIO};
use crate::fe::simulate::Mode;
use crate::rom::Surrogate;

/// Settings of [`confirm_with_fe`].
#[derive(Clone, Debug)]
pub struct FeConfirmSettings {
    /// The FE settings (mesh, contact, solver); the material is the refitted one each round,
    /// the geometry and the effects those of the sensitivities' sweep with the refitted
    /// effects set.
    pub sweep: SweepSettings,
    /// Where the ramps are cached (round 1; round k > 1 in `round_k/` inside it): an
    /// interrupted confirmation resumes.
    pub cache: std::path::PathBuf,
    /// At most this many FE rounds.
    pub rounds: usize,
    /// The FE confirms the refit when the root mean square of (FE − linearised)/σ over the
    /// used cells is below this.
    pub tolerance: f64,
}

impl FeConfirmSettings {
    /// `sweep` cached in `cache`, at most 3 rounds, tolerance 0.5 σ.
    pub fn new(sweep: SweepSettings, cache: &std::path::Path) -> Self {
        Self {
            sweep,
            cache: cache.to_path_buf(),
            rounds: 3,
            tolerance: 0.5,
        }
    }
}

/// The FE value of a cell's output in `ramps`, if its ramp reached its pressure.
fn fe_value(ramps: &[SweepRamp], c: &Cell) -> Option<f64> {
    let mode = if c.output == Output::Force {
        Mode::Force
    } else {
        Mode::Bending
    };
    let r = ramps.iter().find(|r| {
        r.mode == mode
            && r.n_bellows == c.n_bellows as usize
            && r.wall_thickness_mm == c.wall_thickness_mm
    })?;
    let st = r.at(c.pressure_bar)?;
    match c.output {
        Output::TipUz => Some(st.tip_uz_mm),
        Output::TipUy => Some(st.tip_uy_mm),
        Output::Angle => Some(st.angle_deg),
        Output::Force => st.force_n,
        Output::MarkerUz(k) => st.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[0]),
        Output::MarkerUy(k) => st.markers.get(usize::from(k).wrapping_sub(1)).map(|m| m[1]),
    }
}

/// What one FE evaluation returns for the used cells: each cell's value (none where its
/// ramp stopped before), the ramps run now, and the ramps that stopped, in words.
pub type FeEvaluation = (Vec<Option<f64>>, usize, Vec<String>);

/// An FE model for the confirmation: `(material, effect values) → FeEvaluation`.
pub type FeModel<'a> = dyn FnMut(&OgdenSet, &[f64]) -> Result<FeEvaluation, DiagnoseError> + 'a;

/// Confirms `refit` with the FE model: the recorded designs, built as in the sweep of `sens`
/// (its geometry and effects), run with the refitted material and the effect(s) set to their
/// refitted values; where FE and the linearised prediction differ by more than
/// `fe.tolerance` (rms over the cells, in σ), the difference becomes the correction `cᵢ` of
/// the prediction and the refit is redone around it, at most `fe.rounds` times. Each round is recorded in [`Refit::fe`]; the refit returned is the last.
/// `progress(done, total)` after every FE ramp.
///
/// # Errors
/// As [`refit`](super::refit()); an FE sweep error (a design out of range, an unwritable cache).
pub fn confirm_with_fe(
    cells: &[Cell],
    sens: &SweepSensitivities,
    model: &Surrogate,
    first: Refit,
    s: &RefitSettings,
    fe: &FeConfirmSettings,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Refit, DiagnoseError> {
    s.validate()?;
    let rows = Rows::of(cells, sens, &s.effects)?;
    let mut designs: Vec<SweepDesign> = Vec::new();
    for c in &rows.cells {
        let n = c.n_bellows as usize;
        match designs
            .iter_mut()
            .find(|d| d.n_bellows == n && d.wall_thickness_mm == c.wall_thickness_mm)
        {
            Some(d) => {
                if !d.pressures_bar.contains(&c.pressure_bar) {
                    d.pressures_bar.push(c.pressure_bar);
                }
            }
            None => designs.push(SweepDesign {
                n_bellows: n,
                wall_thickness_mm: c.wall_thickness_mm,
                pressures_bar: vec![0.0, c.pressure_bar],
            }),
        }
    }
    for d in &mut designs {
        d.pressures_bar.sort_by(f64::total_cmp);
        d.pressures_bar.dedup();
    }
    // round 1 in the cache directory, round k > 1 in `round_k/` beside it: every round's
    // ramps stay (one file per design and rig would otherwise be overwritten by the next
    // round's material), so an interrupted confirmation resumes in the round it reached
    let mut round = 0;
    let mut run_fe = |material: &OgdenSet, values: &[f64]| -> Result<FeEvaluation, DiagnoseError> {
        round += 1;
        let cache = if round == 1 {
            fe.cache.clone()
        } else {
            fe.cache.join(format!("round_{round}"))
        };
        // the sweep's actuator (its geometry and fixed effects), the refitted effects set
        let mut effects = sens.effects.clone();
        for (e, v) in s.effects.iter().zip(values) {
            effects
                .set(*e, *v)
                .map_err(|err| DiagnoseError::input(e.name(), v, &err.to_string()))?;
        }
        let settings = SweepSettings {
            material: Material::from_spec(&material.spec(), DEFAULT_BULK_RATIO).map_err(|e| {
                DiagnoseError::input("refitted material", material.spec(), &e.to_string())
            })?,
            geometry: sens.geometry.clone(),
            effects,
            sensitivities: Vec::new(),
            // recordings without forces need no blocked-force ramps
            force: rows.cells.iter().any(|c| c.output == Output::Force),
            ..fe.sweep.clone()
        };
        let ramps = run_ramps(&settings, &designs, Some(&cache), progress)
            .map_err(crate::calibrate::CalibrateError::from)?;
        let run = ramps.iter().filter(|r| r.source == RampSource::Run).count();
        let failed: Vec<String> = ramps
            .iter()
            .filter(|r| !r.error.is_empty())
            .map(|r| {
                format!(
                    "N = {}, T = {} mm, {:?}: {}",
                    r.n_bellows, r.wall_thickness_mm, r.mode, r.error
                )
            })
            .collect();
        Ok((
            rows.cells.iter().map(|c| fe_value(&ramps, c)).collect(),
            run,
            failed,
        ))
    };
    let mut out = confirm_with(&rows, model, first, s, fe.rounds, fe.tolerance, &mut run_fe)?;
    out.verdict = out.verdict.replace(
        " FE (",
        &format!(" FE ({} mesh, ", fe.sweep.mesh.level.name()),
    );
    Ok(out)
}

/// The rounds of [`confirm_with_fe`] with any FE model: `fe(material, effect values)` gives
/// the used cells' values.
///
/// # Errors
/// As [`refit`](super::refit()), and whatever `fe` returns.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub fn confirm_with(
    rows: &Rows,
    model: &Surrogate,
    first: Refit,
    s: &RefitSettings,
    max_rounds: usize,
    tolerance: f64,
    fe: &mut FeModel<'_>,
) -> Result<Refit, DiagnoseError> {
    let mut rows = rows.clone();
    let space = ParamSpace::training_domain(model)?;
    let mut current = first;
    let mut rounds: Vec<FeRound> = Vec::new();
    loop {
        let material = current.after.material;
        let (values, ramps_run, failed) = fe(&material, &current.after.effects)?;
        let mut x: Vec<f64> = space.unit(&material).to_vec();
        x.extend(
            s.effects
                .iter()
                .zip(&current.after.effects)
                .zip(&rows.base)
                .map(|((_, v), base)| v - base),
        );
        let pb = Problem::new(&rows, model, space.clone(), &s.effects, s.effects.len());
        let lin = pb.predictions(&x)?;
        let mut fe_pred = lin.clone();
        let mut diffs = vec![0.0; rows.cells.len()];
        let mut worst = (0.0, String::new());
        for (i, c) in rows.cells.iter().enumerate() {
            if let Some(v) = values[i] {
                fe_pred[i] = v;
                diffs[i] = v - lin[i];
                let z = diffs[i].abs() / c.sigma;
                if z > worst.0 {
                    worst = (
                        z,
                        format!(
                            "{} at N = {}, T = {} mm, {} bar",
                            c.output.name(),
                            c.n_bellows,
                            c.wall_thickness_mm,
                            c.pressure_bar
                        ),
                    );
                }
            }
        }
        let rms = (diffs
            .iter()
            .zip(&rows.cells)
            .map(|(d, c)| (d / c.sigma).powi(2))
            .sum::<f64>()
            / rows.cells.len() as f64)
            .sqrt();
        rounds.push(FeRound {
            material,
            effects: current.after.effects.clone(),
            quality: quality(&rows.cells, &fe_pred),
            rms_fe_minus_linear: rms,
            worst,
            ramps_run,
            failed,
            z: rows
                .cells
                .iter()
                .zip(&fe_pred)
                .map(|(c, p)| (p - c.recorded) / c.sigma)
                .collect(),
        });
        if rms <= tolerance || rounds.len() >= max_rounds.max(1) {
            break;
        }
        for (o, d) in rows.offset.iter_mut().zip(&diffs) {
            *o += d;
        }
        let linearised_at = current.linearised_at.clone();
        let base = linearised_at
            .split(", corrected by the FE")
            .next()
            .unwrap_or_default()
            .to_string();
        current = fit_rows(&rows, model, &material, s)?;
        current.linearised_at = format!("{base}, corrected by the FE of round {}", rounds.len());
    }
    let last = rounds.last().expect("at least one round");
    let confirmed = last.rms_fe_minus_linear <= tolerance;
    current.verdict.push_str(&format!(
        " FE ({} round(s)): {}; with the effect on at {} the FE misses the recordings by a \
         mean tip BE of {} (FE − linearised: rms {:.2} σ, worst {:.2} σ at {}).",
        rounds.len(),
        if confirmed {
            "confirmed"
        } else {
            "NOT confirmed within the tolerance"
        },
        last.effects
            .iter()
            .zip(&s.effects)
            .map(|(v, e)| format!("{} = {v:.4}", e.name()))
            .collect::<Vec<_>>()
            .join(", "),
        last.quality
            .mean_be_mm
            .map_or("—".to_string(), |b| format!("{b:.2} mm")),
        last.rms_fe_minus_linear,
        last.worst.0,
        last.worst.1
    ));
    current.fe = rounds;
    Ok(current)
}
