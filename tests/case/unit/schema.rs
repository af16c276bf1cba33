//! The unit tests of `src/schema.rs`.
//!
//! The column lists against the shipped files' headers and the module docs' tables.

use std::collections::{BTreeMap, BTreeSet};
use std::io::BufRead;
use surrogate::schema::*;

fn shipped(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The header line of a shipped file.
fn header(path: &str) -> String {
    let file = std::fs::File::open(shipped(path)).unwrap();
    let mut line = String::new();
    std::io::BufReader::new(file).read_line(&mut line).unwrap();
    line.trim_end().to_string()
}

fn joined(columns: &[Quantity]) -> String {
    columns.iter().map(|c| c.name).collect::<Vec<_>>().join(",")
}

/// Every quantity by the tag of the formats it belongs to (the docs' `files` column).
fn formats() -> Vec<(&'static str, Vec<Quantity>)> {
    vec![
        (
            "snapshots",
            [&SNAPSHOT_COLUMNS[..], &PROVENANCE_COLUMNS].concat(),
        ),
        (
            "query",
            [&QUERY_COLUMNS[..], &[MATERIAL], &OGDEN_COLUMNS].concat(),
        ),
        (
            "prediction",
            [
                &PREDICTION_INPUT_COLUMNS[..],
                &OUTPUTS,
                &[IN_DOMAIN, OUTSIDE_DOMAIN],
            ]
            .concat(),
        ),
        (
            "model",
            [&PREDICTION_INPUT_COLUMNS[..], &OUTPUTS, &VALIDATION_GROUPS].concat(),
        ),
        ("domain", DOMAIN_INPUTS.to_vec()),
        (
            "calibration",
            [&OGDEN_COLUMNS[..], &OGDEN_COORDINATES].concat(),
        ),
        ("bending", BENDING_COLUMNS.to_vec()),
        ("force", FORCE_COLUMNS.to_vec()),
        ("markers", MARKER_RECORDING_COLUMNS.to_vec()),
        (
            "units",
            RECORDING_UNIT_COLUMNS.iter().map(|u| u.column).collect(),
        ),
    ]
}

#[test]
fn unit_columns_stand_for_a_recording_column_of_the_same_quantity() {
    let recordings = [
        &BENDING_COLUMNS[..],
        &FORCE_COLUMNS,
        &MARKER_RECORDING_COLUMNS,
    ]
    .concat();
    for u in RECORDING_UNIT_COLUMNS {
        assert!(recordings.contains(&u.canonical), "{}", u.column.name);
        // the same stem, another unit suffix
        let stem = |name: &'static str| name.rsplit_once('_').map_or(name, |(s, _)| s);
        assert_eq!(stem(u.column.name), stem(u.canonical.name));
        assert_ne!(u.column.unit, u.canonical.unit);
        assert!(u.to_canonical.is_finite() && u.to_canonical > 0.0);
        assert!(!recordings.iter().any(|c| c.name == u.column.name));
    }
}

#[test]
fn names_are_unique_within_each_list() {
    let lists: [(&str, &[Quantity]); 14] = [
        ("SNAPSHOT_COLUMNS", &SNAPSHOT_COLUMNS),
        ("PROVENANCE_COLUMNS", &PROVENANCE_COLUMNS),
        (
            "snapshot store",
            &[&SNAPSHOT_COLUMNS[..], &PROVENANCE_COLUMNS].concat(),
        ),
        ("OUTPUTS", &OUTPUTS),
        ("VALIDATION_GROUPS", &VALIDATION_GROUPS),
        ("QUERY_COLUMNS", &QUERY_COLUMNS),
        ("OGDEN_COLUMNS", &OGDEN_COLUMNS),
        ("OGDEN_COORDINATES", &OGDEN_COORDINATES),
        (
            "prediction",
            &[
                &PREDICTION_INPUT_COLUMNS[..],
                &OUTPUTS,
                &[IN_DOMAIN, OUTSIDE_DOMAIN],
            ]
            .concat(),
        ),
        ("DOMAIN_INPUTS", &DOMAIN_INPUTS),
        ("BENDING_COLUMNS", &BENDING_COLUMNS),
        ("FORCE_COLUMNS", &FORCE_COLUMNS),
        ("MARKER_RECORDING_COLUMNS", &MARKER_RECORDING_COLUMNS),
        ("markers", &[&MARKER_UZ[..], &MARKER_UY].concat()),
    ];
    for (list, columns) in lists {
        let mut seen = BTreeSet::new();
        for c in columns {
            assert!(seen.insert(c.name), "{list}: `{}` twice", c.name);
        }
    }
    // one meaning and unit per name, wherever it is listed
    let mut by_name = BTreeMap::new();
    for (_, columns) in formats() {
        for c in columns {
            assert_eq!(*by_name.entry(c.name).or_insert(c), c, "{}", c.name);
        }
    }
}

#[test]
fn column_lists_are_the_shipped_files_headers() {
    let store = [&SNAPSHOT_COLUMNS[..], &PROVENANCE_COLUMNS].concat();
    assert_eq!(header("training_data/snapshots_coarse.csv"), joined(&store));
    assert_eq!(
        header("training_data/bending_experiments.csv"),
        joined(&BENDING_COLUMNS)
    );
    assert_eq!(
        header("training_data/blocked_force_experiments.csv"),
        joined(&FORCE_COLUMNS)
    );
    // a model file: inputs with units, outputs, validation groups
    let text = std::fs::read_to_string(shipped("models/as_modelled/actuator.json")).unwrap();
    let model: serde_json::Value = serde_json::from_str(&text).unwrap();
    let model = &model["model"];
    let inputs: Vec<(&str, &str)> = model["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| (i["name"].as_str().unwrap(), i["unit"].as_str().unwrap()))
        .collect();
    let expected: Vec<(&str, &str)> = PREDICTION_INPUT_COLUMNS
        .iter()
        .map(|c| (c.name, c.unit))
        .collect();
    assert_eq!(inputs, expected);
    let strings = |v: &serde_json::Value| -> Vec<String> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(strings(&model["outputs"]), names(&OUTPUTS));
    let groups: Vec<&str> = model["validation"]["outputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["name"].as_str().unwrap())
        .collect();
    assert_eq!(groups, names(&VALIDATION_GROUPS));
    // a plan's ranges are the domain inputs but the pressure (a plan has a pressure ramp)
    let text =
        std::fs::read_to_string(shipped("training_data/snapshots_coarse.plan.json")).unwrap();
    let plan: serde_json::Value = serde_json::from_str(&text).unwrap();
    let ranges: BTreeSet<&str> = plan["ranges"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    let expected: BTreeSet<&str> = DOMAIN_INPUTS
        .iter()
        .filter(|c| **c != PRESSURE)
        .map(|c| c.name)
        .collect();
    assert_eq!(ranges, expected);
}

/// The module docs' table: column → (unit, meaning, tags).
fn doc_table() -> BTreeMap<String, (String, String, BTreeSet<String>)> {
    let mut rows = BTreeMap::new();
    for line in include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/schema.rs")).lines() {
        let Some(row) = line.strip_prefix("//! | `") else {
            continue;
        };
        let cells: Vec<&str> = row.trim_end_matches(" |").split(" | ").collect();
        assert_eq!(cells.len(), 4, "{line}");
        let tags = cells[3].split(", ").map(str::to_string).collect();
        let (unit, meaning) = (cells[1].to_string(), cells[2].to_string());
        let column = cells[0].trim_end_matches('`');
        // `m1_uz_mm` … `m9_uz_mm`: one row for the nine markers, meaning with `k`
        let expanded: Vec<(String, String)> = match column.split_once("` … `") {
            Some((first, _)) => (1..=9)
                .map(|k| {
                    let name = first.replacen('1', &k.to_string(), 1);
                    (name, meaning.replacen(" k ", &format!(" {k} "), 1))
                })
                .collect(),
            None => vec![(column.to_string(), meaning)],
        };
        for (name, meaning) in expanded {
            let old = rows.insert(name, (unit.clone(), meaning, BTreeSet::clone(&tags)));
            assert!(old.is_none(), "{line}: given twice");
        }
    }
    rows
}

#[test]
fn docs_table_lists_every_quantity_with_its_unit_meaning_and_files() {
    let table = doc_table();
    let mut listed = BTreeSet::new();
    for (tag, columns) in formats() {
        for c in columns {
            let (unit, meaning, tags) = table
                .get(c.name)
                .unwrap_or_else(|| panic!("`{}` is not in the docs' table", c.name));
            let want_unit = if c.unit.is_empty() { "—" } else { c.unit };
            assert_eq!(unit, want_unit, "{}", c.name);
            assert_eq!(meaning, c.meaning, "{}", c.name);
            assert!(tags.contains(tag), "`{}`: files lack {tag}", c.name);
            listed.insert(c.name.to_string());
        }
    }
    for (name, (_, _, tags)) in &table {
        for tag in tags {
            let format = formats().into_iter().find(|(t, _)| t == tag);
            let (_, columns) = format.unwrap_or_else(|| panic!("`{name}`: unknown file {tag}"));
            assert!(
                columns.iter().any(|c| c.name == name),
                "`{name}` is not in {tag}"
            );
        }
    }
    assert_eq!(table.keys().cloned().collect::<BTreeSet<_>>(), listed);
}
