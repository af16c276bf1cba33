//! The scalar fast path (POD folded into the regression weights, kernel vector by feature)
//! gives the general path's values.
use surrogate::case::Query;
use surrogate::rom::fast::kernel_vector;
use surrogate::rom::regression::gp::Gp;
use surrogate::rom::regression::RegressorKind;
use surrogate::rom::Surrogate;

use crate::rom_common;

fn queries() -> Vec<Query> {
    let cases = rom_common::synthetic_cases(10, 99);
    let mut out = Vec::new();
    for c in &cases.cases {
        for p in [0.0, 0.1, 0.4, 1.0, 1.9, 2.75, 3.4, 3.5, 4.0] {
            out.push(Query::from_case(&c.inputs, p));
        }
    }
    out
}

/// Largest |fast − general| relative to each scalar's largest |value|.
#[allow(clippy::needless_range_loop)]
fn max_gap(m: &Surrogate) -> f64 {
    let mut fast = m.new_prediction();
    let mut general = m.new_prediction();
    let mut worst: f64 = 0.0;
    let qs: Vec<Query> = queries()
        .into_iter()
        .filter(|q| m.check_query(q).is_ok())
        .collect();
    assert!(qs.len() > 50);
    let mut scale = [1e-12f64; 22];
    for q in &qs {
        m.predict_into(q, &mut general).unwrap();
        for k in 18..22 {
            scale[k] = scale[k].max(general.values[k].abs());
        }
    }
    for q in &qs {
        m.predict_scalars_into(q, &mut fast).unwrap();
        m.predict_scalars_unfolded_into(q, &mut general).unwrap();
        for k in 18..22 {
            assert!(fast.values[k].is_finite());
            worst = worst.max((fast.values[k] - general.values[k]).abs() / scale[k]);
        }
    }
    worst
}

#[test]
fn folded_scalar_path_matches_the_general_path() {
    let gp = rom_common::small_model(Some(RegressorKind::GP));
    let poly = rom_common::small_model(Some(RegressorKind::POLY));
    // mixed: both regressors are fitted on every coefficient, so a block may switch
    let mut mixed = gp.clone();
    let b = mixed.output_block[19];
    mixed.blocks[b].regressor = RegressorKind::POLY;
    let mixed = Surrogate {
        derived: Default::default(),
        ..mixed
    };
    let grouped = rom_common::grouped_model();
    assert!(grouped.regressors.get::<Gp>().unwrap().n_groups() == grouped.blocks.len());
    for (name, m) in [
        ("gp", &gp),
        ("poly", &poly),
        ("mixed", &mixed),
        ("grouped", &grouped),
    ] {
        let gap = max_gap(m);
        println!("{name}: max relative gap {gap:e}");
        assert!(gap < 1e-12, "{name}: fast path off by {gap:e}");
    }
    // a perturbed weight changes the fast path too: it is not reading a cached answer
    let mut other = gp.clone();
    let gp_of_other = other.regressors.get_mut::<Gp>().unwrap();
    gp_of_other.alpha.iter_mut().for_each(|a| *a *= 1.01);
    let other = Surrogate {
        derived: Default::default(),
        ..other
    };
    let q = queries()[3];
    let (mut a, mut b) = (gp.new_prediction(), other.new_prediction());
    gp.predict_scalars_into(&q, &mut a).unwrap();
    other.predict_scalars_into(&q, &mut b).unwrap();
    assert_ne!(a.values[18], b.values[18]);
}

#[test]
fn kernel_vector_by_feature_is_bit_identical() {
    let model = rom_common::small_model(Some(RegressorKind::GP));
    let m = model.regressors.get::<Gp>().unwrap();
    let (n, d) = (m.n, m.d);
    let mut xs_t = vec![0.0; n * d];
    for i in 0..n {
        for j in 0..d {
            xs_t[j * n + i] = m.xs[i * d + j];
        }
    }
    for (s, x0) in [-1.0, -0.3, 0.0, 0.45, 1.2].iter().enumerate() {
        let x: Vec<f64> = (0..d).map(|j| x0 + 0.1 * (j + s) as f64).collect();
        let (mut k1, mut k2) = (vec![0.0; n], vec![0.0; n]);
        m.kernel_vector_into(0, &x, &mut k1);
        kernel_vector(&xs_t, &m.inv_len, &x, &mut k2);
        assert_eq!(k1, k2);
    }
}
