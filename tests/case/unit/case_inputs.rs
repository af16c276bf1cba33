//! The unit tests of `src/case/inputs.rs`.

use surrogate::case::inputs::*;
use surrogate::case::OgdenSet;

const CASE: CaseInputs = CaseInputs {
    n_bellows: 11,
    wall_thickness_mm: 2.0,
    material: OgdenSet::from_array([1.13, 3.11, -13.17, -0.6]),
};

#[test]
fn case_inputs_keep_their_flat_shape_in_json_and_csv() {
    let json = serde_json::to_string(&CASE).unwrap();
    assert_eq!(
        json,
        r#"{"n_bellows":11,"wall_thickness_mm":2.0,"mu1_mpa":1.13,"alpha1":3.11,"mu2_mpa":-13.17,"alpha2":-0.6}"#
    );
    assert_eq!(serde_json::from_str::<CaseInputs>(&json).unwrap(), CASE);
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(CASE).unwrap();
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    assert_eq!(
        text,
        "n_bellows,wall_thickness_mm,mu1_mpa,alpha1,mu2_mpa,alpha2\n11,2.0,1.13,3.11,-13.17,-0.6\n"
    );
    let back: CaseInputs = csv::Reader::from_reader(text.as_bytes())
        .deserialize()
        .next()
        .unwrap()
        .unwrap();
    assert_eq!(back, CASE);
}

#[test]
fn a_query_round_trips_through_its_case() {
    let q = Query::from_case(&CASE, 2.5);
    assert_eq!(q.case(), CASE);
    assert_eq!(q.as_array(), [11.0, 2.0, 2.5, 1.13, 3.11, -13.17, -0.6]);
}
