//! The embedded predictor (the `surrogate-predict` crate) agrees with the library, and a
//! `#![no_std]` crate of exported models that depends on it builds, also as a C static library.
use surrogate::case::{OgdenSet, Query};
use surrogate::predict::{evaluate, evaluate_ramp, EmbeddedError, RampTables};
use surrogate::rom::export::{
    c_header, ramp_c_header, ramp_rust_source, rust_source, EmbeddedTables, Precision,
};
use surrogate::rom::regression::RegressorKind;
use surrogate::rom::Surrogate;

use crate::rom_common;

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
    for only in [Some(RegressorKind::POLY), Some(RegressorKind::GP), None] {
        let m = rom_common::small_model(only.clone());
        let gap = max_relative_gap(&m);
        println!("{only:?}: max relative gap {gap:e}");
        assert!(
            gap <= 1e-5,
            "{only:?}: embedded f32 differs from the library by {gap:e} (relative)"
        );
    }
    // one kernel per POD block
    let gap = max_relative_gap(&rom_common::grouped_model());
    assert!(gap <= 1e-5, "kernel per block: embedded f32 off by {gap:e}");
}

#[test]
fn embedded_rejects_bad_inputs_with_codes() {
    let m = rom_common::small_model(Some(RegressorKind::POLY));
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

/// A scratch crate under the test's target directory that depends on the `surrogate-predict`
/// crate of this workspace by path: `Cargo.toml` (with `extra` appended) and `src/lib.rs`, its
/// other sources written by the caller into `src/`.
fn scratch_crate(name: &str, lib_rs: &str, extra: &str) -> std::path::PathBuf {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(dir.join("src")).unwrap();
    let predict = concat!(env!("CARGO_MANIFEST_DIR"), "/predict");
    std::fs::write(
        dir.join("Cargo.toml"),
        format!(
            "[package]\nname = \"{name}\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\n[dependencies]\nsurrogate-predict = {{ path = {predict:?} }}\n\n# not a member of the surrogate workspace\n[workspace]\n{extra}"
        ),
    )
    .unwrap();
    std::fs::write(dir.join("src/lib.rs"), lib_rs).unwrap();
    dir
}

/// `cargo build --release --offline` of a scratch crate, in its own target directory.
fn cargo_build(dir: &std::path::Path) {
    let out = std::process::Command::new(env!("CARGO"))
        .args(["build", "--release", "--offline", "--quiet"])
        .arg("--manifest-path")
        .arg(dir.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(dir.join("target"))
        .env_remove("CARGO_TARGET_DIR")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "cargo build of {} failed:\n{}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The exported models (f32, f64) and ramps compile in a `#![no_std]` crate that depends on
/// `surrogate-predict` by path, as a controller's crate does.
#[test]
fn no_std_crate_compiles() {
    let bare = rom_common::small_model(None);
    let m = with_model_form(&bare);
    let dir = scratch_crate(
        "rom_no_std_check",
        "#![no_std]\n//! no_std check of the embedded predictor and exported models\npub mod model32;\npub mod model64;\npub mod ramp32;\npub mod ramp64;\n",
        "",
    );
    let src = dir.join("src");
    let sum = m.checksum().unwrap();
    std::fs::write(
        src.join("model32.rs"),
        rust_source(&m, Precision::F32, &sum).unwrap(),
    )
    .unwrap();
    std::fs::write(
        src.join("model64.rs"),
        rust_source(&bare, Precision::F64, &sum).unwrap(),
    )
    .unwrap();
    let q = Query::new(
        11,
        2.0,
        0.0,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    for (file, p, model) in [
        ("ramp32.rs", Precision::F32, &m),
        ("ramp64.rs", Precision::F64, &bare),
    ] {
        let text = ramp_rust_source(model, &q, p, &sum).unwrap();
        assert!(text.contains("pub static MODEL_FORM"));
        assert!(text.contains("Needs the `surrogate-predict` crate"));
        std::fs::write(src.join(file), text).unwrap();
    }
    cargo_build(&dir);
    let header = c_header(&m, Precision::F32, &sum);
    assert!(header.contains("int32_t surrogate_predict_f32(uint32_t n, float t_mm, float p_bar"));
    let header = ramp_c_header(&m, Precision::F64, &sum, &q);
    assert!(header.contains("int32_t surrogate_ramp_f64(double p_bar, double *out);"));
}

/// An exported ramp (one design and material) gives the library's prepared ramp: bit for bit
/// in f64, to 1e-5 of each quantity's largest |value| in f32.
#[test]
fn exported_ramp_agrees_with_the_library_ramp() {
    for only in [Some(RegressorKind::GP), None] {
        let m = rom_common::small_model(only.clone());
        for q in held_out(&m).into_iter().step_by(6) {
            let ramp = m.ramp(&q).unwrap();
            let t64 = RampTables {
                pressures: ramp.pressures(),
                values: ramp.values(),
            };
            let v32: Vec<f32> = ramp.values().iter().map(|&v| v as f32).collect();
            let t32 = RampTables {
                pressures: ramp.pressures(),
                values: &v32,
            };
            let mut largest = [0.0f64; 22];
            for (i, v) in ramp.values().iter().enumerate() {
                largest[i % 22] = largest[i % 22].max(v.abs());
            }
            let mut pred = m.new_prediction();
            let (mut o64, mut o32) = ([0f64; 22], [0f32; 22]);
            for i in 0..=40 {
                let p = -0.1 + 0.09 * i as f64;
                ramp.predict_into(p, &mut pred).unwrap();
                evaluate_ramp(&t64, p, &mut o64).unwrap();
                assert_eq!(o64, pred.values, "p = {p}");
                evaluate_ramp(&t32, p as f32, &mut o32).unwrap();
                for k in 0..22 {
                    let gap = (o32[k] as f64 - pred.values[k]).abs() / largest[k].max(1e-12);
                    assert!(gap <= 1e-5, "quantity {k}, p = {p}: relative gap {gap:e}");
                }
            }
            assert_eq!(
                evaluate_ramp(&t64, f64::NAN, &mut o64),
                Err(EmbeddedError::NonFinite(2))
            );
            let bad = RampTables {
                pressures: ramp.pressures(),
                values: &ramp.values()[1..],
            };
            assert_eq!(
                evaluate_ramp(&bad, 1.0, &mut o64),
                Err(EmbeddedError::BadModel)
            );
        }
    }
}

/// The exported `extern "C"` entry point, built with `surrogate-predict` as a `#![no_std]`
/// static library (cargo, `panic = "abort"`) and called from C through the generated header,
/// gives the library's values.
#[test]
fn c_entry_point_links_and_agrees() {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    if std::process::Command::new(&cc)
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped: no C compiler ({cc})");
        return;
    }
    let m = with_model_form(&rom_common::small_model(None));
    let dir = scratch_crate(
        "rom_c_check",
        "#![no_std]\npub mod model32;\npub mod ramp32;\n#[panic_handler]\nfn panic(_: &core::panic::PanicInfo) -> ! {\n    loop {}\n}\n",
        "\n[lib]\ncrate-type = [\"staticlib\"]\n\n[profile.release]\npanic = \"abort\"\n",
    );
    let sum = m.checksum().unwrap();
    std::fs::write(
        dir.join("src/model32.rs"),
        rust_source(&m, Precision::F32, &sum).unwrap(),
    )
    .unwrap();
    std::fs::write(dir.join("model.h"), c_header(&m, Precision::F32, &sum)).unwrap();
    // the same design and material exported as a ramp
    let q_ramp = Query {
        n: 11,
        t_mm: 2.0,
        p_bar: 0.0,
        material: OgdenSet::from_array([
            1.13f32 as f64,
            3.11f32 as f64,
            -13.17f32 as f64,
            -0.6f32 as f64,
        ]),
    };
    std::fs::write(
        dir.join("src/ramp32.rs"),
        ramp_rust_source(&m, &q_ramp, Precision::F32, &sum).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("ramp.h"),
        ramp_c_header(&m, Precision::F32, &sum, &q_ramp),
    )
    .unwrap();
    std::fs::write(
        dir.join("main.c"),
        "#include <stdio.h>\n#include \"model.h\"\n#include \"ramp.h\"\n/* the precompiled libcore refers to it even with panic=abort; never called */\nvoid rust_eh_personality(void) {}\nint main(void) {\n  float out[SURROGATE_N_OUTPUTS];\n  int rc = surrogate_predict_f32(11, 2.0f, 1.5f, 1.13f, 3.11f, -13.17f, -0.6f, out);\n  int bad = surrogate_predict_f32(12, 2.0f, 1.5f, 1.13f, 3.11f, -13.17f, -0.6f, out + 0);\n  printf(\"%d %d\", rc, bad);\n  rc = surrogate_predict_f32(11, 2.0f, 1.5f, 1.13f, 3.11f, -13.17f, -0.6f, out);\n  for (int i = 0; i < SURROGATE_N_OUTPUTS; i++) printf(\" %.9g\", out[i]);\n  float ramp[SURROGATE_N_OUTPUTS];\n  printf(\" %d\", surrogate_ramp_f32(1.5f, ramp));\n  for (int i = 0; i < SURROGATE_N_OUTPUTS; i++) printf(\" %.9g\", ramp[i]);\n  /* the named indices, from both headers */\n  printf(\" %d %d %d %d %d\", SURROGATE_M1_UZ, SURROGATE_M9_UY, SURROGATE_TIP_UZ, SURROGATE_ANGLE, SURROGATE_FORCE);\n  /* the model-form error, from both headers (guarded) */\n  static const double mf_p[SURROGATE_MODEL_FORM_N_LEVELS] = SURROGATE_MODEL_FORM_P_BAR;\n  static const double mf_angle[SURROGATE_MODEL_FORM_N_LEVELS] = SURROGATE_MODEL_FORM_ANGLE;\n  printf(\" %.17g %.17g\", mf_p[1], mf_angle[1]);\n  printf(\"\\n\");\n  return 0;\n}\n",
    )
    .unwrap();
    let run = |cmd: &mut std::process::Command| {
        let o = cmd.output().unwrap();
        assert!(
            o.status.success(),
            "{cmd:?}:\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    cargo_build(&dir);
    run(std::process::Command::new(&cc)
        .arg(dir.join("main.c"))
        .arg(dir.join("target/release/librom_c_check.a"))
        .arg("-o")
        .arg(dir.join("main"))
        .arg("-lm"));
    let out = run(&mut std::process::Command::new(dir.join("main")));
    let v: Vec<f64> = out.split_whitespace().map(|t| t.parse().unwrap()).collect();
    assert_eq!((v[0], v[1]), (0.0, 2.0), "return codes");
    let q = Query {
        n: 11,
        t_mm: 2.0,
        p_bar: 1.5,
        material: OgdenSet::from_array([
            1.13f32 as f64,
            3.11f32 as f64,
            -13.17f32 as f64,
            -0.6f32 as f64,
        ]),
    };
    let lib = m.predict(&q).unwrap().values;
    for k in 0..22 {
        assert!(
            (v[2 + k] - lib[k]).abs() <= 1e-5 * lib[k].abs().max(1.0),
            "output {k}: C {} vs library {}",
            v[2 + k],
            lib[k]
        );
    }
    // the ramp entry point: return code 0 and the library ramp's values at 1.5 bar
    assert_eq!(v[24], 0.0, "ramp return code");
    let mut pred = m.new_prediction();
    m.ramp(&q_ramp)
        .unwrap()
        .predict_into(1.5, &mut pred)
        .unwrap();
    for k in 0..22 {
        assert!(
            (v[25 + k] - pred.values[k]).abs() <= 1e-5 * pred.values[k].abs().max(1.0),
            "ramp output {k}: C {} vs library {}",
            v[25 + k],
            pred.values[k]
        );
    }
    use surrogate::predict::{ANGLE, FORCE, M1_UZ, M9_UY, TIP_UZ};
    let named = [M1_UZ, M9_UY, TIP_UZ, ANGLE, FORCE].map(|i| i as f64);
    assert_eq!(v[47..52], named, "the C names of the output indices");
    let e = m.model_form().unwrap();
    assert_eq!(v[52], e.pressures[1]);
    assert_eq!(
        Some(v[53]),
        e.error(ANGLE, e.pressures[1]),
        "the model-form error of the header"
    );
}

/// Both headers define the index of every output under the name of the crate's constant
/// (`SURROGATE_TIP_UZ 18` for `surrogate_predict::TIP_UZ`), and the crate, the library and
/// the schema name the outputs alike.
#[test]
fn headers_name_every_output_index() {
    use surrogate::predict::{marker_uy, marker_uz, OUTPUT_NAMES};
    use surrogate::rom::export::c_output_macro;
    use surrogate::rom::QUANTITY_NAMES;
    assert_eq!(OUTPUT_NAMES, QUANTITY_NAMES);
    let m = rom_common::small_model(None);
    let sum = m.checksum().unwrap();
    let q = Query::new(
        11,
        2.0,
        0.0,
        OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
    );
    for header in [
        c_header(&m, Precision::F32, &sum),
        ramp_c_header(&m, Precision::F64, &sum, &q),
    ] {
        for (i, name) in QUANTITY_NAMES.iter().enumerate() {
            let line = format!("#define {} {i}\n", c_output_macro(name));
            assert!(header.contains(&line), "{line}");
        }
        assert!(header.contains("#define SURROGATE_TIP_UZ 18\n"));
        assert!(header.contains("#define SURROGATE_ANGLE 20\n"));
        assert!(header.contains("#define SURROGATE_M1_UZ 0\n"));
        assert!(header.contains("#define SURROGATE_M9_UY 17\n"));
    }
    for k in 1..=9 {
        let uz = format!("SURROGATE_M{k}_UZ");
        assert_eq!(c_output_macro(QUANTITY_NAMES[marker_uz(k)]), uz);
        assert_eq!(
            c_output_macro(QUANTITY_NAMES[marker_uy(k)]),
            format!("SURROGATE_M{k}_UY")
        );
    }
}

/// `m` with a model-form error of the angle and tip Uz at 1, 2 and 3 bar.
fn with_model_form(m: &surrogate::rom::Surrogate) -> surrogate::rom::Surrogate {
    use surrogate::rom::model_form::{CalibrationSource, ModelFormError, Residual};
    let source = CalibrationSource {
        report: "report.json".into(),
        report_checksum: "crc32:00000000".into(),
        model: m.checksum().unwrap(),
        objective: "tip=1".into(),
        material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
        configurations: 15,
    };
    let residuals: Vec<Residual> = (0..15)
        .flat_map(|k| {
            let p = [1.0, 2.0, 3.0][k % 3];
            [surrogate::predict::ANGLE, surrogate::predict::TIP_UZ].map(|output| Residual {
                pressure_bar: p,
                output,
                value: p * (1.0 + k as f64 / 10.0),
            })
        })
        .collect();
    let mut m = m.clone();
    m.model_form = Some(ModelFormError::from_residuals(source, &residuals).unwrap());
    m
}
