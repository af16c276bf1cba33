//! The unit tests of `src/diagnose/discrimination.rs`.

use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use surrogate::diagnose::discrimination::*;

struct Parts {
    residual: DVector<f64>,
    nuisance: DMatrix<f64>,
    signatures: Vec<DVector<f64>>,
    items: Vec<ItemRow>,
}

impl Parts {
    fn build(&self) -> Discrimination {
        Discrimination::new(
            &self.residual,
            self.nuisance.clone(),
            self.signatures.clone(),
            self.items.clone(),
        )
        .unwrap()
    }
}

/// `n` recorded rows, 4 nuisance columns, `m` candidates and `k` measurements, all
/// random; the residual along candidate 0 with noise.
fn random_parts(seed: u64, n: usize, m: usize, k: usize) -> Parts {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut g = move || rng.gen_range(-1.0..1.0);
    let nuisance = DMatrix::from_fn(n, 4, |_, _| g());
    let signatures: Vec<DVector<f64>> = (0..m).map(|_| DVector::from_fn(n, |_, _| g())).collect();
    let residual = &signatures[0] * 0.8 + DVector::from_fn(n, |_, _| 0.3 * g());
    let items = (0..k)
        .map(|_| ItemRow {
            nuisance: (0..4).map(|_| g()).collect(),
            candidates: (0..m).map(|_| g()).collect(),
        })
        .collect();
    Parts {
        residual,
        nuisance,
        signatures,
        items,
    }
}

/// `T_ab` by brute force: the rows stacked, the rival and the nuisance fitted by SVD.
fn brute_force(p: &Parts, d: &Discrimination, a: usize, b: usize, chosen: &[usize]) -> f64 {
    let n = p.residual.len();
    let rows = n + chosen.len();
    let g = DMatrix::from_fn(rows, 5, |i, j| match (i < n, j < 4) {
        (true, true) => p.nuisance[(i, j)],
        (true, false) => p.signatures[b][i],
        (false, true) => p.items[chosen[i - n]].nuisance[j],
        (false, false) => p.items[chosen[i - n]].candidates[b],
    });
    let v = DVector::from_fn(rows, |i, _| {
        d.size(a)
            * if i < n {
                p.signatures[a][i]
            } else {
                p.items[chosen[i - n]].candidates[a]
            }
    });
    // least squares through the SVD, singular values below 10⁻¹² dropped
    let svd = thin_svd(&g);
    let ut_v = svd.u().transpose() * &v;
    let beta = DVector::from_fn(g.ncols(), |r, _| {
        (0..svd.s().len())
            .filter(|&k| svd.s()[k] > 1e-12)
            .map(|k| svd.v()[(r, k)] * ut_v[k] / svd.s()[k])
            .sum()
    });
    (v - g * beta).norm_squared()
}

#[test]
fn the_lack_of_fit_is_that_of_the_rival_refitted_on_the_stacked_rows() {
    let p = random_parts(1, 40, 3, 12);
    let d = p.build();
    for chosen in [vec![], vec![2], vec![0, 5, 11]] {
        for (a, b) in [(0, 1), (1, 0), (2, 0)] {
            let fast = d.lack_of_fit(a, b, &chosen);
            let slow = brute_force(&p, &d, a, b, &chosen);
            assert!(
                (fast - slow).abs() <= 1e-9 * slow.max(1e-12),
                "{a} {b} {chosen:?}: {fast} against {slow}"
            );
        }
    }
    // the size is the joint fit with the nuisance: the residual along candidate 0 at 0.8
    assert!((d.size(0) - 0.8).abs() < 0.2, "{}", d.size(0));
}

/// Candidates 0 and 1 coincide on the recorded rows (1 is twice 0) and at every
/// measurement but `odd`, where 1 moves by one σ more.
fn coinciding(odd: usize) -> Parts {
    let mut p = random_parts(2, 50, 2, 30);
    p.signatures[1] = &p.signatures[0] * 2.0;
    for (i, it) in p.items.iter_mut().enumerate() {
        it.candidates[1] = 2.0 * it.candidates[0] + if i == odd { 1.0 } else { 0.0 };
    }
    p
}

#[test]
fn the_measurement_where_two_coinciding_signatures_differ_is_chosen() {
    for odd in [3, 17, 29] {
        let d = coinciding(odd).build();
        let before = d.separation(0, 1, &[]);
        assert!(before < 1e-10, "{before}");
        assert_eq!(d.best_single(0, 1).map(|b| b.0), Some(odd));
        let picks = d.greedy(0, &[1], 3);
        assert_eq!(picks[0].item, odd, "{picks:?}");
        assert!(picks[0].separations[0] > 1e-3, "{picks:?}");
    }
}

#[test]
fn the_gain_falls_as_the_noise_grows() {
    let gain = |sigma: f64| {
        let mut p = random_parts(3, 40, 3, 20);
        for it in &mut p.items {
            it.nuisance.iter_mut().for_each(|v| *v /= sigma);
            it.candidates.iter_mut().for_each(|v| *v /= sigma);
        }
        let d = p.build();
        let (_, after) = d.best_single(0, 1).expect("a measurement separates them");
        after - d.separation(0, 1, &[])
    };
    let gains: Vec<f64> = [0.25, 0.5, 1.0, 2.0, 4.0].map(gain).to_vec();
    assert!(gains.windows(2).all(|w| w[1] < w[0]), "{gains:?}");
    // the same with the coinciding pair: the single separating measurement, noisier
    let sep = |sigma: f64| {
        let mut p = coinciding(17);
        p.items[17].nuisance.iter_mut().for_each(|v| *v /= sigma);
        p.items[17].candidates.iter_mut().for_each(|v| *v /= sigma);
        p.build().separation(0, 1, &[17])
    };
    assert!(
        sep(0.5) > sep(1.0) && sep(1.0) > sep(3.0),
        "{} {} {}",
        sep(0.5),
        sep(1.0),
        sep(3.0)
    );
}

#[test]
fn a_record_is_chosen_with_all_its_rows() {
    let d = random_parts(11, 30, 3, 8).build();
    // every measurement its own record: the plain greedy choice
    let each: Vec<usize> = (0..8).collect();
    assert_eq!(
        d.greedy_records(0, &[1, 2], 2, &each),
        d.greedy(0, &[1, 2], 2)
    );
    // measurements in pairs: a pick adds both rows, and names the pair's first
    let pairs: Vec<usize> = (0..8).map(|i| i / 2).collect();
    let picks = d.greedy_records(0, &[1, 2], 2, &pairs);
    assert!(!picks.is_empty());
    let mut rows = Vec::new();
    for p in &picks {
        assert_eq!(p.item % 2, 0, "{picks:?}");
        rows.extend([p.item, p.item + 1]);
        for (j, rival) in [1, 2].into_iter().enumerate() {
            let want = d.separation(0, rival, &rows);
            assert!((p.separations[j] - want).abs() <= 1e-9 * want.abs().max(1.0));
        }
    }
}

#[test]
fn k_greedy_measurements_are_never_worse_than_any_single_one() {
    for seed in [4, 5, 6] {
        let d = random_parts(seed, 30, 4, 25).build();
        let rivals = [1, 2, 3];
        let picks = d.greedy(0, &rivals, 3);
        assert_eq!(picks.len(), 3, "{picks:?}");
        let worst = |s: &[f64]| s.iter().copied().fold(f64::INFINITY, f64::min);
        let three = worst(&picks[2].separations);
        for i in 0..d.items() {
            let single: Vec<f64> = rivals.iter().map(|&j| d.separation(0, j, &[i])).collect();
            assert!(three >= worst(&single) * (1.0 - 1e-12), "item {i}");
        }
        // each pick raises the weakest separation or leaves it, never lowers one
        for w in picks.windows(2) {
            assert!(w[1]
                .separations
                .iter()
                .zip(&w[0].separations)
                .all(|(b, a)| *b >= a * (1.0 - 1e-12)));
        }
        // the separations reported are those of the chosen set
        let chosen: Vec<usize> = picks.iter().map(|p| p.item).collect();
        assert!((d.separation(0, 2, &chosen) - picks[2].separations[1]).abs() < 1e-9);
    }
}

#[test]
fn rescaling_a_signature_changes_nothing() {
    let base = random_parts(7, 35, 3, 20);
    let d = base.build();
    let picks = d.greedy(0, &[1, 2], 3);
    for c in [-0.37, 12.5] {
        let mut p = random_parts(7, 35, 3, 20);
        p.signatures[1] *= c;
        p.items.iter_mut().for_each(|it| it.candidates[1] *= c);
        let scaled = p.build();
        assert!((scaled.size(1) * c - d.size(1)).abs() < 1e-9 * d.size(1).abs());
        let again = scaled.greedy(0, &[1, 2], 3);
        assert_eq!(
            again.iter().map(|p| p.item).collect::<Vec<_>>(),
            picks.iter().map(|p| p.item).collect::<Vec<_>>()
        );
        for (x, y) in again.iter().zip(&picks) {
            for (a, b) in x.separations.iter().zip(&y.separations) {
                assert!((a - b).abs() <= 1e-8 * b.abs().max(1e-12), "{a} {b}");
            }
        }
        assert!(
            (scaled.lack_of_fit(1, 0, &[4]) - d.lack_of_fit(1, 0, &[4])).abs()
                <= 1e-8 * d.lack_of_fit(1, 0, &[4])
        );
    }
}
