//! The FE sensitivities against the model they are used with: a sweep of another actuator
//! (another geometry, other fixed effects) than the model's training cases is refused, naming
//! both; the committed sweeps fit the shipped model.

use std::path::Path;

use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::diagnose::sweep::check_built_as;
use surrogate::diagnose::DiagnoseError;
use surrogate::fe::effects::{Effect, Effects};
use surrogate::fe::preset::Geometry;
use surrogate::rom::provenance::BuiltWith;
use surrogate::rom::Surrogate;

const SWEEP: &str = surrogate::diagnose::setup::AS_MODELLED_SENSITIVITIES;

fn plate(offset: f64) -> Effects {
    Effects::neutral()
        .with(Effect::PlateOffset, offset)
        .unwrap()
}

fn identified() -> Geometry {
    Geometry {
        name: "identified".into(),
        gap_mm: 1.2,
        ..Geometry::as_modelled()
    }
}

#[test]
fn the_committed_sweeps_fit_the_shipped_model() {
    let model = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    assert_eq!(model.training.built_with, None);
    for f in [SWEEP, "data/sensitivities/ogden002_coarse.json"] {
        let sens = SweepSensitivities::read(Path::new(f)).unwrap();
        check_built_as(&sens, model.training.built_with.as_ref()).unwrap();
        // stated explicitly, the geometry as modelled without fixed effects is the same
        let stated = BuiltWith {
            geometry: Geometry::as_modelled(),
            effects: Effects::neutral(),
        };
        check_built_as(&sens, Some(&stated)).unwrap();
    }
}

#[test]
fn a_sweep_without_the_models_fixed_effects_is_refused_naming_both() {
    let sens = SweepSensitivities::read(Path::new(SWEEP)).unwrap();
    let built = BuiltWith {
        geometry: Geometry::as_modelled(),
        effects: plate(-4.5),
    };
    let e = check_built_as(&sens, Some(&built)).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(&e, DiagnoseError::SweepBuiltOtherwise { what, sweep, model }
            if *what == "fixed effects" && sweep == "none" && model == "plate_offset = -4.5"),
        "{e:?}"
    );
    assert!(
        text.contains("computed with fixed effects none")
            && text.contains("built with fixed effects plate_offset = -4.5"),
        "{text}"
    );
    // the sweep of the model's own actuator is taken; one at another plate is not
    let mut own = sens.clone();
    own.effects = plate(-4.5);
    check_built_as(&own, Some(&built)).unwrap();
    own.effects = plate(-4.0);
    let e = check_built_as(&own, Some(&built)).unwrap_err();
    assert!(
        e.to_string().contains("fixed effects plate_offset = -4, "),
        "{e}"
    );
    // a sweep with a fixed effect, used with the shipped model
    assert!(check_built_as(&own, None).is_err());
}

#[test]
fn a_sweep_of_another_geometry_is_refused_naming_both() {
    let sens = SweepSensitivities::read(Path::new(SWEEP)).unwrap();
    let built = BuiltWith {
        geometry: identified(),
        effects: Effects::neutral(),
    };
    let e = check_built_as(&sens, Some(&built)).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(&e, DiagnoseError::SweepBuiltOtherwise { what, .. } if *what == "geometry"),
        "{e:?}"
    );
    assert!(
        text.contains("'as_modelled'") && text.contains("'identified'") && text.contains("1.2"),
        "{text}"
    );
    // the same dimensions under another name are the same actuator
    let mut own = sens.clone();
    own.geometry = Geometry {
        name: "renamed".into(),
        ..identified()
    };
    check_built_as(&own, Some(&built)).unwrap();
    assert!(check_built_as(&own, None).is_err());
}

/// The approximation error's reference FE is sought where the model's own actuator is
/// cached (its geometry and fixed effects in the cache key), not as modelled.
#[test]
fn the_approximation_errors_reference_is_built_as_the_model() {
    use surrogate::calibrate::{OgdenSet, Recordings};
    use surrogate::diagnose::approx_error::{sample, SampleSettings};
    use surrogate::fe::mesh::{MeshLevel, MeshOptions};

    let mut model = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    let rec = Recordings::shipped().unwrap();
    let cache = std::env::temp_dir().join(format!("approx_built_{}", std::process::id()));
    let settings = SampleSettings {
        mesh: MeshOptions::level(MeshLevel::Standard),
        materials: vec![OgdenSet::literature("ogden_002").unwrap(); 2],
        cache: cache.clone(),
        run_fe: false,
    };
    // nothing is cached: the error names the folder the ramps were sought in
    let folder = |model: &Surrogate| {
        let e = sample(model, "m", &settings, &rec, &|_, _, _| {}).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("ramps not in"), "{text}");
        text
    };
    let as_modelled = folder(&model);
    model.training.built_with = Some(BuiltWith {
        geometry: identified(),
        effects: plate(-4.5),
    });
    let built = folder(&model);
    assert_ne!(as_modelled, built);
    // the same folder the built actuator's twins use
    model.training.built_with = Some(BuiltWith {
        geometry: Geometry::as_modelled(),
        effects: Effects::neutral(),
    });
    assert_eq!(folder(&model), as_modelled);
}
