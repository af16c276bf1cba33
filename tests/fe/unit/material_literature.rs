//! The unit tests of `src/fe/material/literature.rs`.

use surrogate::fe::material::literature_sets;

#[test]
fn shipped_sets_parse() {
    let sets = literature_sets().unwrap();
    let names: Vec<_> = sets.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["ogden_002", "ogden_005", "mooney_rivlin_5"]);
    assert!((sets[0].1.initial_shear_modulus() - 5.708).abs() < 1e-3);
}
