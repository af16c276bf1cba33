//! The embedded predictor agrees with the library, and its module compiles with `#![no_std]`.
use surrogate::predict::{evaluate, EmbeddedError};
use surrogate::rom::export::{c_header, rust_source, EmbeddedTables, Precision};
use surrogate::rom::regression::RegressorKind;
use surrogate::rom::{Query, Surrogate};

mod rom_common;

/// Held-out queries: cases of another seed, at pressures between and on the grid nodes.
fn held_out(m: &Surrogate) -> Vec<Query> {
    let cases = rom_common::synthetic_cases(12, 4242);
    let mut out = Vec::new();
    for c in &cases.cases {
        for p in [0.0, 0.4, 1.0, 1.9, 2.75, 3.5] {
            let q = Query::from_case(&c.inputs, p);
            if m.check_query(&q).is_ok() {
                out.push(q);
            }
        }
    }
    out
}

/// Largest |embedded − library| relative to each quantity's largest |value| over the set.
fn max_relative_gap(m: &Surrogate) -> f64 {
    let tables = EmbeddedTables::<f32>::from_surrogate(m).unwrap();
    let blocks = tables.block_tables();
    let model = tables.view(&blocks);
    let queries = held_out(m);
    let mut lib = Vec::new();
    let mut emb = Vec::new();
    for q in &queries {
        lib.push(m.predict(q).unwrap().values);
        let a = q.as_array();
        let input: [f32; 7] = std::array::from_fn(|i| a[i] as f32);
        let mut out = [0f32; 22];
        evaluate(&model, &input, &mut out).unwrap();
        emb.push(out);
    }
    let mut worst: f64 = 0.0;
    for k in 0..22 {
        let scale = lib.iter().fold(1e-12f64, |a, v| a.max(v[k].abs()));
        for (l, e) in lib.iter().zip(&emb) {
            worst = worst.max((e[k] as f64 - l[k]).abs() / scale);
        }
    }
    worst
}

#[test]
fn embedded_f32_agrees_with_library_poly_gp_and_mixed() {
    for only in [Some(RegressorKind::Poly), Some(RegressorKind::Gp), None] {
        let m = rom_common::small_model(only);
        let gap = max_relative_gap(&m);
        println!("{only:?}: max relative gap {gap:e}");
        assert!(
            gap <= 1e-5,
            "{only:?}: embedded f32 differs from the library by {gap:e} (relative)"
        );
    }
}

#[test]
fn embedded_rejects_bad_inputs_with_codes() {
    let m = rom_common::small_model(Some(RegressorKind::Poly));
    let tables = EmbeddedTables::<f64>::from_surrogate(&m).unwrap();
    let blocks = tables.block_tables();
    let model = tables.view(&blocks);
    let mut out = [0.0; 22];
    let ok = [11.0, 2.0, 1.0, 1.13, 3.11, -13.17, -0.6];
    assert!(evaluate(&model, &ok, &mut out).is_ok());
    let mut bad = ok;
    bad[0] = 12.0;
    assert_eq!(
        evaluate(&model, &bad, &mut out),
        Err(EmbeddedError::UnknownN)
    );
    bad = ok;
    bad[2] = f64::NAN;
    assert_eq!(
        evaluate(&model, &bad, &mut out),
        Err(EmbeddedError::NonFinite(2))
    );
    bad = ok;
    bad[6] = 0.6;
    assert_eq!(
        evaluate(&model, &bad, &mut out).map_err(|e| e.code()),
        Err(3)
    );
}

#[test]
fn no_std_module_compiles() {
    let m = rom_common::small_model(None);
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rom_no_std_check");
    std::fs::create_dir_all(&dir).unwrap();
    let predict_src = concat!(env!("CARGO_MANIFEST_DIR"), "/src/predict/mod.rs");
    std::fs::copy(predict_src, dir.join("predict.rs")).unwrap();
    let sum = m.checksum().unwrap();
    std::fs::write(
        dir.join("model32.rs"),
        rust_source(&m, Precision::F32, &sum).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("model64.rs"),
        rust_source(&m, Precision::F64, &sum).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("lib.rs"),
        "#![no_std]\n//! no_std check of the embedded predictor\npub mod predict;\npub mod model32;\npub mod model64;\n",
    )
    .unwrap();
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let out = std::process::Command::new(rustc)
        .args([
            "--edition",
            "2021",
            "--crate-type",
            "rlib",
            "--crate-name",
            "nostd_check",
            "-O",
            "--emit=link",
        ])
        .arg("--out-dir")
        .arg(&dir)
        .arg(dir.join("lib.rs"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "no_std build failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = c_header(Precision::F32, &sum);
    assert!(header.contains("int32_t surrogate_predict_f32(uint32_t n, float t_mm, float p_bar"));
}
