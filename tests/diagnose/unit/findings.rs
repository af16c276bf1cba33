//! The unit tests of `src/diagnose/findings.rs`.

use surrogate::diagnose::cells::Family;
use surrogate::diagnose::findings::*;
use surrogate::diagnose::groups::Misfit;

fn misfit(cells: usize, chi2: f64) -> Misfit {
    Misfit {
        family: Family::TipUz,
        fitted: true,
        cells,
        chi2,
        rms_z: (chi2 / cells as f64).sqrt(),
        p_value: 0.5,
        significant: false,
    }
}

#[test]
fn recordings_more_precise_than_their_sigma_are_reported() {
    // 54 cells with χ² = 20: P(χ²(54) ≤ 20) ≈ 1e-7, far below α
    let f = more_precise_than_stated(&[misfit(27, 10.0), misfit(27, 10.0)], 0.05).unwrap();
    assert_eq!(f.kind, FindingKind::Misfit);
    assert!(
        f.text.contains("more precise than their stated σ"),
        "{}",
        f.text
    );
    assert!(f.text.contains("χ²/n = 0.37"), "{}", f.text);
    // χ² about n: nothing to report
    assert!(more_precise_than_stated(&[misfit(27, 26.0), misfit(27, 29.0)], 0.05).is_none());
    assert!(more_precise_than_stated(&[], 0.05).is_none());
}
