//! The unit tests of `src/calibrate/twin.rs`.

use std::path::Path;
use surrogate::calibrate::experiments::{parse_bending, parse_force, shipped_bending};
use surrogate::calibrate::objective::Recordings;
use surrogate::calibrate::twin::*;
use surrogate::fe::effects::Effects;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::MeshOptions;
use surrogate::fe::preset::Geometry;

#[test]
fn files_have_the_shipped_format_and_read_back() {
    let shipped = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("training_data/bending_experiments.csv"),
    )
    .unwrap();
    let rows = shipped_bending().unwrap();
    let text = bending_csv(&rows);
    // the same header, and the same cells but where the table drops a trailing zero
    assert_eq!(text.lines().next(), shipped.lines().next());
    for (a, b) in text.lines().zip(shipped.lines()).skip(1) {
        let a: Vec<f64> = a.split(',').map(|c| c.parse().unwrap()).collect();
        let b: Vec<f64> = b.split(',').map(|c| c.parse().unwrap()).collect();
        assert_eq!(a, b);
    }
    assert!(
        text.contains("\n9,1.6,2,28.15,-57.30,42.10,3.37\n"),
        "{text}"
    );
    assert_eq!(parse_bending("twin", &text).unwrap(), rows);
    let force = surrogate::calibrate::experiments::shipped_force().unwrap();
    assert_eq!(parse_force("twin", &force_csv(&force)).unwrap(), force);
    assert_eq!(fixed(-0.001, 2), "0.00");
    assert_eq!(fixed(-0.01, 2), "-0.01");
}

#[test]
fn key_and_cache_must_lie_outside_the_output() {
    let dir = std::env::temp_dir().join(format!("surrogate_twin_paths_{}", std::process::id()));
    let out = dir.join("twin");
    assert!(lies_in(&out.join("key.json"), &out));
    assert!(lies_in(&out.join("a/b/c"), &out));
    assert!(!lies_in(&dir.join("key.json"), &out));
    assert!(!lies_in(&dir.join("twin_fe_ramps"), &out));
    let material =
        Material::from_spec("ogden_002", surrogate::fe::material::DEFAULT_BULK_RATIO).unwrap();
    let mut s = TwinSettings::new(
        material,
        "ogden_002",
        MeshOptions::level(surrogate::fe::mesh::MeshLevel::Coarse),
        Effects::default(),
        1,
        &dir,
    );
    s.key = Some(out.join("key.json"));
    let rec = Recordings::shipped().unwrap();
    let e = write_twin(&s, &rec, &out, |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("key = ") && e.contains("outside the twin's directory"),
        "{e}"
    );
    s.key = None;
    s.cache = out.join("cache");
    let e = write_twin(&s, &rec, &out, |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("cache = "), "{e}");
    assert!(!out.exists(), "nothing written on error");
    // twins that differ in the seed share their ramps; another effect does not
    s.cache = dir.clone();
    let a = s.ramp_dir();
    s.seed = 2;
    assert_eq!(s.ramp_dir(), a);
    s.sweep.effects = Effects::parse(["wall_bias=0.1"]).unwrap();
    assert_ne!(s.ramp_dir(), a);
    // nor does another geometry; the geometry as modelled keeps the folder's old name
    s.sweep.effects = Effects::default();
    assert_eq!(s.ramp_dir(), a);
    s.sweep.geometry = Geometry {
        name: "identified".into(),
        gap_mm: 0.5,
        ..Geometry::as_modelled()
    };
    assert_ne!(s.ramp_dir(), a);
}
