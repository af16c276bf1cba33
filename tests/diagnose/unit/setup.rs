//! The unit tests of `src/diagnose/setup.rs`.

use std::path::Path;
use surrogate::diagnose::setup::*;

#[test]
fn defaults_lie_under_the_root_and_given_files_as_given() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let r = DiagnosisSetup::recordings().resolve(root).unwrap();
    // real recordings are diagnosed as the blind study scores: the coarse model, no mesh
    // reference, the shipped approximation error
    assert_eq!(r.model.path, root.join(SHIPPED_COARSE_MODEL));
    assert!(r.model.default);
    assert_eq!(r.mesh_reference, None);
    assert_eq!(
        r.approximation_error,
        ApproximationSource::File(ResolvedFile {
            path: root.join(SHIPPED_APPROXIMATION_ERROR),
            default: true
        })
    );
    // the blind study's twins are built on the geometry as modelled: its model and
    // approximation error are that geometry's
    let b = DiagnosisSetup::blind_study().resolve(root).unwrap();
    assert_eq!(b.model.path, root.join(AS_MODELLED_COARSE_MODEL));
    assert!(b.model.default);
    assert_eq!(b.mesh_reference, None);
    assert_eq!(
        b.approximation_error,
        ApproximationSource::File(ResolvedFile {
            path: root.join(AS_MODELLED_APPROXIMATION_ERROR),
            default: true
        })
    );
    assert_ne!(b.sensitivities, r.sensitivities);
    for f in [AS_MODELLED_COARSE_MODEL, AS_MODELLED_MODEL] {
        assert!(root.join(f).is_file(), "{f}");
    }
    // auto beside the standard model: the coarse one
    let mut s = DiagnosisSetup::recordings();
    s.model = SetupFile::Repository(SHIPPED_MODEL);
    s.mesh_reference = MeshReference::from_flag("auto");
    assert_eq!(
        s.resolve(root).unwrap().mesh_reference,
        Some(ResolvedFile {
            path: root.join(SHIPPED_COARSE_MODEL),
            default: true
        })
    );
    let mut s = DiagnosisSetup::blind_study();
    s.model = SetupFile::Given("elsewhere/actuator.json".into());
    s.mesh_reference = MeshReference::from_flag("auto");
    s.approximation_error = ApproximationSource::from_flag("e.json");
    let r = s.resolve(root).unwrap();
    assert_eq!(r.model.path, Path::new("elsewhere/actuator.json"));
    assert!(!r.model.default);
    // no coarse model beside it: auto is none
    assert_eq!(r.mesh_reference, None);
    assert_eq!(
        r.approximation_error,
        ApproximationSource::File(ResolvedFile {
            path: "e.json".into(),
            default: false
        })
    );
}

#[test]
fn a_choice_of_the_other_use_names_its_flag() {
    let root = Path::new("/repo");
    let mut s = DiagnosisSetup::blind_study();
    s.sensitivities = Sensitivities::from_flag("calibrated");
    let e = s.resolve(root).unwrap_err().to_string();
    assert!(
        e.starts_with("--sensitivities = calibrated: expected a file"),
        "{e}"
    );
    let mut s = DiagnosisSetup::recordings();
    s.approximation_error = ApproximationSource::from_flag("nulls");
    let e = s.resolve(root).unwrap_err().to_string();
    assert!(
        e.starts_with("--approximation-error = nulls: expected none or"),
        "{e}"
    );
}

/// Each setup's default files belong to its default model: the approximation error was sampled
/// from it (its checksum) and the FE sensitivities were run on the actuator its training cases
/// were built as (geometry, fixed effects). The shipped models are on the identified geometry,
/// the blind study's on the geometry as modelled, so the two setups' files differ.
#[test]
fn each_setups_defaults_belong_to_its_model() {
    use surrogate::calibrate::baseline::SweepSensitivities;
    use surrogate::diagnose::approx_error::ApproximationError;
    use surrogate::diagnose::sweep::check_built_as;
    use surrogate::rom::Surrogate;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for setup in [DiagnosisSetup::recordings(), DiagnosisSetup::blind_study()] {
        let r = setup.resolve(root).unwrap();
        let model = Surrogate::load(&r.model.path).unwrap();
        let ApproximationSource::File(e) = &r.approximation_error else {
            panic!("{:?}: no default approximation error", setup.used_for)
        };
        ApproximationError::read(&e.path)
            .unwrap()
            .check_model(&model)
            .unwrap();
        let Sensitivities::File(s) = &r.sensitivities else {
            panic!("{:?}: no default sensitivities", setup.used_for)
        };
        let sens = SweepSensitivities::read(&s.path).unwrap();
        check_built_as(&sens, model.training.built_with.as_ref())
            .unwrap_or_else(|e| panic!("{}: {e}", s.path.display()));
    }
    let shipped = Surrogate::load(&root.join(SHIPPED_COARSE_MODEL)).unwrap();
    let built = shipped
        .training
        .built_with
        .expect("the identified geometry");
    assert_eq!(built.geometry.name, "identified");
}
