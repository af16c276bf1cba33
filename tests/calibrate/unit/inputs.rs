//! The unit tests of `src/calibrate/inputs.rs`.

use surrogate::calibrate::inputs::*;

#[test]
fn records_checksum_size_and_origin() {
    let f = InputFile::of_bytes("bending", "b.csv", b"abc");
    assert_eq!(f.checksum, "crc32:352441c2");
    assert_eq!(f.bytes, 3);
    assert_eq!(f.origin(), "named");
    let mut d = f.clone().as_default();
    d.rows = Some(27);
    d.converted = vec!["pressure_kpa → pressure_bar × 0.01".into()];
    let md = markdown(&[f, d]);
    assert!(
        md.contains("| bending | `b.csv` | crc32:352441c2 |  | named |"),
        "{md}"
    );
    assert!(md.contains("| 27 | default |"), "{md}");
    assert!(
        md.contains("column pressure_kpa → pressure_bar × 0.01"),
        "{md}"
    );
    assert!(markdown(&[]).contains("No file was read."));
}
