//! Every analytic derivative against central finite differences: both regressors (one generic
//! check; the GP exact and sparse) and the surrogate's Jacobian with respect to T, P and the
//! Ogden parameters.
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::case::{OgdenSet, Query};
use surrogate::rom::regression::gp::{Gp, GpParams};
use surrogate::rom::regression::poly::{Poly, PolyParams};
use surrogate::rom::regression::{Data, Regressor, RegressorKind};
use surrogate::rom::surrogate::GRAD_INPUT_NAMES;
use surrogate::rom::Jacobian;

use crate::rom_common;

/// Generic finite-difference check of `jacobian_into` (and of its values vs `predict_into`).
pub(crate) fn check_regressor<R: Regressor>(r: &R, x: &[f64], name: &str) {
    let (d, m) = (x.len(), r.n_outputs());
    let mut scratch = vec![0.0; r.scratch_len()];
    let (mut out, mut jac) = (vec![0.0; m], vec![0.0; m * d]);
    r.jacobian_into(x, &mut out, &mut jac, &mut scratch);
    let mut plain = vec![0.0; m];
    r.predict_into(x, &mut plain, &mut scratch);
    // same values up to summation order
    for (a, b) in out.iter().zip(&plain) {
        assert!(
            (a - b).abs() <= 1e-10 * (1.0 + b.abs()),
            "{name}: jacobian_into value {a} differs from predict_into {b}"
        );
    }
    // h balances truncation (h²) against round-off of the GP's large weights (ε Σ|kα| / h)
    let h = 1e-4;
    for j in 0..d {
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[j] += h;
        xm[j] -= h;
        let (mut fp, mut fm) = (vec![0.0; m], vec![0.0; m]);
        r.predict_into(&xp, &mut fp, &mut scratch);
        r.predict_into(&xm, &mut fm, &mut scratch);
        for c in 0..m {
            let fd = (fp[c] - fm[c]) / (2.0 * h);
            let an = jac[c * d + j];
            assert!(
                (fd - an).abs() <= 1e-6 * (1.0 + an.abs()),
                "{name}: d out{c}/dx{j}: fd {fd} vs {an}"
            );
        }
    }
}

#[test]
fn regressor_jacobians_match_finite_differences() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let (n, d, m) = (30, 3, 2);
    let x: Vec<f64> = (0..n * d).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let y: Vec<f64> = (0..n)
        .flat_map(|i| {
            let p = &x[i * d..(i + 1) * d];
            [(1.5 * p[0]).sin() + p[1] * p[2], (p[0] - p[2]).exp()]
        })
        .collect();
    let data = Data {
        x: &x,
        y: &y,
        n,
        d,
        m,
        weights: &[],
    };
    let gp = Gp::fit(&data, &GpParams::default()).unwrap();
    // a kernel per output column
    let grouped = Gp::fit(
        &data,
        &GpParams {
            groups: vec![0, 1, 2],
            ..Default::default()
        },
    )
    .unwrap();
    assert_ne!(grouped.group_inv_len(0), grouped.group_inv_len(1));
    // sparse on 12 of the 30 points, with one kernel and with a kernel per column
    let sparse = |groups: Vec<usize>| {
        let gp = Gp::fit(
            &data,
            &GpParams {
                inducing: Some(12),
                groups,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(gp.n, 12);
        gp
    };
    let (sparse, sparse_grouped) = (sparse(Vec::new()), sparse(vec![0, 1, 2]));
    let poly = Poly::fit(&data, &PolyParams::default()).unwrap();
    for t in 0..5 {
        let xq: Vec<f64> = (0..d).map(|_| rng.gen_range(-0.9..0.9)).collect();
        check_regressor(&gp, &xq, &format!("gp #{t}"));
        check_regressor(&grouped, &xq, &format!("grouped gp #{t}"));
        check_regressor(&sparse, &xq, &format!("sparse gp #{t}"));
        check_regressor(&sparse_grouped, &xq, &format!("sparse grouped gp #{t}"));
        check_regressor(&poly, &xq, &format!("poly #{t}"));
    }
}

fn check_surrogate(kind: RegressorKind) {
    let name = kind.to_string();
    check_model(&rom_common::small_model(Some(kind)), &name);
}

fn check_model(m: &surrogate::rom::Surrogate, kind: &str) {
    let base = Query {
        n: 11,
        t_mm: 1.9,
        p_bar: 1.37,
        material: OgdenSet::from_array([1.2, 3.0, -12.0, -0.55]),
    };
    let mut pred = m.new_prediction();
    let mut jac = Jacobian::default();
    m.gradient_into(&base, &mut pred, &mut jac).unwrap();
    let plain = m.predict(&base).unwrap();
    for q in 0..22 {
        assert!((pred.values[q] - plain.values[q]).abs() <= 1e-12 * (1.0 + plain.values[q].abs()));
    }
    for i in 0..GRAD_INPUT_NAMES.len() {
        let u = [
            base.t_mm,
            base.p_bar,
            base.material.mu1_mpa,
            base.material.alpha1,
            base.material.mu2_mpa,
            base.material.alpha2,
        ];
        let h = 1e-6 * (1.0 + u[i].abs());
        let at = |delta: f64| {
            let mut v = u;
            v[i] += delta;
            let qq = Query {
                n: 11,
                t_mm: v[0],
                p_bar: v[1],
                material: OgdenSet::from_array([v[2], v[3], v[4], v[5]]),
            };
            m.predict(&qq).unwrap().values
        };
        let (fp, fm) = (at(h), at(-h));
        for q in 0..22 {
            let fd = (fp[q] - fm[q]) / (2.0 * h);
            let an = jac.d[q][i];
            let scale = jac.d[q].iter().fold(1e-3f64, |a, v| a.max(v.abs()));
            assert!(
                (fd - an).abs() <= 1e-5 * scale,
                "{kind}: d q{q}/d {}: fd {fd} vs {an}",
                GRAD_INPUT_NAMES[i]
            );
        }
    }
}

#[test]
fn surrogate_gradient_matches_finite_differences_gp() {
    check_surrogate(RegressorKind::GP);
}

#[test]
fn surrogate_gradient_matches_finite_differences_kernel_per_block() {
    check_model(&rom_common::grouped_model(), "kernel per block");
}

#[test]
fn surrogate_gradient_matches_finite_differences_sparse_gp() {
    check_model(&rom_common::sparse_model(), "sparse gp");
}

#[test]
fn surrogate_gradient_matches_finite_differences_poly() {
    check_surrogate(RegressorKind::POLY);
}
