//! The unit tests of `src/fe/sensitivity/params.rs`.

use surrogate::fe::effects::Effect;
use surrogate::fe::sensitivity::{OgdenParameter, Parameter};

#[test]
fn names_round_trip_and_lists_parse() {
    for p in Parameter::all() {
        assert_eq!(Parameter::from_name(p.name()).unwrap(), p);
    }
    assert_eq!(Parameter::all().len(), 4 + Effect::all().count());
    let l = Parameter::parse_list("mu1, wall_bias").unwrap();
    assert_eq!(
        l,
        vec![
            Parameter::Material(OgdenParameter::Mu1),
            Parameter::Effect(Effect::WallBias)
        ]
    );
    let e = Parameter::parse_list("mu1,wal_bias")
        .unwrap_err()
        .to_string();
    assert!(e.contains("wal_bias") && e.contains("alpha2"), "{e}");
    let e = Parameter::parse_list("mu1,mu1").unwrap_err().to_string();
    assert!(e.contains("mu1"), "{e}");
    assert!(Parameter::parse_list("").is_err());
}
