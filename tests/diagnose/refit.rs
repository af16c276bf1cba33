//! The diagnoser's Model-and-show stage (`surrogate::diagnose::refit`) on recordings made by
//! the shipped surrogate at a known material plus a known, exactly linear effect (the
//! committed FE sensitivities of `pressure_loss` times its size), with noise at the
//! experiments' standard deviations: the refit must find the size, the fit and the
//! held-out designs must improve; without the effect, the size must come out as nothing.

use std::path::Path;

use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::synthetic::{noisy_recordings, TrueOutputs};
use surrogate::calibrate::{OgdenSet, Recordings};
use surrogate::case::Query;
use surrogate::diagnose::refit::{refit, RefitSettings};
use surrogate::diagnose::{diagnose, DiagnoseSettings};
use surrogate::fe::effects::Effect;
use surrogate::fe::sensitivity::Parameter;
use surrogate::fe::simulate::Mode;
use surrogate::rom::Surrogate;

const SWEEP: &str = surrogate::diagnose::setup::AS_MODELLED_SENSITIVITIES;

/// The surrogate's outputs at Ogden 002 plus `size` × the sweep's derivatives of `effect`.
fn truth(
    model: &Surrogate,
    sens: &SweepSensitivities,
    effect: Effect,
    size: f64,
) -> Vec<TrueOutputs> {
    let mut pred = model.new_prediction();
    let m = OgdenSet::literature("ogden_002").unwrap();
    let d = |n: usize, t: f64, p: f64, mode: Mode| {
        let s = sens.design(n, t, mode).unwrap();
        let j = s
            .parameters
            .iter()
            .position(|i| i.parameter == Parameter::Effect(effect))
            .unwrap();
        let st = s.steps.iter().find(|st| st.pressure_bar == p).unwrap();
        st.derivatives[j].clone()
    };
    Recordings::shipped()
        .unwrap()
        .bending
        .iter()
        .map(|r| {
            let (n, t, p) = (r.n_bellows, r.wall_thickness_mm, r.pressure_bar);
            model
                .predict_into(&Query::new(n as u32, t, p, m), &mut pred)
                .unwrap();
            let b = d(n, t, p, Mode::Bending);
            let f = d(n, t, p, Mode::Force);
            TrueOutputs {
                n_bellows: n,
                wall_thickness_mm: t,
                pressure_bar: p,
                tip_uz_mm: pred.tip_uz_mm() + size * b.tip_uz_mm,
                tip_uy_mm: pred.tip_uy_mm() + size * b.tip_uy_mm,
                angle_deg: pred.angle_deg() + size * b.angle_deg,
                force_n: pred.force_n() + size * f.force_n.unwrap(),
            }
        })
        .collect()
}

fn settings() -> DiagnoseSettings {
    super::quick_diagnose_settings()
}

#[test]
fn a_linear_effect_is_refitted_with_its_size_and_helps_held_out_designs() {
    let model = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    let sens = SweepSensitivities::read(Path::new(SWEEP)).unwrap();
    let shipped = Recordings::shipped().unwrap();
    let rec = noisy_recordings(
        &truth(&model, &sens, Effect::PressureLoss, 0.12),
        &shipped,
        3,
        "planted pressure loss",
    )
    .unwrap();
    let d = diagnose(&model, &rec, &settings(), &|_| {}).unwrap();
    let s = RefitSettings::new(vec![Effect::PressureLoss]);
    let r = refit(&d.locate.cells, &sens, &model, &d.calibration.best, &s).unwrap();
    let e = &r.effects[0];
    assert_eq!(e.effect, "pressure_loss");
    assert!(
        (e.value - 0.12).abs() < 3.0 * e.std_error && e.std_error < 0.03,
        "{e:?}"
    );
    assert!(e.interval.0 < e.value && e.value < e.interval.1);
    assert!(r.p_value < 1e-6, "{}", r.verdict);
    assert!(
        r.after.quality.chi2 < 0.5 * r.before.quality.chi2,
        "{}",
        r.verdict
    );
    // every recorded number once: tip Uz, Uy, angle and force at 27 configurations
    assert_eq!(r.n_cells, 27 * 4);
    let h = r.held_out.as_ref().unwrap();
    assert_eq!(h.designs.len(), 9);
    assert!(h.chi2_after < h.chi2_before, "{}", r.verdict);
    assert!(
        h.mean_be_after_mm.unwrap() < h.mean_be_before_mm.unwrap(),
        "{}",
        r.verdict
    );
    assert!(
        r.verdict.starts_with("Refitted with pressure_loss = "),
        "{}",
        r.verdict
    );
}

#[test]
fn without_the_effect_its_refitted_size_is_nothing() {
    let model = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    let sens = SweepSensitivities::read(Path::new(SWEEP)).unwrap();
    let shipped = Recordings::shipped().unwrap();
    let rec = noisy_recordings(
        &truth(&model, &sens, Effect::PressureLoss, 0.0),
        &shipped,
        4,
        "null",
    )
    .unwrap();
    let d = diagnose(&model, &rec, &settings(), &|_| {}).unwrap();
    let mut s = RefitSettings::new(vec![Effect::PressureLoss]);
    s.held_out = false;
    let r = refit(&d.locate.cells, &sens, &model, &d.calibration.best, &s).unwrap();
    let e = &r.effects[0];
    // the library's range starts at 0: the estimate may sit on that bound, and says so
    assert!(e.value < 3.0 * e.std_error.max(1e-3), "{e:?}");
    assert!(r.p_value > 1e-3, "{}", r.verdict);
    assert!(r.held_out.is_none());
    // bad settings are named
    let bad = RefitSettings::new(vec![Effect::GapBias, Effect::GapBias]);
    let err = refit(&d.locate.cells, &sens, &model, &d.calibration.best, &bad)
        .unwrap_err()
        .to_string();
    assert_eq!(
        err,
        "refit effects = gap_bias: expected each effect at most once"
    );
}
