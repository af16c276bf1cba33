//! The sparse Gaussian process (`GpParams::inducing`): its accuracy on the synthetic
//! generator against the exact process and a subset of the data, its determinism, and the
//! training setting that records it in the model. (Its mean equals the exact process's on
//! every point: the unit test of `gp/fit.rs`; its Jacobian: `rom_gradients`.)
use surrogate::case::{raw_features, FeatureScaler};
use surrogate::rom::regression::gp::{Gp, GpParams};
use surrogate::rom::regression::{Data, Regressor, RegressorKind};
use surrogate::rom::synthetic::{response, sample_cases, SyntheticConfig};
use surrogate::rom::{train, TrainConfig, Q_ANGLE, Q_FORCE, Q_TIP_UZ};

use crate::rom_common;

/// A regression set of the synthetic generator: scaled features of `n_cases` cases (training
/// cases first, `n_train` of them; the scaler fitted to them) and, centred on the training
/// mean, tip Uz, angle and force at 1, 2 and 3 bar.
struct Set {
    x: Vec<f64>,
    y: Vec<f64>,
    d: usize,
    m: usize,
    n_train: usize,
}

impl Set {
    fn synthetic(n_train: usize, n_cases: usize) -> Set {
        let cases = sample_cases(&SyntheticConfig {
            n_cases,
            seed: 31,
            ..Default::default()
        });
        let z: Vec<_> = cases.iter().map(raw_features).collect();
        let scaler = FeatureScaler::fit(&z[..n_train]);
        let d = scaler.dim();
        let mut x = vec![0.0; n_cases * d];
        for (i, zi) in z.iter().enumerate() {
            scaler.scale_into(zi, &mut x[i * d..(i + 1) * d]);
        }
        let mut y: Vec<f64> = cases
            .iter()
            .flat_map(|c| {
                [1.0, 2.0, 3.0].into_iter().flat_map(move |p| {
                    let v = response(c, p);
                    [v[Q_TIP_UZ], v[Q_ANGLE], v[Q_FORCE]]
                })
            })
            .collect();
        let m = 9;
        for c in 0..m {
            let mean = (0..n_train).map(|i| y[i * m + c]).sum::<f64>() / n_train as f64;
            (0..n_cases).for_each(|i| y[i * m + c] -= mean);
        }
        Set {
            x,
            y,
            d,
            m,
            n_train,
        }
    }

    /// The first `n` training cases.
    fn train(&self, n: usize) -> Data<'_> {
        Data {
            x: &self.x[..n * self.d],
            y: &self.y[..n * self.m],
            n,
            d: self.d,
            m: self.m,
            weights: &[],
        }
    }

    /// RMSE over the held-out cases of each output, relative to the output's RMS there.
    fn held_out_error(&self, gp: &Gp) -> Vec<f64> {
        let (d, m) = (self.d, self.m);
        let n_test = self.x.len() / d - self.n_train;
        let mut scratch = vec![0.0; gp.scratch_len()];
        let mut out = vec![0.0; m];
        let (mut se, mut ss) = (vec![0.0; m], vec![0.0; m]);
        for i in self.n_train..self.n_train + n_test {
            gp.predict_into(&self.x[i * d..(i + 1) * d], &mut out, &mut scratch);
            for c in 0..m {
                let truth = self.y[i * m + c];
                se[c] += (out[c] - truth).powi(2);
                ss[c] += truth * truth;
            }
        }
        se.iter().zip(&ss).map(|(e, s)| (e / s).sqrt()).collect()
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// On 160 synthetic cases, 80 inducing points: the held-out error is within 3 times the
/// exact process's on all 160, and at most 0.7 times that of the exact process on the first 80
/// cases (a random subset of the same size: the cases are drawn at random).
#[test]
fn sparse_gp_on_half_the_points_is_close_to_exact_and_beats_a_subset() {
    let (n, k) = (160, 80);
    let set = Set::synthetic(n, n + 200);
    let exact = Gp::fit(&set.train(n), &GpParams::default()).unwrap();
    let sparse = Gp::fit(
        &set.train(n),
        &GpParams {
            inducing: Some(k),
            ..Default::default()
        },
    )
    .unwrap();
    let subset = Gp::fit(&set.train(k), &GpParams::default()).unwrap();
    assert_eq!((exact.n, sparse.n, subset.n), (n, k, k));
    // the same hyperparameters: the sparse fit changes the weights only
    assert_eq!(sparse.hyperparameters(), exact.hyperparameters());
    let (e_exact, e_sparse, e_subset) = (
        set.held_out_error(&exact),
        set.held_out_error(&sparse),
        set.held_out_error(&subset),
    );
    eprintln!(
        "relative held-out RMSE: exact {:.2e}, sparse {:.2e}, subset {:.2e}",
        mean(&e_exact),
        mean(&e_sparse),
        mean(&e_subset)
    );
    assert!(
        mean(&e_sparse) <= 3.0 * mean(&e_exact),
        "sparse {e_sparse:?} vs exact {e_exact:?}"
    );
    assert!(
        mean(&e_sparse) <= 0.7 * mean(&e_subset),
        "sparse {e_sparse:?} vs subset {e_subset:?}"
    );
}

/// The same data and settings give the same process bit for bit (inducing points, weights,
/// variances, factor), with one kernel and with one per column group.
#[test]
fn sparse_gp_fit_is_deterministic() {
    let set = Set::synthetic(90, 90);
    for groups in [vec![], vec![0, 3, 6, 9]] {
        let params = GpParams {
            inducing: Some(40),
            groups,
            ..Default::default()
        };
        let a = Gp::fit(&set.train(90), &params).unwrap();
        let b = Gp::fit(&set.train(90), &params).unwrap();
        assert_eq!(a.n, 40);
        assert_eq!(a.x, b.x);
        assert_eq!(a.alpha, b.alpha);
        assert_eq!(a.sigma2, b.sigma2);
        assert_eq!(a, b);
    }
}

/// The inducing points are training inputs, and at least as many as the points give the
/// exact process; fewer than twice the inputs is an error naming the setting.
#[test]
fn inducing_points_are_training_inputs_and_too_few_are_refused() {
    let set = Set::synthetic(50, 50);
    let d = set.d;
    let sparse = Gp::fit(
        &set.train(50),
        &GpParams {
            inducing: Some(20),
            ..Default::default()
        },
    )
    .unwrap();
    for zi in sparse.x.chunks_exact(d) {
        assert!(set.x.chunks_exact(d).any(|xi| xi == zi), "{zi:?}");
    }
    let exact = Gp::fit(&set.train(50), &GpParams::default()).unwrap();
    for k in [50, 60] {
        let all = GpParams {
            inducing: Some(k),
            ..Default::default()
        };
        assert_eq!(Gp::fit(&set.train(50), &all).unwrap(), exact, "k = {k}");
    }
    let too_few = GpParams {
        inducing: Some(2 * d - 1),
        ..Default::default()
    };
    let e = Gp::fit(&set.train(50), &too_few).unwrap_err().to_string();
    assert!(
        e.contains("GP inducing points") && e.contains(&format!("{}", 2 * d - 1)),
        "{e}"
    );
}

/// `TrainConfig::gp.inducing` reaches the final fit (a GP on that many points) and the
/// model's training information, and the model survives a save and load.
#[test]
fn training_with_inducing_points_records_them() {
    let cases = rom_common::synthetic_cases(40, 7);
    let cfg = TrainConfig {
        folds: 3,
        only: Some(RegressorKind::GP),
        gp: GpParams {
            inducing: Some(20),
            ..Default::default()
        },
        ..Default::default()
    };
    let model = train(&cases, "synthetic", 0, &cfg, &|_, _| {})
        .unwrap()
        .surrogate;
    assert_eq!(model.training.gp_inducing, Some(20));
    assert_eq!(model.regressors.get::<Gp>().unwrap().n, 20);
    let path = std::env::temp_dir().join(format!("sparse_gp_{}.json", std::process::id()));
    model.save(&path).unwrap();
    let loaded = surrogate::rom::Surrogate::load(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(loaded.training.gp_inducing, Some(20));
    assert_eq!(loaded.regressors.get::<Gp>().unwrap().n, 20);
}
