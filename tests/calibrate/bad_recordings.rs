//! Every bad recording of `tests/data/bad_recordings/` (one file per case: its README lists
//! them) through the library's loader and, where it loads, the calibration: each gets a named
//! error, or is fitted with every input listed in the report. Nothing is fitted silently.

use std::path::{Path, PathBuf};

use surrogate::calibrate::experiments::ExperimentError;
use surrogate::calibrate::{calibrate, CalibrateError, CalibrationSettings, Recordings};
use surrogate::rom::Surrogate;

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bad_recordings")
}

fn shipped(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("training_data")
        .join(file)
}

/// What a case must give.
enum Expect {
    /// The loader refuses the file: the error's variant, and words it must contain.
    Refused(fn(&ExperimentError) -> bool, &'static [&'static str]),
    /// The loader reads it; the calibration refuses it with these words.
    NotFitted(&'static [&'static str]),
    /// Read and fitted, with the file listed in the report (its rows) and these numbers.
    Fitted { rows: usize, observations: usize },
}

fn record(e: &ExperimentError) -> bool {
    matches!(e, ExperimentError::Record { .. })
}

fn implausible(e: &ExperimentError) -> bool {
    matches!(e, ExperimentError::Implausible { .. })
}

fn separator(e: &ExperimentError) -> bool {
    matches!(e, ExperimentError::Separator { .. })
}

/// The cases: file, whether it is a force recording, what it must give.
fn cases() -> Vec<(&'static str, bool, Expect)> {
    use Expect::*;
    vec![
        (
            "renamed_column.csv",
            false,
            Refused(
                record,
                &["column tip_uz_mm: missing column (the header has tip_z_mm"],
            ),
        ),
        (
            "nan.csv",
            false,
            Refused(record, &["line 5, column angle_deg: 'NaN' is not a finite number"]),
        ),
        (
            "duplicate.csv",
            false,
            Refused(
                record,
                &["line 4, column row: duplicate of line 3 (same configuration: N = 9, T = 1.6 mm, P = 2 bar)"],
            ),
        ),
        (
            "three_rows.csv",
            false,
            Fitted {
                rows: 3,
                observations: 6,
            },
        ),
        (
            "pressure_kpa.csv",
            false,
            Refused(
                implausible,
                &["column pressure_bar looks like kPa", "in 27 rows", "pressure_kpa"],
            ),
        ),
        (
            "pressure_mpa.csv",
            false,
            Refused(
                implausible,
                &["column pressure_bar looks like MPa", "in 27 rows", "pressure_mpa"],
            ),
        ),
        (
            "tip_cm.csv",
            false,
            Refused(
                implausible,
                &["columns tip_uz_mm and tip_uy_mm look like cm", "in 27 rows", "tip_uz_cm"],
            ),
        ),
        (
            "angle_rad.csv",
            false,
            Refused(
                implausible,
                &["column angle_deg looks like rad", "in 27 rows", "angle_rad"],
            ),
        ),
        (
            "force_mn.csv",
            true,
            Refused(
                implausible,
                &["column force_n looks like mN", "in 27 rows", "force_mn", "force_std_mn"],
            ),
        ),
        (
            "sign_flip.csv",
            false,
            Refused(
                implausible,
                &["column tip_uy_mm has the other sign", "in 27 rows"],
            ),
        ),
        (
            "extra_column.csv",
            false,
            Refused(record, &["line 1, column specimen: unexpected column"]),
        ),
        (
            "n10.csv",
            false,
            NotFitted(&[
                "9 recorded rows lie outside the surrogate's domain",
                "column n_bellows: 10 is outside the surrogate's domain (trained N [9, 11, 13])",
                "--exclude 10,1.6,1",
            ]),
        ),
        (
            "n16.csv",
            false,
            NotFitted(&[
                "9 recorded rows lie outside the surrogate's domain",
                "column n_bellows: 16 is outside the surrogate's domain (trained N [9, 11, 13])",
                "--exclude 16,1.6,1",
            ]),
        ),
        (
            "semicolons.csv",
            false,
            Refused(separator, &["line 1: the header is one column", "looks ;-separated"]),
        ),
    ]
}

fn model() -> Surrogate {
    Surrogate::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("models/as_modelled/actuator.json"))
        .unwrap()
}

fn quick() -> CalibrationSettings {
    let mut s = CalibrationSettings::default();
    s.multistart.starts = 2;
    s.identify.profile_points = 4;
    s
}

/// Reads a case as the command-line program does: a bending file alone, or a force file
/// beside the shipped bending file.
fn read(file: &Path, force: bool) -> Result<Recordings, CalibrateError> {
    if force {
        Recordings::read_files(&shipped("bending_experiments.csv"), Some(file), None)
    } else {
        Recordings::read_files(file, None, None)
    }
}

#[test]
fn every_bad_recording_is_refused_by_name_or_fitted_in_the_open() {
    let model = model();
    let cases = cases();
    // every file of the corpus is a case here
    let mut files: Vec<String> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f.ends_with(".csv"))
        .collect();
    files.sort();
    let mut listed: Vec<String> = cases.iter().map(|c| c.0.to_string()).collect();
    listed.sort();
    assert_eq!(files, listed);
    for (file, force, expect) in cases {
        let path = corpus().join(file);
        let loaded = read(&path, force);
        match expect {
            Expect::Refused(kind, words) => {
                let Err(CalibrateError::Experiments(e)) = loaded else {
                    panic!(
                        "{file}: read without a word ({:?})",
                        loaded.map(|r| r.files)
                    );
                };
                assert!(kind(&e), "{file}: {e:?}");
                let text = e.to_string();
                assert!(text.contains(&path.display().to_string()), "{file}: {text}");
                for w in words {
                    assert!(text.contains(w), "{file}: `{w}` not in {text}");
                }
            }
            Expect::NotFitted(words) => {
                let rec = loaded.unwrap_or_else(|e| panic!("{file}: {e}"));
                let e = calibrate(&model, &rec, &quick(), &|_| {}).unwrap_err();
                let text = e.to_string();
                for w in words {
                    assert!(text.contains(w), "{file}: `{w}` not in {text}");
                }
            }
            Expect::Fitted { rows, observations } => {
                let rec = loaded.unwrap_or_else(|e| panic!("{file}: {e}"));
                let cal = calibrate(&model, &rec, &quick(), &|_| {}).unwrap();
                assert_eq!(cal.n_observations, observations, "{file}");
                assert_eq!(cal.inputs.len(), 1, "{file}: only the file given is read");
                let f = &cal.inputs[0];
                assert_eq!(f.path, path.display().to_string());
                assert_eq!((f.rows, f.default), (Some(rows), false), "{file}");
                // and the force it was not given is not fitted from anywhere
                let mut s = quick();
                s.weights = surrogate::calibrate::Weights::parse("tip,force").unwrap();
                let e = calibrate(&model, &rec, &s, &|_| {})
                    .unwrap_err()
                    .to_string();
                assert!(
                    e.contains("blocked-force recordings (none were given)"),
                    "{e}"
                );
            }
        }
    }
}

#[test]
fn the_corpus_readme_lists_every_case() {
    let readme = std::fs::read_to_string(corpus().join("README.md")).unwrap();
    for (file, _, _) in cases() {
        assert!(readme.contains(&format!("`{file}`")), "{file}");
    }
}

/// Every directory of recordings under `dir` (one holding a bending file), but the build's.
fn recording_dirs(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() && name != "target" && !name.starts_with('.') {
            recording_dirs(&p, out);
        } else if name == surrogate::calibrate::experiments::BENDING_FILE {
            out.push(dir.to_path_buf());
        }
    }
}

#[test]
fn every_committed_recording_passes_the_checks() {
    // the shipped experiments and every twin of the studies (noisy, some near zero)
    let mut dirs = Vec::new();
    recording_dirs(Path::new(env!("CARGO_MANIFEST_DIR")), &mut dirs);
    assert!(dirs.len() > 50, "{} directories", dirs.len());
    for d in dirs {
        if let Err(e) = Recordings::read_dir(&d) {
            panic!("{}: {e}", d.display());
        }
    }
}
