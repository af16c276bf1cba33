//! The diagnosing model's own mesh error (`surrogate::diagnose::mesh_error`) tested beside
//! the effects: recordings made by the coarse-mesh surrogate moved part of the way towards the
//! standard-mesh one (a model whose mesh is coarser than the actuator's), with noise at the
//! experiments' standard deviations. The Name stage must say that the residual looks like the
//! model's mesh error, with about the planted share, and name no physics; without the shift,
//! the mesh error must not be significant.

use std::path::Path;

use surrogate::calibrate::baseline::SweepSensitivities;
use surrogate::calibrate::objective::Output;
use surrogate::calibrate::synthetic::{noisy_recordings, TrueOutputs};
use surrogate::calibrate::{OgdenSet, Recordings};
use surrogate::case::Query;
use surrogate::diagnose::name::NameSettings;
use surrogate::diagnose::{diagnose, DiagnoseSettings};
use surrogate::rom::Surrogate;

const SWEEP: &str = "data/sensitivities/ogden002_coarse.json";

/// `coarse + share × (standard − coarse)` at Ogden 002, at the shipped designs.
fn truth(coarse: &Surrogate, standard: &Surrogate, share: f64) -> Vec<TrueOutputs> {
    let (mut a, mut b) = (coarse.new_prediction(), standard.new_prediction());
    let m = OgdenSet::literature("ogden_002").unwrap();
    Recordings::shipped()
        .unwrap()
        .bending
        .iter()
        .map(|r| {
            let q = Query::new(r.n_bellows as u32, r.wall_thickness_mm, r.pressure_bar, m);
            coarse.predict_into(&q, &mut a).unwrap();
            standard.predict_into(&q, &mut b).unwrap();
            let mix = |x: f64, y: f64| x + share * (y - x);
            TrueOutputs {
                n_bellows: r.n_bellows,
                wall_thickness_mm: r.wall_thickness_mm,
                pressure_bar: r.pressure_bar,
                tip_uz_mm: mix(a.tip_uz_mm(), b.tip_uz_mm()),
                tip_uy_mm: mix(a.tip_uy_mm(), b.tip_uy_mm()),
                angle_deg: mix(a.angle_deg(), b.angle_deg()),
                force_n: mix(a.force_n(), b.force_n()),
            }
        })
        .collect()
}

fn settings() -> DiagnoseSettings {
    super::quick_diagnose_settings()
}

#[test]
fn a_model_coarser_than_the_actuator_is_told_from_missing_physics() {
    let coarse = Surrogate::load(Path::new("models/as_modelled/actuator_coarse.json")).unwrap();
    let standard = Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap();
    let sens = SweepSensitivities::read(Path::new(SWEEP)).unwrap();
    let shipped = Recordings::shipped().unwrap();
    for (share, seed) in [(0.6, 5), (0.0, 6)] {
        let rec = noisy_recordings(
            &truth(&coarse, &standard, share),
            &shipped,
            seed,
            "coarse model, finer actuator",
        )
        .unwrap();
        let mut d = diagnose(&coarse, &rec, &settings(), &|_| {}).unwrap();
        let me = d
            .mesh_error_with(&coarse, &standard, "models/as_modelled/actuator.json")
            .unwrap()
            .clone();
        // the direction is the two surrogates' difference at the calibrated material
        let c = &d.locate.cells[0];
        let m = d.calibration.best;
        let q = Query::new(c.n_bellows, c.wall_thickness_mm, c.pressure_bar, m);
        let (mut a, mut b) = (coarse.new_prediction(), standard.new_prediction());
        coarse.predict_into(&q, &mut a).unwrap();
        standard.predict_into(&q, &mut b).unwrap();
        let value = |p: &surrogate::rom::Prediction| match c.output {
            Output::TipUz => p.tip_uz_mm(),
            Output::TipUy => p.tip_uy_mm(),
            Output::Angle => p.angle_deg(),
            Output::Force => p.force_n(),
            other => panic!("first cell {}", other.name()),
        };
        let d0 = me.direction.per_cell[0].unwrap();
        assert!((d0 - (value(&b) - value(&a))).abs() < 1e-9, "{d0}");
        assert!(me.rms_sigma > 1.0, "{}", me.rms_sigma);
        let n = d
            .name_with(&sens, &coarse, &NameSettings::default())
            .unwrap()
            .clone();
        let mesh = n
            .candidates
            .iter()
            .find(|c| c.model_error)
            .expect("the mesh error is a candidate");
        if share > 0.0 {
            let best = n.model_error().unwrap_or_else(|| panic!("{}", n.verdict));
            assert_eq!(best.effect, "model_mesh");
            assert!(n.named().is_none(), "{}", n.verdict);
            assert!(
                (mesh.estimate - share).abs() < 0.25,
                "{} ± {}",
                mesh.estimate,
                mesh.std_error
            );
        } else {
            assert!(!mesh.significant, "{}", n.verdict);
        }
    }
}
