//! Twin recordings on a reduced noise source (one design, one pressure, coarse mesh: two short
//! FE ramps): the files read back through the experiment loader, hold nothing else, the key
//! goes to its own file, the same seed gives the same bytes and another seed runs no FE.

use std::path::Path;

use surrogate::calibrate::experiments::{BENDING_FILE, FORCE_FILE, MARKERS_FILE};
use surrogate::calibrate::twin::{write_twin, TwinKey, TwinSettings};
use surrogate::calibrate::Recordings;
use surrogate::fe::effects::{Effect, Effects};
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};

fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn twins_conceal_their_key_are_reproducible_and_reuse_the_fe_runs() {
    let dir = std::env::temp_dir().join(format!("surrogate_twin_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut noise = Recordings::shipped().unwrap();
    let one = |n: usize, t: f64, p: f64| n == 11 && t == 2.0 && p == 1.0;
    noise
        .bending
        .retain(|r| one(r.n_bellows, r.wall_thickness_mm, r.pressure_bar));
    noise
        .force
        .retain(|r| one(r.n_bellows, r.wall_thickness_mm, r.pressure_bar));
    let material = Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap();
    let effects = Effects::parse(["wall_bias=0.1"]).unwrap();
    let mut settings = TwinSettings::new(
        material,
        "ogden_002",
        MeshOptions::level(MeshLevel::Coarse),
        effects.clone(),
        7,
        &dir.join("cache"),
    );
    settings.key = Some(dir.join("keys/a.json"));
    let a = write_twin(&settings, &noise, &dir.join("a"), |_, _| {}).unwrap();
    assert_eq!((a.ramps_run, a.ramps_cached), (2, 0));
    assert!(a.missing.is_empty(), "{:?}", a.missing);
    assert_eq!(a.rows, [1, 1, 9]);
    // the effect reached the FE case: the cached ramps are keyed by it
    let cached = std::fs::read_to_string(a.ramp_dir.join("n11_t2_bending.json")).unwrap();
    assert!(
        cached.contains(r#"\"effects\":{\"wall_bias\":0.1}"#),
        "{cached}"
    );
    // the output holds the three recordings and nothing that names the settings
    let out = dir.join("a");
    assert_eq!(files(&out), [BENDING_FILE, FORCE_FILE, MARKERS_FILE]);
    for f in files(&out) {
        let text = std::fs::read_to_string(out.join(&f)).unwrap();
        for secret in ["wall_bias", "ogden", "effect", "mu1"] {
            assert!(!text.contains(secret), "{f} names {secret}");
        }
    }
    // the experiment loader reads them; the values are the FE's within the noise
    let twin = Recordings::read_dir(&out).unwrap();
    assert_eq!(
        (twin.bending.len(), twin.force.len(), twin.markers.len()),
        (1, 1, 9)
    );
    let (b, f) = (&twin.bending[0], &twin.force[0]);
    assert_eq!(b.angle_std_deg, noise.bending[0].angle_std_deg);
    assert_eq!(f.force_std_n, noise.force[0].force_std_n);
    assert!(b.tip_uy_mm < -5.0 && b.angle_deg > 5.0, "{b:?}");
    assert!(f.force_n > 0.0, "{f:?}");
    assert_eq!(twin.markers[8].marker, 9);
    // the key, in its own file
    let key: TwinKey =
        serde_json::from_str(&std::fs::read_to_string(dir.join("keys/a.json")).unwrap()).unwrap();
    assert_eq!(key.effects.get(Effect::WallBias), 0.1);
    assert_eq!((key.seed, key.material.as_str()), (7, "ogden_002"));
    // another seed: no FE run, other noise
    settings.seed = 8;
    settings.key = None;
    let b8 = write_twin(&settings, &noise, &dir.join("b"), |_, _| {}).unwrap();
    assert_eq!((b8.ramps_run, b8.ramps_cached), (0, 2));
    let bending = |d: &str| std::fs::read(dir.join(d).join(BENDING_FILE)).unwrap();
    assert_ne!(bending("a"), bending("b"));
    // the same seed again: the same bytes
    settings.seed = 7;
    write_twin(&settings, &noise, &dir.join("c"), |_, _| {}).unwrap();
    for f in files(&out) {
        let read = |d: &str| std::fs::read(dir.join(d).join(&f)).unwrap();
        assert_eq!(read("a"), read("c"), "{f}");
    }
    // a noise source without forces: bending ramps only (the cached one), no force row
    let mut bending_only = noise.clone();
    bending_only.force.clear();
    let d = write_twin(&settings, &bending_only, &dir.join("d"), |_, _| {}).unwrap();
    assert_eq!((d.ramps_run, d.ramps_cached), (0, 1));
    assert!(d.missing.is_empty(), "{:?}", d.missing);
    assert_eq!(d.rows, [1, 0, 9]);
    assert_eq!(bending("d"), bending("a"));
    assert_eq!(files(&dir.join("d")), [BENDING_FILE, MARKERS_FILE]);
    let read = Recordings::read_dir(&dir.join("d")).unwrap();
    assert_eq!((read.bending.len(), read.force.len()), (1, 0));
    // over a twin with forces, the stale force file goes
    write_twin(&settings, &bending_only, &dir.join("a"), |_, _| {}).unwrap();
    assert_eq!(files(&dir.join("a")), [BENDING_FILE, MARKERS_FILE]);
    std::fs::remove_dir_all(&dir).unwrap();
}
