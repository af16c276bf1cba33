//! The unit tests of `src/diagnose/refit/confirm.rs`.

use super::cells::UnitCell;
use super::fixtures::DESIGNS;
use std::path::Path;
use surrogate::calibrate::objective::Output;
use surrogate::case::OgdenSet;
use surrogate::case::Query;
use surrogate::diagnose::cells::Cell;
use surrogate::diagnose::refit::{confirm_with, fit_rows, FeEvaluation, RefitSettings, Rows};
use surrogate::diagnose::DiagnoseError;
use surrogate::fe::effects::Effect;
use surrogate::rom::Surrogate;

pub(super) fn value(model: &Surrogate, m: &OgdenSet, n: u32, t: f64, p: f64, o: Output) -> f64 {
    let mut pred = model.new_prediction();
    model
        .predict_scalars_into(&Query::new(n, t, p, *m), &mut pred)
        .unwrap();
    match o {
        Output::TipUz => pred.tip_uz_mm(),
        Output::TipUy => pred.tip_uy_mm(),
        _ => pred.angle_deg(),
    }
}

/// The effect's "true" response: `g(θ) = θ + 2θ²` times a fixed pattern over the cells.
pub(super) fn g(theta: f64) -> f64 {
    theta + 2.0 * theta * theta
}

/// The coarse shipped model and the literature set the recordings are made at.
pub(super) fn coarse_model_and_material() -> (Surrogate, OgdenSet) {
    let model = Surrogate::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/as_modelled/actuator_coarse.json"),
    )
    .unwrap();
    (model, OgdenSet::literature("ogden_002").unwrap())
}

/// The effect's fixed pattern over the cells, scaled by `w`: tip Uz `w₀ p (2.7 − t)`,
/// tip Uy `w₁ p`, angle `w₂ p N / 11`.
pub(super) fn pattern(w: [f64; 3], n: u32, t: f64, p: f64, o: Output) -> f64 {
    match o {
        Output::TipUz => w[0] * p * (2.7 - t),
        Output::TipUy => w[1] * p,
        _ => w[2] * p * f64::from(n) / 11.0,
    }
}

/// Rows of recordings `model` makes at `m` with an effect of response `size` (from the
/// sweep's value `base`) along the pattern `w` over the cells.
pub(super) fn planted(model: &Surrogate, m: &OgdenSet, base: f64, w: [f64; 3], size: f64) -> Rows {
    let mut rows = Rows {
        base: vec![base],
        cells: Vec::new(),
        d: Vec::new(),
        offset: Vec::new(),
    };
    for (n, t) in DESIGNS {
        for p in [1.0, 2.0, 3.0] {
            for o in [Output::TipUz, Output::TipUy, Output::Angle] {
                let d = pattern(w, n, t, p, o);
                let mut c = Cell::unit(n, t, p, o, 0.0);
                c.recorded = value(model, m, n, t, p, o) + size * d;
                rows.cells.push(c);
                rows.d.push(vec![d]);
                rows.offset.push(0.0);
            }
        }
    }
    rows
}

/// The stand-in FE on the cells of `rows`: `model` at `mat` plus the effect's response
/// `size` along the rows' pattern.
pub(super) fn stand_in_fe(
    rows: &Rows,
    model: &Surrogate,
    mat: &OgdenSet,
    size: f64,
) -> Vec<Option<f64>> {
    rows.cells
        .iter()
        .zip(&rows.d)
        .map(|(c, d)| {
            let at = (c.n_bellows, c.wall_thickness_mm, c.pressure_bar);
            Some(value(model, mat, at.0, at.1, at.2, c.output) + size * d[0])
        })
        .collect()
}

#[test]
fn sizes_are_measured_from_the_sweeps_value_and_kept_in_range_from_it() {
    let (model, m) = coarse_model_and_material();
    let w = [2.0, -0.8, 0.4];
    // a sweep with the plate 4.5 mm closer (the force rig's), the actuator's 0.3 mm further
    let rows = planted(&model, &m, -4.5, w, 0.3);
    let s = RefitSettings::new(vec![Effect::PlateOffset]);
    let first = fit_rows(&rows, &model, &m, &s).unwrap();
    let e = &first.effects[0];
    assert!((e.estimate - 0.3).abs() < 1e-3, "{e:?}");
    assert_eq!(e.value, -4.5 + e.estimate);
    assert!(e.interval.0 <= e.value && e.value <= e.interval.1, "{e:?}");
    assert!(e.at_bound.is_none(), "{e:?}");
    assert_eq!(first.after.effects, vec![e.value]);
    let held = first.held_out.as_ref().unwrap();
    assert!(held
        .designs
        .iter()
        .all(|d| (d.effects[0] + 4.2).abs() < 1e-2));
    // the FE of the sweep's actuator with the effect at its refitted value agrees
    let mut fe = |mat: &OgdenSet, v: &[f64]| -> Result<FeEvaluation, DiagnoseError> {
        Ok((stand_in_fe(&rows, &model, mat, v[0] + 4.5), 0, Vec::new()))
    };
    let r = confirm_with(&rows, &model, first.clone(), &s, 3, 0.01, &mut fe).unwrap();
    assert_eq!(r.fe.len(), 1);
    assert!(r.fe[0].rms_fe_minus_linear < 1e-6, "{:?}", r.fe[0]);
    // 0.3 mm closer than the sweep's plate is beyond the range's −4.5: the fit stops there
    let rows = planted(&model, &m, -4.5, w, -0.3);
    let mut s = s;
    s.held_out = false;
    let e = fit_rows(&rows, &model, &m, &s).unwrap().effects[0].clone();
    assert_eq!((e.value, e.estimate), (-4.5, 0.0), "{e:?}");
    assert!(e.at_bound.is_some(), "{e:?}");
}

#[test]
fn fe_rounds_correct_a_nonlinear_effect_that_the_linearisation_misjudges() {
    let (model, m) = coarse_model_and_material();
    let truth = 0.1;
    let rows = planted(&model, &m, 0.0, [8.0, -3.0, 1.5], g(truth));
    let mut s = RefitSettings::new(vec![Effect::PressureLoss]);
    s.held_out = false;
    let first = fit_rows(&rows, &model, &m, &s).unwrap();
    // the linearisation (slope 1 at 0) reads g(0.1) = 0.12 as the size
    let linear = first.effects[0].value;
    assert!((linear - g(truth)).abs() < 2e-3, "{}", first.verdict);
    let mut calls = 0;
    let mut fe = |mat: &OgdenSet, v: &[f64]| -> Result<FeEvaluation, DiagnoseError> {
        calls += 1;
        Ok((stand_in_fe(&rows, &model, mat, g(v[0])), 2, Vec::new()))
    };
    let r = confirm_with(&rows, &model, first, &s, 8, 0.01, &mut fe).unwrap();
    let last = r.fe.last().unwrap();
    assert!(r.fe.len() >= 3 && r.fe.len() <= 8, "{} rounds", r.fe.len());
    assert_eq!(calls, r.fe.len());
    // the first round sees the linearisation's error; the last one agrees with the FE
    assert!(r.fe[0].rms_fe_minus_linear > 0.05, "{:?}", r.fe[0]);
    assert!(last.rms_fe_minus_linear <= 0.01, "{last:?}");
    assert!((last.effects[0] - truth).abs() < 2e-3, "{:?}", last.effects);
    assert!(r.verdict.contains("round(s)): confirmed;"), "{}", r.verdict);
    assert!(r.linearised_at.contains("corrected by the FE of round"));
}
