//! The unit tests of `src/rom/regression/poly.rs`.

use surrogate::rom::regression::poly::*;

#[test]
fn monomial_counts() {
    assert_eq!(monomials(6, 3).len() / 6, 84);
    assert_eq!(monomials(2, 2), vec![0, 0, 1, 0, 0, 1, 2, 0, 1, 1, 0, 2]);
}
