//! The unit tests of `src/fe/assembly/load/factor.rs`.

use surrogate::fe::assembly::load::factor::*;

#[test]
fn the_builtin_factors_are_the_registry_in_order() {
    let names: Vec<_> = (0..LOAD_FACTORS.len())
        .map(|i| LoadFactor::from_index(i).map(LoadFactor::name))
        .collect();
    assert_eq!(
        names,
        [
            Some("pressure"),
            Some("gravity"),
            Some("traction"),
            Some("prescribed")
        ]
    );
    assert_eq!(LoadFactor::PRESSURE.index(), 0);
    assert_eq!(LoadFactor::PRESCRIBED.index(), 3);
    assert_eq!(LoadFactor::by_name("gravity"), Some(LoadFactor::GRAVITY));
    assert_eq!(LoadFactor::by_name("no such factor"), None);
}

#[test]
fn registering_is_idempotent_and_checked() {
    let info = FactorInfo {
        name: "unit test factor",
        description: "a factor of the registry's unit test",
        bounds_increment: false,
    };
    let a = LoadFactor::register(info).unwrap();
    let b = LoadFactor::register(info).unwrap();
    assert_eq!(a, b);
    assert!(!a.is_builtin());
    assert_eq!(a.info(), info);
    assert_eq!(LoadFactor::by_name(info.name), Some(a));
    assert!(LoadFactor::all().any(|f| f == a));
    let other = FactorInfo {
        bounds_increment: true,
        ..info
    };
    assert_eq!(
        LoadFactor::register(other),
        Err(LoadFactorError::Conflict { name: info.name })
    );
    let builtin = FactorInfo {
        description: "something else",
        ..LOAD_FACTORS[0]
    };
    assert!(LoadFactor::register(builtin).is_err());
    let empty = FactorInfo { name: "", ..info };
    assert_eq!(LoadFactor::register(empty), Err(LoadFactorError::EmptyName));
}
