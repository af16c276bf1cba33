//! The blind study's committed twins diagnosed with the diagnosing model's approximation
//! error (`surrogate::diagnose::approx_error`), sampled from the null twins' committed FE
//! (no FE runs here): a concealed effect whose signature the material cannot absorb is
//! named, a null twin diagnosed without its own group's sample names nothing, the error of
//! one model is refused for another, and the error file written and read back is the same.

use std::path::Path;

use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::Recordings;
use surrogate::diagnose::approx_error::ApproximationError;
use surrogate::diagnose::study::{
    diagnose_twin, null_approximation_error, Diagnoser, StudyDirs, StudyPlan,
};
use surrogate::rom::Surrogate;

const STUDY: &str = "fe_reference/diagnosis/blind";
const SWEEP: &str = "data/sensitivities/ogden002_coarse.json";

#[test]
fn committed_twins_are_named_right_with_the_approximation_error() {
    let model = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json")).unwrap();
    let sens = SweepSensitivities::read(Path::new(SWEEP)).unwrap();
    let plan = StudyPlan::read(&Path::new(STUDY).join("plan.json")).unwrap();
    let dirs = StudyDirs::under(Path::new(STUDY));
    let shipped = Recordings::shipped().unwrap();
    let all = null_approximation_error(
        &plan,
        &shipped,
        &dirs,
        &model,
        // the name the committed study recorded, before the as-modelled models moved to
        // models/as_modelled/ (the file is the same: its checksum is checked below)
        "models/actuator_coarse.json",
    )
    .unwrap();
    assert_eq!(all.samples.len(), 6);
    // what `twin-study` committed is what the library makes from the committed FE
    let committed =
        ApproximationError::read(&Path::new(STUDY).join("approximation_error.json")).unwrap();
    assert_eq!(committed, all);
    // it is the error of this model: the other shipped model is refused, naming both
    all.check_model(&model).unwrap();
    let other = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    let e = all.check_model(&other).unwrap_err().to_string();
    assert!(
        e.starts_with("approximation error's model = models/actuator_coarse.json (crc32:")
            && e.contains(&other.checksum().unwrap()),
        "{e}"
    );
    // every sample holds the force error at each recorded design and pressure
    let f: Vec<f64> = all
        .samples
        .iter()
        .flat_map(|s| {
            s.values
                .iter()
                .filter(|v| v.output == surrogate::calibrate::objective::Output::Force)
                .map(|v| v.error)
        })
        .collect();
    assert_eq!(f.len(), 6 * 27);
    let named = |twin: &str, a: Option<&ApproximationError>| {
        let by = Diagnoser {
            model: &model,
            sens: &sens,
            mesh_reference: None,
            markers: false,
            approximation: a,
        };
        let d = diagnose_twin(&dirs.twins.join(twin), &by).unwrap();
        let n = d.naming().unwrap();
        (
            n.named().map(|c| c.effect.clone()),
            n.candidates
                .iter()
                .find(|c| twin.starts_with(&c.effect))
                .map(|c| c.estimate),
        )
    };
    // concealed gap_bias −0.3 mm and pressure_loss 0.15: named, sizes about right
    let (e, size) = named("gap_bias_2_s2", Some(&all));
    assert_eq!(e.as_deref(), Some("gap_bias"));
    assert!((size.unwrap() + 0.3).abs() < 0.06, "{size:?}");
    let (e, size) = named("pressure_loss_2_s1", Some(&all));
    assert_eq!(e.as_deref(), Some("pressure_loss"));
    assert!((size.unwrap() - 0.15).abs() < 0.03, "{size:?}");
    // a null twin, its own material's sample left out: nothing is named
    let own = all.without(&["null_1"]).unwrap();
    assert_eq!(own.samples.len(), 5);
    let (e, _) = named("null_1_s1", Some(&own));
    assert_eq!(e, None);
    // the file round-trips
    let tmp = std::env::temp_dir().join(format!("approx_error_it_{}.json", std::process::id()));
    all.write(&tmp).unwrap();
    assert_eq!(ApproximationError::read(&tmp).unwrap(), all);
    std::fs::remove_file(&tmp).unwrap();
}
