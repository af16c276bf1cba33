//! The unit tests of `src/fe/assembly/load/mod.rs`.

use surrogate::fe::assembly::load::*;

/// A level as the solver reports wrote it before the factors were a vector.
const OLD: &str = r#"{"pressure":0.1,"gravity":1.0,"traction":0.25,"prescribed":0.5}"#;

#[test]
fn an_old_level_reads_and_writes_unchanged() {
    let level: LoadLevel = serde_json::from_str(OLD).unwrap();
    assert_eq!(level.pressure(), 0.1);
    assert_eq!(level.gravity(), 1.0);
    assert_eq!(level.traction(), 0.25);
    assert_eq!(level.prescribed(), 0.5);
    assert_eq!(serde_json::to_string(&level).unwrap(), OLD);
    assert_eq!(
        format!("{level:?}"),
        "LoadLevel { pressure: 0.1, gravity: 1.0, traction: 0.25, prescribed: 0.5 }"
    );
    // missing factors are 0; unknown and repeated ones are errors
    let partial: LoadLevel = serde_json::from_str(r#"{"gravity":1.0}"#).unwrap();
    assert_eq!(partial, LoadLevel::ZERO.with(LoadFactor::GRAVITY, 1.0));
    let unknown = serde_json::from_str::<LoadLevel>(r#"{"presure":1.0}"#).unwrap_err();
    assert!(unknown.to_string().contains("presure"), "{unknown}");
    assert!(serde_json::from_str::<LoadLevel>(r#"{"gravity":1,"gravity":2}"#).is_err());
}

#[test]
fn a_registered_factor_round_trips_by_name() {
    let tip = LoadFactor::register(FactorInfo {
        name: "level test tip load",
        description: "a point load of the level's unit test",
        bounds_increment: false,
    })
    .unwrap();
    let level = LoadLevel::ZERO
        .with(LoadFactor::PRESSURE, 0.2)
        .with(tip, -1.5);
    let json = serde_json::to_string(&level).unwrap();
    assert!(
        json.ends_with(r#""prescribed":0.0,"level test tip load":-1.5}"#),
        "{json}"
    );
    let back: LoadLevel = serde_json::from_str(&json).unwrap();
    assert_eq!(back, level);
    // zero: not written
    let zero = serde_json::to_string(&LoadLevel::ZERO).unwrap();
    assert!(!zero.contains("tip"), "{zero}");
    assert_eq!(
        format!("{level}"),
        "pressure=0.2000 level test tip load=-1.5000"
    );
    assert_eq!(format!("{}", LoadLevel::ZERO), "no load");
}

#[test]
fn lerp_changing_and_the_bounded_increment_go_factor_by_factor() {
    let a = LoadLevel::ZERO.with(LoadFactor::GRAVITY, 1.0);
    let b = a
        .with(LoadFactor::PRESSURE, 0.3)
        .with(LoadFactor::TRACTION, 2.0);
    let m = a.lerp(&b, 0.5);
    assert_eq!(m.pressure(), 0.15);
    assert_eq!(m.gravity(), 1.0);
    assert_eq!(m.traction(), 1.0);
    let changing: Vec<_> = a.changing(&b).collect();
    assert_eq!(changing, [LoadFactor::PRESSURE, LoadFactor::TRACTION]);
    // only the pressure bounds the increment
    assert_eq!(a.bounded_increment(&b), 0.3);
    assert_eq!(b.bounded_increment(&a), 0.3);
    assert_eq!(a.changing(&a).count(), 0);
}
