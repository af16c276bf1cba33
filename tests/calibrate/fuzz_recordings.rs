//! The recording readers under random input (proptest): arbitrary text, the shipped files with
//! a random fault, and every subset of the shipped rows in another unit. The readers never
//! panic; what they accept is finite, unique and in the format's units; a unit or sign fault
//! is refused naming the unit, whatever the rows.

use proptest::prelude::*;
use surrogate::calibrate::experiments::{
    parse_bending, parse_force, parse_markers, BendingRecord, ExperimentError, ForceRecord,
};

const BENDING: &str = include_str!("../../training_data/bending_experiments.csv");
const FORCE: &str = include_str!("../../training_data/blocked_force_experiments.csv");
const MARKERS: &str = "n_bellows,wall_thickness_mm,pressure_bar,marker,uz_mm,uy_mm,std_mm\n\
                       9,1.6,1,9,9.4,-35.9,2\n9,1.6,1,5,3.1,-14.2,1.5\n11,2,2,9,27.3,-55.4,2\n";

/// Cells a faulty file may hold.
fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("-0".to_string()),
        Just("1e308".to_string()),
        Just("9.5".to_string()),
        Just("1,5".to_string()),
        Just("\"".to_string()),
        any::<f64>().prop_map(|x| x.to_string()),
        "[ -~]{0,8}",
    ]
}

/// A fault applied to the text of a recording.
#[derive(Clone, Debug)]
enum Fault {
    /// Cell (row, column) replaced.
    Cell(usize, usize, String),
    /// A header cell replaced.
    Header(usize, String),
    /// A column dropped.
    DropColumn(usize),
    /// A row repeated.
    RepeatRow(usize),
    /// A column multiplied.
    Scale(usize, f64),
    /// The text cut at a byte.
    Truncate(usize),
    /// Commas replaced by another separator.
    Separator(char),
}

fn fault() -> impl Strategy<Value = Fault> {
    prop_oneof![
        (0..40usize, 0..8usize, cell()).prop_map(|(r, c, v)| Fault::Cell(r, c, v)),
        (0..8usize, "[a-z_]{0,16}").prop_map(|(c, v)| Fault::Header(c, v)),
        (0..8usize).prop_map(Fault::DropColumn),
        (0..40usize).prop_map(Fault::RepeatRow),
        (
            0..8usize,
            prop_oneof![
                Just(0.001),
                Just(0.01),
                Just(0.1),
                Just(10.0),
                Just(100.0),
                Just(1000.0),
                Just(-1.0)
            ]
        )
            .prop_map(|(c, f)| Fault::Scale(c, f)),
        (0..1200usize).prop_map(Fault::Truncate),
        prop_oneof![Just(';'), Just('\t'), Just(' ')].prop_map(Fault::Separator),
    ]
}

fn apply(text: &str, faults: &[Fault]) -> String {
    let mut rows: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let mut cut = None;
    let mut sep = ',';
    for f in faults {
        let n = rows.len();
        match f {
            Fault::Cell(r, c, v) => {
                let row = &mut rows[1 + r % (n - 1)];
                let k = c % row.len();
                row[k] = v.clone();
            }
            Fault::Header(c, v) => {
                let k = c % rows[0].len();
                rows[0][k] = v.clone();
            }
            Fault::DropColumn(c) => {
                let k = c % rows[0].len();
                for row in &mut rows {
                    if k < row.len() {
                        row.remove(k);
                    }
                }
            }
            Fault::RepeatRow(r) => {
                let row = rows[1 + r % (n - 1)].clone();
                rows.push(row);
            }
            Fault::Scale(c, x) => {
                let k = c % rows[0].len();
                for row in rows.iter_mut().skip(1) {
                    if let Some(v) = row.get_mut(k).and_then(|v| {
                        let y: f64 = v.parse().ok()?;
                        Some((v, y))
                    }) {
                        *v.0 = (v.1 * x).to_string();
                    }
                }
            }
            Fault::Truncate(b) => cut = Some(*b),
            Fault::Separator(s) => sep = *s,
        }
    }
    let mut out: String = rows
        .iter()
        .map(|r| r.join(&sep.to_string()) + "\n")
        .collect();
    if let Some(b) = cut {
        let b = (0..=b.min(out.len()))
            .rev()
            .find(|&i| out.is_char_boundary(i))
            .unwrap_or(0);
        out.truncate(b);
    }
    out
}

fn bending_ok(rows: &[BendingRecord]) {
    for r in rows {
        for v in [
            r.wall_thickness_mm,
            r.pressure_bar,
            r.tip_uz_mm,
            r.tip_uy_mm,
            r.angle_deg,
        ] {
            assert!(v.is_finite());
        }
        assert!(r.angle_std_deg > 0.0);
        assert!((0.0..=10.0).contains(&r.pressure_bar), "{r:?}");
    }
}

fn force_ok(rows: &[ForceRecord]) {
    for r in rows {
        assert!(r.force_n.is_finite() && r.force_n <= 20.0 && r.force_std_n > 0.0);
        assert!((0.0..=10.0).contains(&r.pressure_bar), "{r:?}");
    }
}

/// An error names its source and says something.
fn named(e: &ExperimentError, name: &str) {
    let text = e.to_string();
    assert!(text.starts_with(name), "{text}");
    assert!(text.len() > name.len() + 10, "{text}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,400}") {
        for r in [
            parse_bending("b.csv", &text).map(|_| ()),
            parse_force("f.csv", &text).map(|_| ()),
            parse_markers("m.csv", &text).map(|_| ()),
        ] {
            if let Err(e) = r {
                prop_assert!(!e.to_string().is_empty());
            }
        }
    }

    #[test]
    fn faulty_files_are_read_in_the_format_or_refused_by_name(
        faults in prop::collection::vec(fault(), 1..4)
    ) {
        match parse_bending("b.csv", &apply(BENDING, &faults)) {
            Ok(rows) => bending_ok(&rows),
            Err(e) => named(&e, "b.csv"),
        }
        match parse_force("f.csv", &apply(FORCE, &faults)) {
            Ok(rows) => force_ok(&rows),
            Err(e) => named(&e, "f.csv"),
        }
        if let Err(e) = parse_markers("m.csv", &apply(MARKERS, &faults)) {
            named(&e, "m.csv");
        }
    }

    #[test]
    fn any_rows_in_another_unit_are_refused_naming_it(
        keep in prop::collection::vec(any::<bool>(), 27),
        unit in 0..7usize,
    ) {
        prop_assume!(keep.iter().any(|&k| k));
        let pick = |text: &str| -> String {
            let mut lines = text.lines();
            let mut out = format!("{}\n", lines.next().unwrap());
            for (line, k) in lines.zip(&keep) {
                if *k {
                    out.push_str(line);
                    out.push('\n');
                }
            }
            out
        };
        // (file is force, column, factor, the unit named)
        let (force, column, factor, likely) = [
            (false, 2, 100.0, "looks like kPa"),
            (false, 2, 0.1, "looks like MPa"),
            (false, 3, 0.1, "look like cm"),
            (false, 5, std::f64::consts::PI / 180.0, "looks like rad"),
            (false, 4, -1.0, "has the other sign"),
            (true, 3, 1000.0, "looks like mN"),
            (true, 2, 0.1, "looks like MPa"),
        ][unit];
        let text = pick(if force { FORCE } else { BENDING });
        let mut faults = vec![Fault::Scale(column, factor)];
        if column == 3 && !force {
            faults.push(Fault::Scale(4, factor)); // both tip components in cm
        }
        let bad = apply(&text, &faults);
        let e = if force {
            parse_force("f.csv", &bad).map(|_| ()).unwrap_err()
        } else {
            parse_bending("b.csv", &bad).map(|_| ()).unwrap_err()
        };
        prop_assert!(matches!(e, ExperimentError::Implausible { .. }), "{}", e);
        prop_assert!(e.to_string().contains(likely), "{}", e);
    }
}
