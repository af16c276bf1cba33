//! The unit tests of `src/diagnose/name/mod.rs`.
//!
//! The Name stage on sweeps with random signatures and recordings made by their linear model.

use super::cells::UnitCell;
use super::fixtures::{bending_sweep, every_parameter, random_outputs, DESIGNS};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::diagnose::cells::Cell;
use surrogate::diagnose::name::derivs_of;
use surrogate::fe::sensitivity::{OgdenParameter, Parameter};

use surrogate::calibrate::objective::Output;
use surrogate::diagnose::approx_error::ErrorSpread;
use surrogate::diagnose::mesh_error::ErrorDirection;
use surrogate::diagnose::name::*;
use surrogate::diagnose::signature::derivative_of;
use surrogate::fe::effects::{Acts, Effect, Effects};
use surrogate::fe::sensitivity::{Outputs, StepSensitivities};

/// A bending sweep with random signatures for every parameter.
fn sweep(seed: u64) -> SweepSensitivities {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let parameters = every_parameter();
    let designs = DESIGNS
        .iter()
        .map(|&(n, t)| {
            let steps = [0.0, 1.0, 2.0, 3.0]
                .iter()
                .map(|&p| StepSensitivities {
                    pressure_bar: p,
                    values: random_outputs(&mut rng),
                    // the force rig's own effects move nothing in bending
                    derivatives: parameters
                        .iter()
                        .map(|i| {
                            let mut o = random_outputs(&mut rng);
                            if matches!(
                                i.parameter,
                                Parameter::Effect(e) if e.acts_on() == Acts::Force
                            ) {
                                o = Outputs {
                                    tip_uz_mm: 0.0,
                                    tip_uy_mm: 0.0,
                                    angle_deg: 0.0,
                                    markers: vec![[0.0; 2]; 9],
                                    force_n: None,
                                };
                            }
                            o
                        })
                        .collect(),
                })
                .collect();
            (n as usize, t, steps)
        })
        .collect();
    bending_sweep(&parameters, designs)
}

/// Cells (tip Uz, tip Uy, angle at 1, 2, 3 bar, σ = 1) of recordings made by the sweep's
/// linear model with the material off by `material` and `planted` effects, plus noise.
fn cells(sens: &SweepSensitivities, planted: &[(Effect, f64)], seed: u64) -> Vec<Cell> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let params = &sens.designs[0].sensitivities.parameters;
    let at = |p: Parameter| params.iter().position(|i| i.parameter == p).unwrap();
    let material = [0.3, -0.2, 0.1, 0.25];
    let mut out = Vec::new();
    for d in &sens.designs {
        for st in &d.sensitivities.steps[1..] {
            for output in [Output::TipUz, Output::TipUy, Output::Angle] {
                let mut delta = 0.0;
                for (k, m) in OgdenParameter::ALL.iter().zip(material) {
                    delta +=
                        m * derivative_of(&st.derivatives[at(Parameter::Material(*k))], output)
                            .unwrap();
                }
                for &(e, v) in planted {
                    delta += v * derivative_of(&st.derivatives[at(Parameter::Effect(e))], output)
                        .unwrap();
                }
                // the actuator has the offsets the model lacks: z = (model − actuator)/σ
                let z = -delta + 0.05 * rng.gen_range(-1.0..1.0);
                out.push(Cell::unit(
                    d.n_bellows as u32,
                    d.wall_thickness_mm,
                    st.pressure_bar,
                    output,
                    z,
                ));
            }
        }
    }
    out
}

#[test]
fn a_planted_effect_is_named_with_its_size() {
    let sens = sweep(1);
    let n = name(
        &cells(&sens, &[(Effect::WallBias, 0.12)], 2),
        &sens,
        &NameSettings::default(),
    )
    .unwrap();
    let top = &n.candidates[0];
    assert_eq!(top.effect, "wall_bias", "{:#?}", n.candidates[..3].to_vec());
    assert!(top.significant && top.plausible);
    assert!(
        (top.estimate - 0.12).abs() < 3.0 * top.std_error && top.std_error < 0.02,
        "{} ± {}",
        top.estimate,
        top.std_error
    );
    assert!(n.verdict.starts_with("wall_bias explains"), "{}", n.verdict);
    // the material's offsets were projected out, not blamed on an effect
    assert!(n.candidates[1..].iter().all(|c| !c.significant));
    // force-rig effects move nothing a bending recording holds
    assert!(n.untestable.iter().any(|u| u.effect == "plate_offset"));
}

/// A sweep with `plate_offset` fixed at `base` (a model trained with the force rig's plate),
/// the effect given a signature in bending so that these cells can test it.
fn sweep_with_plate(seed: u64, base: f64) -> SweepSensitivities {
    let mut sens = sweep(seed);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed + 100);
    let plate = Parameter::Effect(Effect::PlateOffset);
    let j = sens.designs[0]
        .sensitivities
        .parameters
        .iter()
        .position(|i| i.parameter == plate)
        .unwrap();
    for d in &mut sens.designs {
        for st in &mut d.sensitivities.steps {
            st.derivatives[j] = random_outputs(&mut rng);
        }
    }
    sens.effects = Effects::neutral().with(Effect::PlateOffset, base).unwrap();
    sens
}

/// The `plate_offset` candidate of the Name stage on `sens` with the plate planted `theta`
/// from the sweep's.
fn plate_candidate(sens: &SweepSensitivities, theta: f64) -> (Candidate, Naming) {
    let planted = [(Effect::PlateOffset, theta)];
    let n = name(&cells(sens, &planted, 2), sens, &NameSettings::default()).unwrap();
    let c = n.candidates.iter().find(|c| c.effect == "plate_offset");
    (c.unwrap().clone(), n)
}

#[test]
fn a_size_is_measured_from_the_sweeps_value_of_the_effect() {
    let sens = sweep_with_plate(1, -4.5);
    // 0.3 mm further than the sweep's plate: −4.2 mm, inside the range
    let (c, n) = plate_candidate(&sens, 0.3);
    assert_eq!(c.base, Some(-4.5));
    assert!((c.estimate - 0.3).abs() < 3.0 * c.std_error, "{c:#?}");
    assert_eq!(c.size(), -4.5 + c.estimate);
    assert!(c.significant && c.plausible, "{c:#?}");
    assert!(
        n.verdict.starts_with(&format!(
            "plate_offset explains {:.0} % of the residual left after the material re-fit \
             (size {:.3} (-4.5 {:+.3}) ±",
            100.0 * c.explained,
            c.size(),
            c.estimate
        )),
        "{}",
        n.verdict
    );
    // 0.3 mm closer: −4.8 mm, beyond the range's −4.5, so not named
    let (c, n) = plate_candidate(&sens, -0.3);
    assert!(c.significant && !c.plausible && c.size() < -4.5, "{c:#?}");
    assert!(n.named().is_none_or(|c| c.effect != "plate_offset"));
    // the same estimate from the neutral plate is a plausible −0.3 mm
    let neutral = sweep_with_plate(1, 0.0);
    let (c, _) = plate_candidate(&neutral, -0.3);
    assert_eq!(c.base, None);
    assert_eq!(c.size(), c.estimate);
    assert!(c.significant && c.plausible, "{c:#?}");
}

#[test]
fn a_second_effect_is_reported_beside_the_named_one() {
    let sens = sweep(1);
    let planted = [(Effect::WallBias, 0.12), (Effect::Density, 0.25)];
    let n = name(&cells(&sens, &planted, 2), &sens, &NameSettings::default()).unwrap();
    let (first, second) = (&n.candidates[0], &n.candidates[1]);
    let names = [first.effect.as_str(), second.effect.as_str()];
    assert!(
        names.contains(&"wall_bias") && names.contains(&"density"),
        "{:#?}",
        n.candidates[..3].to_vec()
    );
    assert!(second.significant && second.plausible, "{second:#?}");
    assert!(
        n.verdict.starts_with(&format!("{} explains", first.effect))
            && n.verdict.contains(&format!(
                "also significant at a plausible size, explaining less: {} (",
                second.effect
            )),
        "{}",
        n.verdict
    );
}

/// A random model-error direction over `cells` (unit of each output).
fn direction(cells: &[Cell], seed: u64) -> ErrorDirection {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    ErrorDirection {
        name: "model_mesh".into(),
        per_cell: cells
            .iter()
            .map(|_| Some(rng.gen_range(-1.0..1.0)))
            .collect(),
    }
}

#[test]
fn the_models_own_error_is_told_from_physics() {
    let sens = sweep(11);
    let clean = cells(&sens, &[], 12);
    let d = direction(&clean, 13);
    // the model misses the actuator by 0.8 of its mesh error: that, not physics, is said
    let mut off = clean.clone();
    for (i, c) in off.iter_mut().enumerate() {
        c.standardised -= 0.8 * d.at(i);
    }
    let s = NameSettings {
        model_errors: vec![d.clone()],
        ..NameSettings::default()
    };
    let n = name(&off, &sens, &s).unwrap();
    let me = n
        .model_error()
        .expect("the mesh error explains the residual");
    assert_eq!(me.effect, "model_mesh");
    assert!(me.model_error && n.named().is_none(), "{}", n.verdict);
    assert!(
        (me.estimate - 0.8).abs() < 3.0 * me.std_error,
        "{}",
        me.estimate
    );
    assert!(n.verdict.contains("discretisation error"), "{}", n.verdict);
    // a planted effect still wins over the model's error when the error is not there
    let planted = cells(&sens, &[(Effect::WallBias, 0.12)], 12);
    let n = name(&planted, &sens, &s).unwrap();
    assert_eq!(n.named().map(|c| c.effect.as_str()), Some("wall_bias"));
    assert!(n.candidates.iter().any(|c| c.model_error && !c.significant));
    // a direction of another table is refused, naming it
    let short = ErrorDirection {
        per_cell: vec![Some(1.0); 3],
        ..d
    };
    let err = name(
        &off,
        &sens,
        &NameSettings {
            model_errors: vec![short],
            ..NameSettings::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("model_mesh (3 values)"), "{err}");
}

#[test]
fn a_model_error_weighed_by_its_covariance_is_not_named_as_physics() {
    let sens = sweep(21);
    let params = &sens.designs[0].sensitivities.parameters;
    let j = params
        .iter()
        .position(|p| p.parameter == Parameter::Effect(Effect::FreeLengthBias))
        .unwrap();
    // the model's own error lies along free_length_bias's signature (as if the actuator
    // were 1.5 mm longer); the recordings' noise is 1 σ
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(22);
    let base = cells(&sens, &[], 23);
    let e: Vec<f64> = base
        .iter()
        .map(|c| -1.5 * derivs_of(&sens, c).unwrap()[j])
        .collect();
    let noisy: Vec<Cell> = base
        .iter()
        .zip(&e)
        .map(|(c, ei)| {
            let mut c = c.clone();
            c.standardised += ei + 1.7 * rng.gen_range(-1.0..1.0);
            c
        })
        .collect();
    let plain = name(&noisy, &sens, &NameSettings::default()).unwrap();
    assert_eq!(
        plain.named().map(|c| c.effect.as_str()),
        Some("free_length_bias"),
        "{}",
        plain.verdict
    );
    // samples of the model's error at three materials: +e, −e, 0 (covariance e eᵀ)
    let spread = ErrorSpread {
        sources: vec!["a".into(), "b".into(), "c".into()],
        deviations: vec![
            e.iter().map(|v| v / 2f64.sqrt()).collect(),
            e.iter().map(|v| -v / 2f64.sqrt()).collect(),
            vec![0.0; e.len()],
        ],
    };
    let s = NameSettings {
        error_spread: Some(spread.clone()),
        ..NameSettings::default()
    };
    let weighed = name(&noisy, &sens, &s).unwrap();
    assert!(weighed.named().is_none(), "{}", weighed.verdict);
    // an effect the model's error does not resemble is still named beside that error,
    // with its size (recordings of little noise)
    let planted: Vec<Cell> = cells(&sens, &[(Effect::WallBias, 0.3)], 23)
        .into_iter()
        .zip(&e)
        .map(|(mut c, ei)| {
            c.standardised += ei;
            c
        })
        .collect();
    let n = name(&planted, &sens, &s).unwrap();
    let top = n.named().unwrap_or_else(|| panic!("{}", n.verdict));
    assert_eq!(top.effect, "wall_bias", "{}", n.verdict);
    assert!(
        (top.estimate - 0.3).abs() < 3.0 * top.std_error,
        "{} ± {}",
        top.estimate,
        top.std_error
    );
    // a spread of another table is refused
    let short = ErrorSpread {
        deviations: vec![vec![0.0; 3]; 3],
        ..spread
    };
    let err = name(
        &noisy,
        &sens,
        &NameSettings {
            error_spread: Some(short),
            ..NameSettings::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("3 values per sample"), "{err}");
}

#[test]
fn a_derivative_spike_is_reported() {
    let mut sens = sweep(17);
    // tip Uz at N = 9, T = 1.6, 2 bar: density's derivative 1000 times the others'
    let j = sens.designs[0]
        .sensitivities
        .parameters
        .iter()
        .position(|p| p.parameter == Parameter::Effect(Effect::Density))
        .unwrap();
    let steps = &mut sens.designs[0].sensitivities.steps;
    for st in steps.iter_mut() {
        st.derivatives[j].tip_uz_mm = 0.01;
    }
    steps[2].derivatives[j].tip_uz_mm = 10.0;
    let cells = cells(&sens, &[], 18);
    let n = name(&cells, &sens, &NameSettings::default()).unwrap();
    assert!(
        n.spikes.iter().any(|s| s.starts_with(
            "N = 9, T = 1.6 mm, 2 bar, tip_uz_mm: its FE derivative by density is 1000 times"
        )),
        "{:?}",
        n.spikes
    );
    assert!(!n.spikes.iter().any(
        |s| s.starts_with("N = 9, T = 1.6 mm, 1 bar, tip_uz_mm: its FE derivative by density")
    ));
}

#[test]
fn material_offsets_and_noise_alone_name_nothing() {
    let sens = sweep(3);
    let n = name(&cells(&sens, &[], 4), &sens, &NameSettings::default()).unwrap();
    assert!(n.candidates.iter().all(|c| !c.significant), "{}", n.verdict);
    assert!(n.verdict.starts_with("No effect"), "{}", n.verdict);
    // the material took its offsets: what is left is the noise (σ_noise² = 0.05²/3)
    assert!(
        n.chi2_material < 0.05 * n.chi2,
        "{} of {}",
        n.chi2_material,
        n.chi2
    );
}

#[test]
fn collinear_candidates_are_reported_as_indistinguishable() {
    let mut sens = sweep(5);
    // gap_bias moves every output as wall_bias does, twice as much, plus a trace
    let params = sens.designs[0].sensitivities.parameters.clone();
    let at = |p: Effect| {
        params
            .iter()
            .position(|i| i.parameter == Parameter::Effect(p))
            .unwrap()
    };
    let (w, g) = (at(Effect::WallBias), at(Effect::GapBias));
    for d in &mut sens.designs {
        for st in &mut d.sensitivities.steps {
            let mut copy = st.derivatives[w].clone();
            copy.tip_uz_mm = 2.0 * copy.tip_uz_mm + 1e-3;
            copy.tip_uy_mm *= 2.0;
            copy.angle_deg *= 2.0;
            // the markers (not recorded) tell them apart
            copy.markers.iter_mut().for_each(|m| m[1] += 1.0);
            st.derivatives[g] = copy;
        }
    }
    let n = name(
        &cells(&sens, &[(Effect::WallBias, 0.12)], 6),
        &sens,
        &NameSettings::default(),
    )
    .unwrap();
    let pair = n
        .indistinguishable
        .iter()
        .find(|p| [&p.a, &p.b].contains(&&"gap_bias".to_string()))
        .unwrap_or_else(|| panic!("{:#?}", n.indistinguishable));
    assert!(pair.cosine > 0.99);
    assert!(
        pair.separated_by
            .as_deref()
            .is_some_and(|s| s.starts_with('m') && s.contains("_uy_mm at N = ")),
        "{pair:?}"
    );
    assert!(n.verdict.contains("cannot be told apart"), "{}", n.verdict);
}

#[test]
fn a_sweep_without_the_material_is_refused() {
    let mut sens = sweep(7);
    for d in &mut sens.designs {
        d.sensitivities
            .parameters
            .retain(|p| matches!(p.parameter, Parameter::Effect(_)));
    }
    let e = name(&cells(&sweep(7), &[], 1), &sens, &NameSettings::default()).unwrap_err();
    assert!(e.to_string().contains("mu1"), "{e}");
}
