//! The unit tests of `src/calibrate/verdict.rs`.

use surrogate::calibrate::experiments::shipped_files;
use surrogate::calibrate::inputs::InputFile;
use surrogate::calibrate::verdict::*;

#[test]
fn verdict_words_follow_the_residuals_size() {
    // the shipped experiments' `tip` fit: χ²/dof 14.7, residuals 3.8 times the scatter
    let v = fit_verdict(14.7 * 50.0, 50);
    assert!(
        v.starts_with(
            "**Verdict: residuals 3.8× the measurement scatter: the model misses these data.**"
        ),
        "{v}"
    );
    assert!(
        v.contains("χ²/dof = 14.70 over 50 degrees of freedom"),
        "{v}"
    );
    let v = fit_verdict(52.0, 50);
    assert!(
        v.starts_with("**Verdict: residuals 1.0× the measurement scatter: the model fits"),
        "{v}"
    );
    let v = fit_verdict(10.0, 50);
    assert!(
        v.contains("0.4× the measurement scatter, smaller than noise alone makes"),
        "{v}"
    );
    // just past the 99 % quantile of χ²₅₀ (76.15) misses, just under it fits
    assert!(fit_verdict(77.0, 50).contains("misses"));
    assert!(fit_verdict(75.0, 50).contains("fits these data"));
    assert!(fit_verdict(3.0, 0).starts_with("**Verdict: none.**"));
    assert!(fit_verdict(f64::NAN, 10).starts_with("**Verdict: none.**"));
}

#[test]
fn the_reference_study_is_quoted_for_the_shipped_experiments_only() {
    let (b, f) = shipped_files().unwrap();
    // shipped files, wherever they were read from (the checksum decides)
    let mut named_b = b.file.clone();
    named_b.path = "/elsewhere/copy.csv".into();
    named_b.default = false;
    let model = InputFile::of_bytes("model", "m.json", b"{}");
    for inputs in [
        vec![model.clone(), b.file.clone(), f.file.clone()],
        vec![model.clone(), named_b.clone()],
        vec![
            named_b.clone(),
            InputFile::of_bytes("markers", "m.csv", b"x"),
        ],
    ] {
        assert_eq!(reference_study_line(&inputs), Some(REFERENCE_STUDY));
    }
    let mine = InputFile::of_bytes("bending", "mine.csv", b"n_bellows\n");
    let mine_force = InputFile::of_bytes("force", "f.csv", b"n_bellows\n");
    for inputs in [
        vec![model.clone(), mine.clone()],
        vec![mine, f.file.clone()],
        vec![b.file.clone(), mine_force],
        vec![model],
    ] {
        assert_eq!(reference_study_line(&inputs), None);
    }
}
