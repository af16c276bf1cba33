//! Snapshot CSV contract: column rule, bad cells, unconverged rows, ramps per case.
use surrogate::rom::data::SnapshotSet;
use surrogate::rom::RomError;
use surrogate::schema::SNAPSHOT_COLUMN_NAMES;

use crate::rom_common;

fn read(text: &str) -> Result<SnapshotSet, RomError> {
    SnapshotSet::from_reader(text.as_bytes(), "t.csv")
}

/// Replaces line `line` (1-based) of a CSV text.
fn edit_line(text: &str, line: usize, f: impl Fn(&str) -> String) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == line { f(l) } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn trailing_provenance_columns_are_ignored() {
    let text = rom_common::synthetic_csv(3, 1);
    assert!(text
        .lines()
        .next()
        .unwrap()
        .ends_with("newton_iterations,mesh,code_version"));
    let set = read(&text).unwrap();
    assert_eq!(set.rows.len(), 3 * 15);
    // no trailing columns at all is fine too
    let bare: String = text
        .lines()
        .map(|l| {
            l.split(',')
                .take(SNAPSHOT_COLUMN_NAMES.len())
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        })
        .collect();
    assert_eq!(read(&bare).unwrap().rows.len(), 45);
}

#[test]
fn extra_column_between_required_ones_is_an_error_naming_it() {
    let text = rom_common::synthetic_csv(2, 1);
    let text = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let mut c: Vec<&str> = l.split(',').collect();
            c.insert(3, if i == 0 { "density" } else { "1.19e-9" });
            c.join(",")
        })
        .collect::<Vec<_>>()
        .join("\n");
    let e = read(&text).unwrap_err().to_string();
    assert!(
        e.contains("unknown column `density` at position 4") && e.contains("mu1_mpa"),
        "{e}"
    );
}

#[test]
fn missing_required_column_is_an_error_naming_it() {
    let text = rom_common::synthetic_csv(2, 1);
    let text = text
        .lines()
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            c[..SNAPSHOT_COLUMN_NAMES.len() - 1].join(",")
        })
        .collect::<Vec<_>>()
        .join("\n");
    let e = read(&text).unwrap_err().to_string();
    assert!(e.contains("missing required column `m9_uy_mm`"), "{e}");
}

#[test]
fn nan_cell_names_line_and_column() {
    let text = rom_common::synthetic_csv(2, 1);
    let text = edit_line(&text, 5, |l| {
        let mut c: Vec<String> = l.split(',').map(String::from).collect();
        c[11] = "NaN".into(); // angle_deg
        c.join(",")
    });
    let e = read(&text).unwrap_err().to_string();
    assert!(
        e.contains("line 5") && e.contains("`angle_deg`") && e.contains("finite number"),
        "{e}"
    );
}

#[test]
fn inadmissible_material_and_bad_integer_are_rejected() {
    let text = rom_common::synthetic_csv(1, 1);
    let neg = edit_line(&text, 2, |l| {
        let mut c: Vec<String> = l.split(',').map(String::from).collect();
        c[4] = "-3.0".into(); // alpha1 with mu1 > 0
        c.join(",")
    });
    assert!(read(&neg).unwrap_err().to_string().contains("μ₁α₁ > 0"));
    let frac = edit_line(&text, 3, |l| {
        let mut c: Vec<String> = l.split(',').map(String::from).collect();
        c[1] = "9.5".into();
        c.join(",")
    });
    let e = read(&frac).unwrap_err().to_string();
    assert!(e.contains("line 3") && e.contains("`n_bellows`"), "{e}");
}

#[test]
fn unconverged_rows_are_skipped_and_truncated_ramps_dropped() {
    let cfg = surrogate::rom::synthetic::SyntheticConfig {
        n_cases: 20,
        unconverged_fraction: 0.3,
        ..Default::default()
    };
    let mut buf = Vec::new();
    surrogate::rom::synthetic::write_csv(&cfg, &mut buf).unwrap();
    let set = SnapshotSet::from_reader(buf.as_slice(), "s").unwrap();
    assert!(set.skipped_unconverged > 0 && set.skipped_unconverged.is_multiple_of(2));
    let dropped_expected = set.skipped_unconverged / 2;
    let cases = set.into_cases().unwrap();
    assert_eq!(cases.pressures.len(), 15);
    assert_eq!(cases.dropped.len(), dropped_expected);
    assert_eq!(cases.cases.len(), 20 - dropped_expected);
}

#[test]
fn interior_gap_is_interpolated_and_inconsistent_case_rejected() {
    let text = rom_common::synthetic_csv(3, 1);
    // drop line 5 (case 0, pressure 0.75): interior gap
    let gap: String = text
        .lines()
        .enumerate()
        .filter(|(i, _)| *i != 4)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let cases = read(&gap).unwrap().into_cases().unwrap();
    assert_eq!(cases.interpolated_points, 1);
    assert_eq!(cases.cases.len(), 3);
    let bad = edit_line(&text, 4, |l| {
        let mut c: Vec<String> = l.split(',').map(String::from).collect();
        c[2] = "2.71".into();
        c.join(",")
    });
    let e = read(&bad).unwrap().into_cases().unwrap_err().to_string();
    assert!(e.contains("line 4") && e.contains("same design"), "{e}");
}

#[test]
fn sets_of_distinct_cases_append_and_a_shared_case_is_named() {
    let text = rom_common::synthetic_csv(3, 1);
    let mut a = read(&text).unwrap();
    let other = text.replace("\ncase", "\next_case");
    let b = SnapshotSet::from_reader(other.as_bytes(), "ext.csv").unwrap();
    let (rows_a, rows_b) = (a.rows.len(), b.rows.len());
    a.append(b).unwrap();
    assert_eq!(a.rows.len(), rows_a + rows_b);
    assert_eq!(a.source, "t.csv + ext.csv");
    assert_eq!(a.clone().into_cases().unwrap().cases.len(), 6);
    // the same cases again: refused, naming the case and both sets
    let again = SnapshotSet::from_reader(text.as_bytes(), "again.csv").unwrap();
    let err = a.append(again).unwrap_err().to_string();
    assert!(
        err.starts_with("again.csv: case `case0000` is also in t.csv + ext.csv"),
        "{err}"
    );
    assert_eq!(a.rows.len(), rows_a + rows_b, "a refused set adds nothing");
}
