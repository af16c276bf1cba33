//! The unit tests of `src/diagnose/refit/rank.rs`: candidates ranked by their FE-confirmed
//! refits, with stand-in FE models.

use super::refit_confirm::{coarse_model_and_material, g, pattern, planted, stand_in_fe};
use surrogate::case::OgdenSet;
use surrogate::diagnose::refit::{
    confirm_with, fit_rows, rank_confirmed, vuong_z, FeEvaluation, FeRankSettings, Picked, Refit,
    RefitSettings, Rows,
};
use surrogate::diagnose::DiagnoseError;
use surrogate::fe::effects::Effect;
use surrogate::rom::Surrogate;

/// The rows of `rows`' recordings seen through another effect's pattern `w`.
fn through(rows: &Rows, w: [f64; 3]) -> Rows {
    let mut r = rows.clone();
    for (c, d) in r.cells.iter().zip(r.d.iter_mut()) {
        d[0] = pattern(
            w,
            c.n_bellows,
            c.wall_thickness_mm,
            c.pressure_bar,
            c.output,
        );
    }
    r
}

/// A deterministic scatter of about ±0.3 σ on every recording.
fn scatter(rows: &mut Rows) {
    for (i, c) in rows.cells.iter_mut().enumerate() {
        c.recorded += 0.3 * ((i as f64 * 2.399).sin());
    }
}

/// `rows` refitted with `effect` and confirmed by the stand-in FE whose response to the
/// effect's value `θ` is `response(θ)` along the rows' pattern.
fn confirmed(
    rows: &Rows,
    model: &Surrogate,
    m: &OgdenSet,
    effect: Effect,
    response: fn(f64) -> f64,
) -> Refit {
    let mut s = RefitSettings::new(vec![effect]);
    s.held_out = false;
    let first = fit_rows(rows, model, m, &s).unwrap();
    let mut fe = |mat: &OgdenSet, v: &[f64]| -> Result<FeEvaluation, DiagnoseError> {
        Ok((stand_in_fe(rows, model, mat, response(v[0])), 0, Vec::new()))
    };
    confirm_with(rows, model, first, &s, 6, 0.01, &mut fe).unwrap()
}

fn picked(linear_rank: usize, effect: Effect) -> Picked {
    Picked {
        linear_rank,
        effect: effect.name().to_string(),
        unit: String::new(),
        linear_delta_chi2: 0.0,
    }
}

#[test]
fn the_fe_ranking_puts_the_true_effect_first_where_the_linearised_ranking_did_not() {
    let (model, m) = coarse_model_and_material();
    // recordings with a nonlinear effect along one pattern, and a rival along another
    let w_true = [8.0, -3.0, 1.5];
    let mut rows = planted(&model, &m, 0.0, w_true, g(0.1));
    scatter(&mut rows);
    let rival = through(&rows, [-2.0, 1.0, 4.0]);
    let truth = confirmed(&rows, &model, &m, Effect::PressureLoss, g);
    let other = confirmed(&rival, &model, &m, Effect::WallBias, |t| t);
    // the linearised ranking (given) put the rival first
    let p = [picked(1, Effect::WallBias), picked(2, Effect::PressureLoss)];
    let r = rank_confirmed(
        &p,
        &[other, truth],
        &FeRankSettings::default(),
        0.01,
        "coarse",
    )
    .unwrap();
    assert_eq!(r.candidates[0].effect, "pressure_loss", "{}", r.verdict);
    assert!(
        (r.candidates[0].value - 0.1).abs() < 5e-3,
        "{:?}",
        r.candidates[0]
    );
    assert!(r.candidates[0].fe_chi2 < r.candidates[1].fe_chi2);
    assert!(!r.agrees, "{}", r.verdict);
    let z = r.candidates[1].vuong_z.unwrap();
    assert!(z > 1.96 && !r.candidates[1].tied_with_first, "z = {z}");
    assert!(r
        .verdict
        .contains("reverses the linearised one, which put wall_bias first"));
    assert!(r.verdict.contains("significantly better"), "{}", r.verdict);
    assert_eq!(r.n_cells, rows.cells.len());
}

#[test]
fn two_candidates_the_fe_fits_equally_well_stay_tied() {
    let (model, m) = coarse_model_and_material();
    let w = [8.0, -3.0, 1.5];
    let mut rows = planted(&model, &m, 0.0, w, g(0.1));
    scatter(&mut rows);
    // the same response along the same pattern: no recording prefers one
    let a = confirmed(&rows, &model, &m, Effect::PressureLoss, g);
    let b = confirmed(&rows, &model, &m, Effect::WallBias, g);
    let p = [picked(1, Effect::PressureLoss), picked(3, Effect::WallBias)];
    let r = rank_confirmed(&p, &[a, b], &FeRankSettings::default(), 0.01, "coarse").unwrap();
    assert!(r.candidates[1].tied_with_first, "{}", r.verdict);
    assert!(r.verdict.contains("cannot tell"), "{}", r.verdict);
}

#[test]
fn the_likelihood_ratio_z_has_the_sign_of_the_better_fit_and_refuses_too_few_cells() {
    let a = [0.1, -0.2, 0.3, 0.0, -0.1];
    let b = [1.0, -1.5, 2.0, 0.8, -1.2];
    assert!(vuong_z(&a, &b).unwrap() > 0.0);
    assert!(vuong_z(&b, &a).unwrap() < 0.0);
    assert_eq!(vuong_z(&a, &a), None);
    assert_eq!(vuong_z(&a[..1], &b[..1]), None);
    assert_eq!(vuong_z(&a, &b[..3]), None);
    // settings and lengths are checked
    let p = [picked(1, Effect::WallBias)];
    let bad = FeRankSettings {
        top: 1,
        ..FeRankSettings::default()
    };
    assert!(rank_confirmed(&p, &[], &bad, 0.5, "coarse").is_err());
    assert!(rank_confirmed(&p, &[], &FeRankSettings::default(), 0.5, "coarse").is_err());
}
