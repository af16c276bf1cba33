//! The unit tests of `src/fe/element.rs`.

use surrogate::fe::element::*;

#[test]
fn shape_functions_partition_unity() {
    let (n, dn) = shape([0.3, -0.7, 0.1]);
    assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    for m in 0..3 {
        assert!(dn.iter().map(|d| d[m]).sum::<f64>().abs() < 1e-13);
    }
    let t = table();
    assert!((t.w.iter().sum::<f64>() - 8.0).abs() < 1e-13);
}
