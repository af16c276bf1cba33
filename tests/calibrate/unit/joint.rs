//! The unit tests of `src/calibrate/joint/mod.rs`.
//!
//! The bounded Levenberg–Marquardt and its box step on small problems, the held-out splits,
//! and the unknowns' names and bounds.

use nalgebra::{DMatrix, DVector};

use surrogate::calibrate::joint::evaluation::{Evaluation, Recorded, Residual};
use surrogate::calibrate::joint::held_out::{combinations, held_out};
use surrogate::calibrate::joint::in_paper_nine;
use surrogate::calibrate::joint::lm::{bounded_lm, box_step};
use surrogate::calibrate::joint::{bounds, Unknown};
use surrogate::calibrate::joint::{JointStop, MIN_GAIN_CHI2};
use surrogate::fe::effects::Effect;
use surrogate::fe::sensitivity::{OgdenParameter, Parameter};

#[test]
fn every_k_subset_once() {
    let mut out = Vec::new();
    combinations(9, 3, &mut Vec::new(), 0, &mut out);
    assert_eq!(out.len(), 84);
    assert_eq!(out[0], vec![0, 1, 2]);
    assert_eq!(out[83], vec![6, 7, 8]);
}

/// A linear model whose designs all share one unknown: holding any out changes nothing,
/// so the held-out error is the in-sample one; a design with its own bias is predicted
/// worse when held out.
#[test]
fn held_out_designs_are_predicted_by_the_refit_of_the_others() {
    let designs = [(9, 1.6), (11, 2.0), (13, 2.4), (9, 2.4)];
    let mut what = Vec::new();
    let mut r = Vec::new();
    for &(n, t) in &designs {
        for output in [Recorded::TipUz, Recorded::TipUy] {
            what.push(Residual {
                n,
                t,
                output,
                sigma: 2.0,
            });
            // residual 0.5 everywhere, 3 at N = 13 (its own bias)
            r.push(if n == 13 { 3.0 } else { 0.5 });
        }
    }
    let m = r.len();
    let e = Evaluation {
        r: DVector::from_vec(r),
        j: DMatrix::from_element(m, 1, 1.0),
        what,
        rows: Vec::new(),
        error: String::new(),
    };
    let h = held_out(&e, &[0.0], &[(-10.0, 10.0)], 1);
    assert_eq!(h.splits, 4);
    // leaving N = 13 out: the others fit exactly (θ = −0.5), N = 13 predicted at
    // 2.5·√2·2 mm; leaving another out: θ = −(0.5·2 + 3)/3 = −4/3, that design misses by
    // (0.5 − 4/3)·√2·2 mm
    let expected = (2.5 * 2f64.sqrt() * 2.0 + 3.0 * (4.0 / 3.0 - 0.5) * 2f64.sqrt() * 2.0) / 4.0;
    assert!(
        (h.mean_be_mm - expected).abs() < 1e-6,
        "{} vs {expected}",
        h.mean_be_mm
    );
    assert_eq!(h.worst, vec![(13, 2.4)]);
}

#[test]
fn the_paper_nine_move_t_and_p_together() {
    assert!(in_paper_nine(1.6, 1.0) && in_paper_nine(2.0, 2.0) && in_paper_nine(2.4, 3.0));
    assert!(!in_paper_nine(1.6, 3.0) && !in_paper_nine(2.4, 1.0));
}

/// Residuals of a bounded test problem: `r = (x₀ − 1, 10(x₁ − x₀²), x₂ − 5)`, the last
/// coordinate bounded to [0, 2] so that its optimum lies on the bound.
#[allow(clippy::type_complexity)]
fn rosenbrock(x: &[f64]) -> Result<Option<(DVector<f64>, DMatrix<f64>)>, ()> {
    let r = DVector::from_vec(vec![x[0] - 1.0, 10.0 * (x[1] - x[0] * x[0]), x[2] - 5.0]);
    let j = DMatrix::from_row_slice(
        3,
        3,
        &[1.0, 0.0, 0.0, -20.0 * x[0], 10.0, 0.0, 0.0, 0.0, 1.0],
    );
    Ok(Some((r, j)))
}

#[test]
fn bounded_lm_finds_an_interior_optimum_and_stops_on_a_bound() {
    let bnds = [(-2.0, 2.0), (-1.0, 3.0), (0.0, 2.0)];
    let t = bounded_lm(&[-1.2, 1.0, 1.0], &bnds, 1e-2, 1.0, 200, 0.0, rosenbrock).unwrap();
    let x = &t.steps[t.best].x;
    assert!(
        (x[0] - 1.0).abs() < 0.05 && (x[1] - 1.0).abs() < 0.1,
        "{x:?}"
    );
    assert_eq!(x[2], 2.0, "the bounded coordinate ends on its bound");
    assert!(t
        .steps
        .iter()
        .all(|s| s.x.iter().zip(&bnds).all(|(v, b)| *v >= b.0 && *v <= b.1)));
    // χ² never rises along the accepted steps
    let acc: Vec<f64> = t
        .steps
        .iter()
        .filter(|s| s.accepted)
        .map(|s| s.chi2)
        .collect();
    assert!(acc.windows(2).all(|w| w[1] <= w[0]), "{acc:?}");
    // only (5 − 2)² is left, to the stopping rule's relative 1e-3 of χ²
    assert!(
        t.steps[t.best].chi2 < 9.0 * (1.0 + 2e-3),
        "{:?}",
        t.steps[t.best]
    );
}

#[test]
fn no_unknown_moves_by_more_than_the_trust_radius_and_the_radius_adapts() {
    let bnds = [(-2.0, 2.0), (-1.0, 3.0), (0.0, 2.0)];
    let t = bounded_lm(&[-1.2, 1.0, 1.0], &bnds, 1e-2, 0.05, 200, 0.0, rosenbrock).unwrap();
    // the first step: at most 5 % of every range
    let (a, b) = (&t.steps[0].x, &t.steps[1].x);
    for i in 0..3 {
        assert!(
            (b[i] - a[i]).abs() <= 0.05 * (bnds[i].1 - bnds[i].0) + 1e-12,
            "{i}: {a:?} → {b:?}"
        );
    }
    // the radius grows where the linearisation holds: it still gets there
    let x = &t.steps[t.best].x;
    assert!((x[0] - 1.0).abs() < 0.05 && x[2] == 2.0, "{x:?}");
}

#[test]
fn the_box_step_is_the_minimum_of_the_model_over_the_box() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
    for case in 0..200 {
        let k = 1 + case % 4;
        let m = DMatrix::from_fn(k + 2, k, |_, _| rng.gen_range(-1.0..1.0));
        let a = m.transpose() * &m + DMatrix::identity(k, k) * 0.05;
        let g = DVector::from_fn(k, |_, _| rng.gen_range(-2.0..2.0));
        let lo: Vec<f64> = (0..k)
            .map(|_| {
                if rng.gen_bool(0.2) {
                    0.0
                } else {
                    -rng.gen_range(0.01..1.0)
                }
            })
            .collect();
        let hi: Vec<f64> = (0..k)
            .map(|_| {
                if rng.gen_bool(0.2) {
                    0.0
                } else {
                    rng.gen_range(0.01..1.0)
                }
            })
            .collect();
        let q = |d: &DVector<f64>| 0.5 * d.dot(&(&a * d)) + g.dot(d);
        let d = box_step(&a, &g, &lo, &hi).unwrap();
        assert!((0..k).all(|i| d[i] >= lo[i] - 1e-12 && d[i] <= hi[i] + 1e-12));
        // projected gradient descent to the same minimum
        let step = 1.0 / a.norm();
        let mut e = DVector::zeros(k);
        for _ in 0..20_000 {
            let gr = &a * &e + &g;
            for i in 0..k {
                e[i] = (e[i] - step * gr[i]).clamp(lo[i], hi[i]);
            }
        }
        assert!(q(&d) <= q(&e) + 1e-9, "case {case}: {} > {}", q(&d), q(&e));
    }
}

#[test]
fn a_coordinate_far_from_its_optimum_does_not_shorten_the_others_steps() {
    // x₀ is 5 % of its range from its optimum, x₁ 50 %: a radius of 10 % holds x₁ only,
    // and x₀ takes its whole Gauss–Newton step (a single radius keeping the step's
    // direction would move it by a fifth of it)
    let bnds = [(0.0, 10.0), (-1.0, 1.0)];
    let t = bounded_lm(&[0.0, 0.0], &bnds, 1e-9, 0.1, 2, 0.0, |x| {
        let r = DVector::from_vec(vec![x[0] - 0.5, 3.0 * (x[1] - 1.0)]);
        let j = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 3.0]);
        Ok::<_, ()>(Some((r, j)))
    })
    .unwrap();
    let x = &t.steps[1].x;
    assert!((x[0] - 0.5).abs() < 1e-6, "{x:?}");
    assert!((x[1] - 0.2).abs() < 1e-12, "{x:?}");
}

#[test]
fn bounded_lm_stops_at_a_stationary_point_without_another_evaluation() {
    // linear residuals with an irreducible part: the first step reaches the optimum, and
    // the next undamped step predicts no gain, so nothing more is evaluated
    let bnds = [(-5.0, 5.0), (-5.0, 5.0)];
    let lin = |x: &[f64]| {
        let r = DVector::from_vec(vec![x[0] - 1.0, x[1] + 2.0, 3.0]);
        Ok::<_, ()>(Some((
            r,
            DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]),
        )))
    };
    let t = bounded_lm(&[0.0, 0.0], &bnds, 1e-9, 1.0, 10, MIN_GAIN_CHI2, lin).unwrap();
    assert_eq!(t.stop, JointStop::Converged);
    assert_eq!(t.steps.len(), 2, "{:?}", t.steps.len());
    assert!((t.steps[1].chi2 - 9.0).abs() < 1e-9);
    // without the test, the same problem spends its budget on refused steps
    let t = bounded_lm(&[0.0, 0.0], &bnds, 1e-9, 1.0, 10, 0.0, lin).unwrap();
    assert!(t.steps.len() > 2);
}

#[test]
fn bounded_lm_treats_a_failed_evaluation_as_a_failed_step_and_keeps_to_the_budget() {
    let bnds = [(-2.0, 2.0), (-1.0, 3.0), (0.0, 2.0)];
    let mut calls = 0;
    let t = bounded_lm(&[-1.2, 1.0, 1.0], &bnds, 1e-2, 1.0, 6, 0.0, |x| {
        calls += 1;
        // the model fails at every second trial
        if calls % 2 == 0 {
            Ok(None)
        } else {
            rosenbrock(x)
        }
    })
    .unwrap();
    assert_eq!(t.steps.len(), 6);
    assert_eq!(t.stop, JointStop::Budget);
    assert!(t
        .steps
        .iter()
        .skip(1)
        .step_by(2)
        .all(|s| !s.accepted && s.chi2.is_infinite()));
    assert!(t.steps[t.best].accepted);
}

#[test]
fn unknowns_are_named_and_biases_refused() {
    for n in [
        "mu1",
        "alpha2",
        "gap",
        "side_wall",
        "plate_offset",
        "wall_bias_bellows",
    ] {
        assert_eq!(Unknown::from_name(n).unwrap().name(), n);
    }
    let e = Unknown::from_name("gap_bias").unwrap_err().to_string();
    assert!(e.contains("not its bias"), "{e}");
    assert!(Unknown::from_name("colour").is_err());
    assert_eq!(
        Unknown::SideWall.parameter(),
        Parameter::Effect(Effect::WallBiasSide)
    );
    assert_eq!(
        bounds(Unknown::Material(OgdenParameter::Mu2), -5.0),
        (-25.0, -1.0)
    );
    assert_eq!(
        bounds(Unknown::Material(OgdenParameter::Alpha2), -2.0),
        (-12.0, -0.5)
    );
}

/// A row left out of the fit is reported but not counted in the means; an exclusion names
/// the recording it leaves out.
#[test]
fn excluded_rows_are_reported_but_not_averaged() {
    use surrogate::calibrate::joint::evaluation::summary_of;
    use surrogate::calibrate::joint::JointRow;
    use surrogate::calibrate::objective::{Config, Exclusion, Recording};
    let row = |be: f64, f_err: f64, tip_excluded: bool, force_excluded: bool| JointRow {
        n_bellows: 11,
        wall_thickness_mm: 1.6,
        pressure_bar: 2.0,
        paper_nine: false,
        uz_mm: [0.0; 2],
        uy_mm: [0.0; 2],
        angle_deg: [0.0; 2],
        force_n: [1.0, 1.0 + f_err],
        be_mm: be,
        tip_excluded,
        force_excluded,
    };
    let rows = [
        row(2.0, 0.1, false, false),
        row(4.0, -0.3, false, false),
        row(15.0, 0.2, true, false),
        row(3.0, 1.0, false, true),
    ];
    let (be, f) = summary_of(&rows);
    assert!((be - 3.0).abs() < 1e-12, "{be}");
    assert!((f - 0.2).abs() < 1e-12, "{f}");
    let e = Exclusion::parse("bending:11,1.6,2").unwrap();
    let c = Config::of(11, 1.6, 2.0);
    assert!(e.applies(&c, Recording::Bending) && !e.applies(&c, Recording::Force));
    assert!(!e.applies(&Config::of(11, 1.6, 3.0), Recording::Bending));
}

/// The wall law's two unknowns read the sensitivity to every wall's offset, the second scaled
/// by the design's inverse cavity length, and live in the point's geometry.
#[test]
fn the_wall_law_unknowns_scale_the_wall_derivative_by_design() {
    use surrogate::calibrate::joint::JointPoint;
    use surrogate::case::OgdenSet;
    use surrogate::fe::effects::Effects;
    use surrogate::fe::preset::Geometry;
    let a = Unknown::from_name("wall_law_offset").unwrap();
    let b = Unknown::from_name("wall_law_inverse_cavity").unwrap();
    assert_eq!(a.parameter(), Parameter::Effect(Effect::WallBias));
    assert_eq!(b.parameter(), Parameter::Effect(Effect::WallBias));
    let mut x = JointPoint {
        ogden: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
        geometry: Geometry::as_modelled(),
        effects: Effects::default(),
    };
    assert_eq!((x.get(a), x.get(b)), (0.0, 0.0));
    x.set(b, 1.2).unwrap();
    x.set(a, -0.3).unwrap();
    let w = x.geometry.wall_law.unwrap();
    assert_eq!((w.offset_mm, w.inverse_cavity_mm2), (-0.3, 1.2));
    let c = 92.0 / 13.0 - 1.0 - 2.0 * 2.4;
    assert!((b.design_factor(&x.geometry, 13, 2.4) - 1.0 / c).abs() < 1e-12);
    assert_eq!(a.design_factor(&x.geometry, 13, 2.4), 1.0);
    assert_eq!(bounds(b, 0.0), (-3.0, 3.0));
}

/// The mesh correction is the fine table minus the coarse one, configuration by
/// configuration; a configuration missing from a table or a value the FE did not reach is
/// refused, naming it.
#[test]
fn the_mesh_correction_is_fine_minus_coarse_and_refuses_gaps() {
    use surrogate::calibrate::baseline::BaselineRow;
    use surrogate::calibrate::joint::MeshCorrection;
    let row = |n: usize, p: f64, uz: f64, uy: f64, f: f64| BaselineRow {
        n_bellows: n,
        wall_thickness_mm: 2.0,
        pressure_bar: p,
        uz_exp_mm: 0.0,
        uz_sim_mm: uz,
        uy_exp_mm: 0.0,
        uy_sim_mm: uy,
        angle_exp_deg: 0.0,
        angle_sim_deg: 2.0 * uz,
        be_mm: 0.0,
        force_exp_n: 0.0,
        force_sim_n: f,
        force_error_n: 0.0,
        error: String::new(),
    };
    let fine = [row(9, 1.0, 5.0, -20.0, 0.5), row(9, 2.0, 20.0, -45.0, 1.5)];
    // the coarse table in another order: rows are matched by configuration
    let coarse = [row(9, 2.0, 22.0, -48.0, 1.4), row(9, 1.0, 6.0, -21.0, 0.45)];
    let c = MeshCorrection::from_tables(&fine, &coarse, "fine.csv", "coarse.csv").unwrap();
    let e = c.at(9, 2.0, 2.0).unwrap();
    assert_eq!((e.uz_mm, e.uy_mm, e.angle_deg), (-2.0, 3.0, -4.0));
    assert!((e.force_n - 0.1).abs() < 1e-12);
    let e = c.at(9, 2.0, 1.0).unwrap();
    assert_eq!((e.uz_mm, e.uy_mm), (-1.0, 1.0));
    assert!(c.at(11, 2.0, 1.0).is_none());
    assert!((c.mean_tip_mm() - (13f64.sqrt() + 2f64.sqrt()) / 2.0).abs() < 1e-12);
    let err = MeshCorrection::from_tables(&fine[..1], &coarse, "fine.csv", "coarse.csv")
        .unwrap_err()
        .to_string();
    assert!(err.contains("fine.csv") && err.contains("P = 2"), "{err}");
    let mut failed = coarse.clone();
    failed[1].force_sim_n = f64::NAN;
    let err = MeshCorrection::from_tables(&fine, &failed, "fine.csv", "coarse.csv")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("force_sim_n") && err.contains("coarse.csv: N = 9, T = 2, P = 1"),
        "{err}"
    );
}

/// With a mesh correction, every FE value of a row and its residual carry the correction;
/// the Jacobian stays the coarse mesh's.
#[test]
fn the_mesh_correction_shifts_values_and_residuals_not_the_jacobian() {
    use surrogate::calibrate::baseline::{RampSource, SweepRamp};
    use surrogate::calibrate::experiments::{BendingRecord, ForceRecord};
    use surrogate::calibrate::joint::evaluation::residuals;
    use surrogate::calibrate::joint::JointPoint;
    use surrogate::calibrate::joint::{CorrectionEntry, MeshCorrection};
    use surrogate::calibrate::joint::{JointSettings, ModelSigma};
    use surrogate::calibrate::objective::Recordings;
    use surrogate::case::OgdenSet;
    use surrogate::fe::effects::Effects;
    use surrogate::fe::mesh::{MeshLevel, MeshOptions};
    use surrogate::fe::preset::Geometry;
    use surrogate::fe::sensitivity::{
        Outputs, ParameterInfo, Sensitivities, SensitivityCost, StepSensitivities,
    };
    use surrogate::fe::simulate::Mode;
    let outputs = |uz: f64, uy: f64, force: Option<f64>| Outputs {
        tip_uz_mm: uz,
        tip_uy_mm: uy,
        angle_deg: 20.0,
        markers: Vec::new(),
        force_n: force,
    };
    let mu1 = Unknown::from_name("mu1").unwrap();
    let ramp = |mode: Mode, values: Outputs, d: Outputs| SweepRamp {
        n_bellows: 9,
        wall_thickness_mm: 2.0,
        mode,
        steps: Vec::new(),
        error: String::new(),
        source: RampSource::Cache,
        sensitivities: Some(Sensitivities {
            format: "surrogate-sensitivities".into(),
            version: 1,
            mode,
            parameters: vec![ParameterInfo {
                parameter: mu1.parameter(),
                unit: "MPa".into(),
                value: 1.0,
                step: 0.0,
                how: String::new(),
            }],
            steps: vec![StepSensitivities {
                pressure_bar: 1.0,
                values,
                derivatives: vec![d],
            }],
            cost: SensitivityCost::default(),
        }),
    };
    let ramps = [
        ramp(
            Mode::Bending,
            outputs(8.0, -30.0, None),
            outputs(-2.0, 4.0, None),
        ),
        ramp(
            Mode::Force,
            outputs(0.0, 0.0, Some(0.6)),
            outputs(0.0, 0.0, Some(-0.5)),
        ),
    ];
    let rec = Recordings {
        bending: vec![BendingRecord {
            n_bellows: 9,
            wall_thickness_mm: 2.0,
            pressure_bar: 1.0,
            tip_uz_mm: 7.0,
            tip_uy_mm: -31.0,
            angle_deg: 20.0,
            angle_std_deg: 0.0,
        }],
        force: vec![ForceRecord {
            n_bellows: 9,
            wall_thickness_mm: 2.0,
            pressure_bar: 1.0,
            force_n: 0.5,
            force_std_n: 0.0,
        }],
        ..Recordings::default()
    };
    let mut s = JointSettings {
        unknowns: vec![mu1],
        start: JointPoint {
            ogden: OgdenSet::from_array([1.0, 8.0, -1.4, -0.5]),
            geometry: Geometry::as_modelled(),
            effects: Effects::default(),
        },
        mesh: MeshOptions::level(MeshLevel::Coarse),
        max_sweeps: 1,
        lambda0: 1e-2,
        max_step: 0.1,
        model_sigma: ModelSigma {
            tip_mm: 2.0,
            force_n: 0.1,
        },
        cache: None,
        warm_start: false,
        exclude: Vec::new(),
        correction: None,
    };
    let plain = residuals(&s, &rec, &s.start, &ramps);
    s.correction = Some(MeshCorrection {
        fine: "standard.csv".into(),
        coarse: "coarse.csv".into(),
        entries: vec![CorrectionEntry {
            n_bellows: 9,
            wall_thickness_mm: 2.0,
            pressure_bar: 1.0,
            uz_mm: -1.0,
            uy_mm: 3.0,
            angle_deg: -2.0,
            force_n: 0.15,
        }],
    });
    let corrected = residuals(&s, &rec, &s.start, &ramps);
    assert_eq!(plain.r.len(), 3);
    // Uz 8 − 7 = 1 → 0 after −1; Uy −30 + 31 = 1 → 4 after +3; force 0.1 → 0.25
    let expect_plain = [1.0 / 2.0, 1.0 / 2.0, 0.1 / 0.1];
    let expect_corrected = [0.0, 4.0 / 2.0, 0.25 / 0.1];
    for i in 0..3 {
        assert!((plain.r[i] - expect_plain[i]).abs() < 1e-12, "{}", plain.r);
        assert!(
            (corrected.r[i] - expect_corrected[i]).abs() < 1e-12,
            "{}",
            corrected.r
        );
    }
    assert_eq!(plain.j, corrected.j);
    let row = &corrected.rows[0];
    assert_eq!(
        (row.uz_mm[1], row.uy_mm[1], row.angle_deg[1]),
        (7.0, -27.0, 18.0)
    );
    assert!((row.force_n[1] - 0.75).abs() < 1e-12);
    assert!((row.be_mm - 4.0).abs() < 1e-12, "{}", row.be_mm);
}
