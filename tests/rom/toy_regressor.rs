//! A regressor from outside the crate: one type implementing `Regressor` (a constant-plus-linear
//! least-squares fit, `y_c = a_c + Σ_j b_jc x_j`) and one registry line. It is trained through
//! `train`, saved, loaded back through the same registry and evaluated; without the line the
//! model file is refused, and the embedded predictor, which cannot evaluate it, refuses its
//! export with a named error.
use std::ops::Range;

use serde::{Deserialize, Serialize};
use surrogate::case::{raw_features, Query};
use surrogate::rom::export::EmbeddedTables;
use surrogate::rom::regression::{Data, Registry, Regressor, RegressorKind, TrainingSettings};
use surrogate::rom::{RomError, Surrogate, TrainConfig};

use crate::rom_common;

/// `y_c = a_c + Σ_j b_jc x_j`, fitted by least squares (normal equations).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Affine {
    d: usize,
    m: usize,
    /// Row 0: the constants `a`; row `1 + j`: the slopes `b_j`, `(d + 1) × m`.
    coef: Vec<f64>,
}

impl Regressor for Affine {
    const NAME: &'static str = "affine";
    type Params = ();

    fn fit(data: &Data<'_>, _: &()) -> Result<Self, RomError> {
        let (n, d, m, p) = (data.n, data.d, data.m, data.d + 1);
        if n < p {
            return Err(RomError::InsufficientData(format!(
                "{n} points, {p} needed"
            )));
        }
        let row = |i: usize| std::iter::once(1.0).chain(data.x[i * d..(i + 1) * d].iter().copied());
        // [ΦᵀΦ | ΦᵀY], then Gauss-Jordan elimination with partial pivoting
        let w = p + m;
        let mut a = vec![0.0; p * w];
        for i in 0..n {
            let phi: Vec<f64> = row(i).collect();
            for r in 0..p {
                for c in 0..p {
                    a[r * w + c] += phi[r] * phi[c];
                }
                for c in 0..m {
                    a[r * w + p + c] += phi[r] * data.y[i * m + c];
                }
            }
        }
        for k in 0..p {
            let piv = (k..p)
                .max_by(|&i, &j| a[i * w + k].abs().total_cmp(&a[j * w + k].abs()))
                .unwrap_or(k);
            for c in 0..w {
                a.swap(k * w + c, piv * w + c);
            }
            let diag = a[k * w + k];
            if diag.abs() < 1e-300 {
                return Err(RomError::InsufficientData("collinear inputs".into()));
            }
            for c in 0..w {
                a[k * w + c] /= diag;
            }
            for r in (0..p).filter(|&r| r != k) {
                let f = a[r * w + k];
                for c in 0..w {
                    a[r * w + c] -= f * a[k * w + c];
                }
            }
        }
        let coef = (0..p)
            .flat_map(|r| a[r * w + p..r * w + w].to_vec())
            .collect();
        Ok(Affine { d, m, coef })
    }

    fn training_params(_: &TrainingSettings<'_>) {}

    fn n_inputs(&self) -> usize {
        self.d
    }

    fn n_outputs(&self) -> usize {
        self.m
    }

    fn scratch_len(&self) -> usize {
        0
    }

    fn predict_cols_into(&self, x: &[f64], cols: Range<usize>, out: &mut [f64], _: &mut [f64]) {
        for c in cols {
            out[c] = self.coef[c];
            for (j, xj) in x.iter().enumerate() {
                out[c] += xj * self.coef[(1 + j) * self.m + c];
            }
        }
    }

    fn jacobian_into(&self, x: &[f64], out: &mut [f64], jac: &mut [f64], s: &mut [f64]) {
        self.predict_into(x, out, s);
        for c in 0..self.m {
            for j in 0..self.d {
                jac[c * self.d + j] = self.coef[(1 + j) * self.m + c];
            }
        }
    }
}

/// The registry with the toy regressor: the one line a new regressor needs.
fn registry() -> Registry {
    Registry::builtin().with::<Affine>().unwrap()
}

#[test]
fn the_toy_fit_recovers_a_known_affine_function() {
    // y₀ = 1 + 2x₀ − 3x₁, y₁ = −0.5 + 0.25x₁ on a 4 × 4 grid
    let x: Vec<f64> = (0..16)
        .flat_map(|i| [(i % 4) as f64 / 3.0 - 0.5, (i / 4) as f64 / 3.0 - 0.5])
        .collect();
    let y: Vec<f64> = x
        .chunks(2)
        .flat_map(|p| [1.0 + 2.0 * p[0] - 3.0 * p[1], -0.5 + 0.25 * p[1]])
        .collect();
    let data = Data {
        x: &x,
        y: &y,
        n: 16,
        d: 2,
        m: 2,
        weights: &[],
    };
    let fit = Affine::fit(&data, &()).unwrap();
    let known = [1.0, -0.5, 2.0, 0.0, -3.0, 0.25];
    for (c, k) in fit.coef.iter().zip(known) {
        assert!((c - k).abs() < 1e-12, "{:?} against {known:?}", fit.coef);
    }
    let mut out = [0.0; 2];
    fit.predict_into(&[0.5, -0.25], &mut out, &mut []);
    assert!(
        (out[0] - 2.75).abs() < 1e-12 && (out[1] + 0.5625).abs() < 1e-12,
        "{out:?}"
    );
    crate::rom_gradients::check_regressor(&fit, &[0.3, -0.7], "affine");
}

#[test]
fn a_registered_regressor_is_trained_saved_loaded_and_evaluated() {
    let registry = registry();
    let affine = RegressorKind::of::<Affine>();
    let cases = rom_common::synthetic_cases(24, 3);
    let cfg = TrainConfig {
        folds: 3,
        regressors: registry.clone(),
        only: Some(affine.clone()),
        ..Default::default()
    };
    let model = surrogate::rom::train(&cases, "synthetic", 0, &cfg, &|_, _| {})
        .unwrap()
        .surrogate;
    assert_eq!(model.regressors.names(), ["gp", "poly", "affine"]);
    assert!(model.blocks.iter().all(|b| b.regressor == affine));
    assert!(model
        .validation
        .outputs
        .iter()
        .all(|o| o.source.ends_with("/affine")));

    // saved, and loaded back through the registry: the same model, the same predictions
    let path = std::env::temp_dir().join(format!("toy_regressor_{}.json", std::process::id()));
    model.save(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"affine\":{") && text.contains("\"regressor\":\"affine\""));
    let back = Surrogate::load_with(&path, &registry).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(back, model);
    assert_eq!(back.checksum().unwrap(), model.checksum().unwrap());

    // each output at a grid pressure of a training case is the POD reconstruction of the
    // affine coefficients, computed here from the toy's own tables
    let fit = back.regressors.get::<Affine>().unwrap();
    let case = &cases.cases[5];
    let j = 3;
    let q = Query::from_case(&case.inputs, back.pressures[j]);
    let mut x = vec![0.0; back.features.dim()];
    back.features
        .scale_into(&raw_features(&case.inputs), &mut x);
    let mut coef = vec![0.0; fit.m];
    fit.predict_into(&x, &mut coef, &mut []);
    let (pred, scalars) = (back.predict(&q).unwrap(), {
        let mut p = back.new_prediction();
        back.predict_scalars_into(&q, &mut p).unwrap();
        p
    });
    for qi in 0..22 {
        let b = &back.blocks[back.output_block[qi]];
        let e = j * b.pod.quantities.len() + back.output_slot[qi];
        let expected = b
            .pod
            .entry(e, &coef[b.coef_offset..b.coef_offset + b.pod.n_modes]);
        let got = pred.values[qi];
        assert!(
            (got - expected).abs() <= 1e-9 * (1.0 + expected.abs()),
            "output {qi}: {got} against {expected}"
        );
        if qi >= surrogate::rom::Q_TIP_UZ {
            assert_eq!(scalars.values[qi], got, "scalar path, output {qi}");
        }
    }
    // an affine fit to the synthetic tip deflection: near the FE value, not equal to it
    let truth = case.values[j][surrogate::rom::Q_TIP_UY];
    let err = (pred.tip_uy_mm() - truth).abs();
    assert!(
        err > 0.0 && err < 0.5 * truth.abs().max(1.0),
        "{} vs {truth}",
        pred.tip_uy_mm()
    );

    // without the registry line the file is refused, naming the regressor
    let e = Surrogate::from_json(&text, "toy.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("regressor `affine`"), "{e}");

    // the embedded predictor cannot evaluate it: export is refused with a named error
    match EmbeddedTables::<f64>::from_surrogate(&back) {
        Err(RomError::NotExportable { regressor, .. }) => assert_eq!(regressor, "affine"),
        other => panic!("expected NotExportable, got {other:?}"),
    }
}

#[test]
fn a_registry_refuses_a_name_taken_or_reserved() {
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    struct Blocks(Affine);
    impl Regressor for Blocks {
        const NAME: &'static str = "blocks";
        type Params = ();
        fn fit(data: &Data<'_>, _: &()) -> Result<Self, RomError> {
            Affine::fit(data, &()).map(Blocks)
        }
        fn training_params(_: &TrainingSettings<'_>) {}
        fn n_inputs(&self) -> usize {
            self.0.d
        }
        fn n_outputs(&self) -> usize {
            self.0.m
        }
        fn scratch_len(&self) -> usize {
            0
        }
        fn predict_cols_into(&self, x: &[f64], c: Range<usize>, o: &mut [f64], s: &mut [f64]) {
            self.0.predict_cols_into(x, c, o, s)
        }
        fn jacobian_into(&self, x: &[f64], o: &mut [f64], j: &mut [f64], s: &mut [f64]) {
            self.0.jacobian_into(x, o, j, s)
        }
    }
    assert!(registry().with::<Affine>().is_err(), "registered twice");
    assert!(
        Registry::builtin().with::<Blocks>().is_err(),
        "a model field's name"
    );
}
