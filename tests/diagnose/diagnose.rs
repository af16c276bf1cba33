//! The diagnoser's Locate stage (`surrogate::diagnose`) on recordings with a known residual:
//! the shipped surrogate's own outputs at a known material, noise at the experiments'
//! standard deviations (`calibrate::synthetic`), and a planted structure; and on the same
//! recordings without one (nothing may be found).

use std::path::Path;

use surrogate::calibrate::experiments::MarkerRecord;
use surrogate::calibrate::optimise::MultistartSettings;
use surrogate::calibrate::synthetic::{noisy_markers, noisy_recordings, TrueMarkers, TrueOutputs};
use surrogate::calibrate::{calibrate, CalibrationSettings, OgdenSet, Recordings, Weights};
use surrogate::case::Query;
use surrogate::diagnose::cells::Family;
use surrogate::diagnose::coverage::MissingKind;
use surrogate::diagnose::findings::FindingKind;
use surrogate::diagnose::structure::Term;
use surrogate::diagnose::{diagnose, locate, DiagnoseSettings, Diagnosis, LocateSettings};
use surrogate::rom::Surrogate;

fn model() -> Surrogate {
    Surrogate::load(Path::new("models/as_modelled/actuator.json")).unwrap()
}

/// The literature set: inside the shipped surrogate's training domain.
fn material() -> OgdenSet {
    OgdenSet::literature("ogden_002").unwrap()
}

/// The surrogate's outputs at the shipped configurations and `material()`.
fn truth(model: &Surrogate) -> (Vec<TrueOutputs>, Vec<TrueMarkers>) {
    let mut pred = model.new_prediction();
    let m = material();
    let mut outputs = Vec::new();
    let mut markers = Vec::new();
    for r in Recordings::shipped().unwrap().bending {
        let q = Query::new(r.n_bellows as u32, r.wall_thickness_mm, r.pressure_bar, m);
        model.predict_into(&q, &mut pred).unwrap();
        outputs.push(TrueOutputs {
            n_bellows: r.n_bellows,
            wall_thickness_mm: r.wall_thickness_mm,
            pressure_bar: r.pressure_bar,
            tip_uz_mm: pred.tip_uz_mm(),
            tip_uy_mm: pred.tip_uy_mm(),
            angle_deg: pred.angle_deg(),
            force_n: pred.force_n(),
        });
        markers.push(TrueMarkers {
            n_bellows: r.n_bellows,
            wall_thickness_mm: r.wall_thickness_mm,
            pressure_bar: r.pressure_bar,
            markers: std::array::from_fn(|k| [pred.values[2 * k], pred.values[2 * k + 1]]),
        });
    }
    (outputs, markers)
}

/// Tip and force fitted (the force then carries no misfit of a material the tip cannot
/// determine); few starts and profile points: the test is of Locate, not of the fit.
fn settings() -> CalibrationSettings {
    let mut s = CalibrationSettings {
        weights: Weights::parse("tip,force").unwrap(),
        multistart: MultistartSettings {
            starts: 6,
            ..MultistartSettings::default()
        },
        ..CalibrationSettings::default()
    };
    s.identify.profile_points = 4;
    s
}

#[test]
fn a_planted_trend_over_t_is_found_and_worded() {
    let model = model();
    let (truth, _) = truth(&model);
    let mut rec = noisy_recordings(&truth, &Recordings::shipped().unwrap(), 11, "planted").unwrap();
    // the actuators curl back 15 mm more per mm of wall thickness than the model says:
    // predicted − recorded falls with T
    for r in &mut rec.bending {
        r.tip_uz_mm += 15.0 * (r.wall_thickness_mm - 2.0);
    }
    let cal = calibrate(&model, &rec, &settings(), &|_| {}).unwrap();
    let loc = locate(&cal, &model, &rec, &LocateSettings::default()).unwrap();
    let uz = loc.structure(Family::TipUz).unwrap();
    let t = uz.term(Term::T).unwrap();
    assert!(t.significant && t.coefficient < 0.0, "tip Uz over T: {t:?}");
    // the other terms of tip Uz are not what was planted
    for other in [Term::N, Term::PT] {
        assert!(!uz.term(other).unwrap().significant, "{other:?}: {uz:?}");
    }
    let words: Vec<&str> = loc
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::Structure && f.outputs == [Family::TipUz])
        .map(|f| f.text.as_str())
        .collect();
    assert_eq!(words.len(), 1, "{:#?}", loc.findings);
    let w = words[0];
    assert!(
        w.contains("with T") && w.contains("at T = 1.6 mm") && w.contains("at T = 2.4 mm"),
        "{w}"
    );
    // the plant makes the model curl back too far at thin walls and too little at thick ones
    assert!(
        w.contains("bends too far at T = 1.6 mm")
            && w.contains("does not bend far enough at T = 2.4 mm"),
        "{w}"
    );
    // the table: every recorded number once, shares add up to 1; force and bending fitted,
    // the angle predicted
    assert_eq!(loc.cells.len(), 27 * 4);
    let total: f64 = loc.cells.iter().map(|c| c.chi2_share).sum();
    assert!((total - 1.0).abs() < 1e-12);
    assert!(loc.cells_of(Family::Angle).all(|c| !c.fitted));
    assert!(loc.cells_of(Family::Force).all(|c| c.fitted));
    assert!(loc.missing.iter().any(|m| m.kind == MissingKind::Markers));
    assert!(!loc.consistent_with_scatter());
}

#[test]
fn pure_noise_is_reported_as_nothing_significant() {
    let model = model();
    let (truth, _) = truth(&model);
    let rec = noisy_recordings(&truth, &Recordings::shipped().unwrap(), 11, "null").unwrap();
    let s = DiagnoseSettings {
        calibration: settings(),
        ..DiagnoseSettings::default()
    };
    let d = diagnose(&model, &rec, &s, &|_| {}).unwrap();
    let l = &d.locate;
    assert!(l.misfits.iter().all(|m| !m.significant), "{:?}", l.misfits);
    assert!(
        l.structures
            .iter()
            .all(|s| s.terms.iter().all(|t| !t.significant)),
        "{:?}",
        l.structures
    );
    assert!(l.groups.iter().all(|g| !g.significant));
    // so a name would be a hypothesis; and the noise is at its stated σ, not below it
    assert!(l.consistent_with_scatter());
    assert_eq!(l.findings.len(), 1, "{:#?}", l.findings);
    assert_eq!(l.findings[0].kind, FindingKind::NoStructure);
    assert!(
        l.findings[0]
            .text
            .starts_with("Nothing is significant at α = 0.05"),
        "{}",
        l.findings[0].text
    );
    // the report: versioned JSON that reads back, the stages not run say why
    let json = d.to_json().unwrap();
    let back = Diagnosis::from_json(&json).unwrap();
    assert_eq!(back.locate.findings, l.findings);
    assert!(json.contains("\"format\": \"surrogate.diagnosis\""));
    assert!(json.contains("needs the FE sensitivities"));
    let other = json.replace("\"version\": 1", "\"version\": 7");
    let e = Diagnosis::from_json(&other).unwrap_err().to_string();
    assert!(e.contains("version = 7"), "{e}");
    let md = surrogate::diagnose::summary::summary_markdown(&d);
    assert!(md.starts_with("# Diagnosis") && md.contains("## Findings\n\n- Nothing"));
}

#[test]
fn markers_locate_the_residual_along_the_actuator() {
    let model = model();
    let (truth, markers) = truth(&model);
    let noise = Recordings::shipped().unwrap();
    let mut rec = noisy_recordings(&truth, &noise, 5, "markers").unwrap();
    // markers sag more towards the tip than the model says: recorded Uy lower by 0.15 k² mm,
    // 0.15 mm at marker 1 up to 12 mm at the tip; the markers' σ grows about as k, so z as k
    let mut m: Vec<MarkerRecord> = noisy_markers(&markers, &noise, 5).unwrap();
    for r in &mut m {
        r.uy_mm -= 0.15 * (r.marker * r.marker) as f64;
    }
    rec.markers = m;
    rec.markers_source = "planted markers".into();
    // one design at 2 bar only, and no force: both said, the diagnosis runs on the rest
    rec.bending
        .retain(|r| !(r.n_bellows == 9 && r.wall_thickness_mm == 1.6 && r.pressure_bar != 2.0));
    rec.markers
        .retain(|r| !(r.n_bellows == 9 && r.wall_thickness_mm == 1.6 && r.pressure_bar != 2.0));
    rec.force.clear();
    let mut s = settings();
    s.weights = Weights::parse("tip").unwrap();
    let cal = calibrate(&model, &rec, &s, &|_| {}).unwrap();
    let loc = locate(&cal, &model, &rec, &LocateSettings::default()).unwrap();
    assert!(loc.along_actuator);
    assert_eq!(loc.shares.by_marker.len(), 9);
    let uy = loc.structure(Family::MarkerUy).unwrap();
    let pos = uy.term(Term::Position).unwrap();
    // predicted − recorded > 0 and growing towards the tip
    assert!(pos.significant && pos.coefficient > 0.0, "{pos:?}");
    assert!(
        loc.findings
            .iter()
            .any(|f| f.outputs == [Family::MarkerUy] && f.text.contains("along the actuator")),
        "{:#?}",
        loc.findings
    );
    let kinds: Vec<MissingKind> = loc.missing.iter().map(|m| m.kind).collect();
    assert!(kinds.contains(&MissingKind::Force), "{kinds:?}");
    assert!(!kinds.contains(&MissingKind::Markers), "{kinds:?}");
    let p = loc
        .missing
        .iter()
        .find(|m| m.kind == MissingKind::Pressure)
        .unwrap();
    assert!(
        p.what.contains("N=9 T=1.6: no recording at 1, 3 bar"),
        "{}",
        p.what
    );
    assert!(loc.cells_of(Family::Force).next().is_none());
}

#[test]
fn bad_settings_are_named() {
    let e = LocateSettings { alpha: 0.9 }
        .validate()
        .unwrap_err()
        .to_string();
    assert_eq!(e, "alpha = 0.9: expected a significance level in (0, 0.5]");
}
