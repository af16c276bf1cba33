//! A program's own effect, outside the crate: one type implementing `CaseEffect` (here a
//! gauge reading low, the cavities at `(1 + g)·P`) and one registration line. It parses by
//! name (in effect assignments, parameter lists and JSON), acts on the coarse actuator exactly
//! as the pressure it stands for, and its sensitivity (the method its target declares: the
//! load level's pressure) matches finite differences of full runs.

use std::collections::BTreeMap;

use serde::de::DeserializeSeed;
use surrogate::fe::effects::{
    CaseEffect, Differentiation, Effect, EffectError, EffectInfo, EffectRegistry, Effects, Kind,
    Target,
};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::sensitivity::{
    simulate_with_sensitivities, OgdenParameter, Outputs, Parameter, SensitivityError,
};
use surrogate::fe::simulate::{simulate, Case, ContactSettings, Mode, StepResult};
use surrogate::fe::solver::SolverSettings;
use surrogate::snapshots::plan::{Plan, Ranges};

/// The gauge reads low by the fraction `g`: the cavities hold `(1 + g)·P` at a reading `P`.
struct GaugeGain;

const INFO: EffectInfo = EffectInfo {
    name: "gauge_gain",
    meaning: "the gauge reads low: the cavities hold (1 + g)·P",
    unit: "1",
    neutral: 0.0,
    range: (0.0, 0.5),
    kind: Kind::Tolerance,
    source: "a toy effect of a program using the crate",
};

impl CaseEffect for GaugeGain {
    fn info(&self) -> &EffectInfo {
        &INFO
    }
    fn target(&self) -> Target {
        Target::Pressure
    }
    fn pressure_bar(&self, g: f64, pressure_bar: f64) -> f64 {
        (1.0 + g) * pressure_bar
    }
}

const GAUGE_GAIN: Effect = Effect::new(&GaugeGain);

/// The library and the toy: the one registration line.
fn registry() -> EffectRegistry {
    EffectRegistry::builtin().with(GAUGE_GAIN).unwrap()
}

/// The coarse N = 9, T = 2 actuator bending without contact, at `pressures` (bar).
fn case(pressures: &[f64], effects: Effects) -> Case {
    Case {
        design: DesignParams::new(9, 2.0).validate().unwrap(),
        material: Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap(),
        pressures_bar: pressures.to_vec(),
        gravity: true,
        mesh: MeshOptions::level(MeshLevel::Coarse),
        solver: SolverSettings::default(),
        mode: Mode::Bending,
        contact: ContactSettings {
            enabled: false,
            ..ContactSettings::default()
        },
        effects,
    }
}

fn gain(g: f64) -> Effects {
    Effects::neutral().with(GAUGE_GAIN, g).unwrap()
}

/// Tip, angle and markers, bit for bit.
fn shape(s: &StepResult) -> Vec<u64> {
    let mut v = vec![s.tip_uz_mm, s.tip_uy_mm, s.angle_deg];
    v.extend(s.markers.iter().flatten());
    v.into_iter().map(f64::to_bits).collect()
}

#[test]
fn a_registered_effect_parses_by_name_and_is_refused_elsewhere() {
    let registry = registry();
    let e = registry.parse(["gauge_gain=0.2", "wall_bias=0.1"]).unwrap();
    assert_eq!(e.get(GAUGE_GAIN), 0.2);
    assert_eq!(e.get(Effect::WallBias), 0.1);
    // applied after the library's effects, and written by its name
    let order: Vec<_> = e.iter().map(|(k, _)| k.name()).collect();
    assert_eq!(order, ["wall_bias", "gauge_gain"]);
    assert_eq!(
        serde_json::to_string(&e).unwrap(),
        r#"{"gauge_gain":0.2,"wall_bias":0.1}"#
    );
    assert_eq!(GAUGE_GAIN.differentiation(), Differentiation::LoadLevel);
    // its range is checked as the library's are
    let err = registry.parse(["gauge_gain=0.7"]).unwrap_err().to_string();
    assert!(err.contains("[0, 0.5]"), "{err}");
    // the library alone does not know it, and a name is registered once
    assert!(matches!(
        Effects::parse(["gauge_gain=0.2"]),
        Err(EffectError::Unknown { .. })
    ));
    assert!(matches!(
        registry.with(GAUGE_GAIN),
        Err(EffectError::Invalid { .. })
    ));
}

#[test]
fn a_registered_effect_is_a_parameter_and_reads_from_json_through_its_registry() {
    let registry = registry();
    // a parameter list names it beside the material and the library's effects
    let mu1 = Parameter::Material(OgdenParameter::Mu1);
    let (toy, wall) = (
        Parameter::Effect(GAUGE_GAIN),
        Parameter::Effect(Effect::WallBias),
    );
    assert_eq!(
        Parameter::parse_list_with("mu1, gauge_gain, wall_bias", &registry).unwrap(),
        [mu1, toy, wall]
    );
    let all = Parameter::parse_list_with("all", &registry).unwrap();
    assert_eq!(all.last(), Some(&toy));
    assert_eq!(all.len(), Parameter::all().len() + 1);
    // the library alone refuses it, naming it and the names it knows
    let err = Parameter::parse_list("mu1,gauge_gain").unwrap_err();
    assert!(
        matches!(&err, SensitivityError::Unknown { name, .. } if name == "gauge_gain"),
        "{err}"
    );
    let text = err.to_string();
    assert!(
        text.contains("'gauge_gain'") && text.contains("wall_bias"),
        "{text}"
    );
    assert_eq!(text.matches("gauge_gain").count(), 1, "{text}");
    // a `{name: value}` object reads through the registry, range checked
    let read = |text: &str| registry.deserialize(&mut serde_json::Deserializer::from_str(text));
    let json = r#"{"gauge_gain":0.2,"wall_bias":0.1}"#;
    let e = read(json).unwrap();
    assert_eq!(
        e,
        registry.parse(["gauge_gain=0.2", "wall_bias=0.1"]).unwrap()
    );
    assert_eq!(serde_json::to_string(&e).unwrap(), json);
    let err = read(r#"{"gauge_gain":0.7}"#).unwrap_err().to_string();
    assert!(
        err.contains("gauge_gain = 0.7") && err.contains("[0, 0.5]"),
        "{err}"
    );
    // and the library's reading refuses it, naming it and the library's names
    let err = serde_json::from_str::<Effects>(json)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(r#"unknown effect "gauge_gain": expected one of wall_bias"#),
        "{err}"
    );
    let map: BTreeMap<String, f64> = [("gauge_gain".to_string(), 0.2)].into();
    assert_eq!(
        registry
            .effects_from_map(map.clone())
            .unwrap()
            .get(GAUGE_GAIN),
        0.2
    );
    assert!(matches!(
        Effects::try_from(map),
        Err(EffectError::Unknown { name, .. }) if name == "gauge_gain"
    ));
}

#[test]
fn the_toy_effect_acts_as_the_pressure_it_stands_for() {
    // (1 + 0.2)·0.5 bar is 0.6 bar to the last bit
    let toy = simulate(&case(&[0.0, 0.5], gain(0.2))).unwrap().steps;
    let plain = simulate(&case(&[0.0, 0.6], Effects::neutral()))
        .unwrap()
        .steps;
    // the effect library's plain bending run (`effects`): run once for both
    let nominal = crate::shared_runs::steps(&case(&[0.0, 0.5], Effects::neutral()));
    assert_eq!(toy[1].pressure_bar, 0.5);
    assert_eq!(shape(&toy[1]), shape(&plain[1]));
    // the self-weight state is untouched, and more pressure moves the tip further (a fifth
    // more pressure, about a fifth more motion)
    assert_eq!(shape(&toy[0]), shape(&nominal[0]));
    let moved = |s: &[StepResult]| s[1].tip_uy_mm - s[0].tip_uy_mm;
    assert!(
        moved(&toy) / moved(&nominal) > 1.1 && moved(&toy) / moved(&nominal) < 1.3,
        "tip moved {} mm with the toy, {} mm without",
        moved(&toy),
        moved(&nominal)
    );
}

#[test]
fn the_toy_effects_sensitivity_matches_finite_differences() {
    let (g, delta) = (0.2, 0.005);
    let p = Parameter::Effect(GAUGE_GAIN);
    let base = case(&[0.0, 0.5], gain(g));
    let (response, sens) = simulate_with_sensitivities(&base, &[p], |_, _| {}).unwrap();
    assert_eq!(sens.parameters[0].how, "effective pressure");
    let run = |v: f64| simulate(&case(&[0.0, 0.5], gain(v))).unwrap().steps;
    let (up, down) = (run(g + delta), run(g - delta));
    let named = |s: &StepResult| {
        Outputs {
            tip_uz_mm: s.tip_uz_mm,
            tip_uy_mm: s.tip_uy_mm,
            angle_deg: s.angle_deg,
            markers: s.markers.clone(),
            force_n: s.force_n,
        }
        .named()
    };
    let last = response.steps.len() - 1;
    let d = sens.derivative(last, p).unwrap().named();
    let (yu, yd) = (named(&up[last]), named(&down[last]));
    let fd: Vec<f64> = yu
        .iter()
        .zip(&yd)
        .map(|(a, b)| (a.1 - b.1) / (2.0 * delta))
        .collect();
    let scale = fd.iter().map(|v| v.abs()).fold(0.0f64, f64::max);
    assert!(scale > 1.0, "the toy effect moves the tip: {scale} mm");
    for ((name, s), f) in d.iter().zip(&fd) {
        assert!(
            (s - f).abs() <= 0.01 * scale,
            "{name}: sensitivity {s:.6e}, finite difference {f:.6e}"
        );
    }
    // nothing moves at 0 bar
    let d0 = sens.derivative(0, p).unwrap();
    assert_eq!(d0.tip_uy_mm, 0.0);
}

#[test]
fn a_plan_with_a_registered_effect_reads_inside_its_registrys_scope() {
    let registry = registry();
    let shipped = Plan::read(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("training_data/snapshots_coarse.plan.json"),
    )
    .unwrap();
    let mut settings = shipped.settings.clone();
    settings.effects = registry.parse(["wall_bias=0.05"]).unwrap();
    let ranges = Ranges {
        effects: [("gauge_gain".to_string(), [0.0, 0.2])].into(),
        ..shipped.ranges.clone()
    };
    // outside the scope the library alone is known: the plan is refused, naming the effect
    let refused = Plan::generate(6, 3, ranges.clone(), settings.clone())
        .unwrap_err()
        .to_string();
    assert!(refused.contains("gauge_gain"), "{refused}");
    let plan = registry
        .reading(|| Plan::generate(6, 3, ranges, settings))
        .unwrap();
    assert!(plan
        .cases
        .iter()
        .all(|c| (0.0..=0.2).contains(&c.effects.get(GAUGE_GAIN))));
    let json = plan.canonical_json();
    let err = Plan::from_json(&json, "toy.plan.json")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("toy.plan.json") && err.contains("gauge_gain"),
        "{err}"
    );
    // inside it the plan reads back as written, and scopes nest and end
    let back = registry
        .reading(|| {
            EffectRegistry::builtin().reading(|| {
                assert!(Plan::from_json(&json, "inner").is_err());
            });
            Plan::from_json(&json, "toy.plan.json")
        })
        .unwrap();
    assert_eq!(back, plan);
    assert!(Plan::from_json(&json, "after").is_err());
    // a panic inside a scope ends it too
    let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        registry.reading(|| panic!("inside"))
    }));
    assert!(caught.is_err());
    assert!(Plan::from_json(&json, "after a panic").is_err());
}
