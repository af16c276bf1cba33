//! The query and model-file parsers under random input (proptest). A query CSV with a random
//! fault is read or refused naming its line or header, never a panic. A model file with a
//! random fault in its content (the envelope's checksum made to match, so that the fault
//! reaches the parser behind it) is refused with a message, or loads and answers a query
//! with a prediction or an error, never a panic.

use std::path::Path;
use std::sync::OnceLock;

use proptest::prelude::*;
use serde_json::Value;
use surrogate::case::{OgdenSet, Query};
use surrogate::rom::batch::read_queries;
use surrogate::rom::Surrogate;

fn root(path: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The demonstration model (the smallest shipped one), loaded once.
fn model() -> &'static Surrogate {
    static M: OnceLock<Surrogate> = OnceLock::new();
    M.get_or_init(|| Surrogate::load(&root("models/synthetic_demo.json")).unwrap())
}

/// The demonstration model's content as JSON, and the paths into it a fault may hit: every
/// object member, and of each array the array itself and its first and last element.
fn content() -> &'static (Value, Vec<Vec<Step>>) {
    static C: OnceLock<(Value, Vec<Vec<Step>>)> = OnceLock::new();
    C.get_or_init(|| {
        let text = std::fs::read_to_string(root("models/synthetic_demo.json")).unwrap();
        let env: Value = serde_json::from_str(&text).unwrap();
        let model = env["model"].clone();
        let mut paths = Vec::new();
        walk(&model, &mut Vec::new(), &mut paths);
        (model, paths)
    })
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn walk(v: &Value, at: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(at.clone());
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                at.push(Step::Key(k.clone()));
                walk(x, at, out);
                at.pop();
            }
        }
        Value::Array(a) if !a.is_empty() => {
            for i in [0, a.len() - 1] {
                at.push(Step::Index(i));
                walk(&a[i], at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

/// The value at `path`, if an earlier fault left it there.
fn at<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    let pointer: String = path
        .iter()
        .map(|s| match s {
            Step::Key(k) => format!("/{}", k.replace('~', "~0").replace('/', "~1")),
            Step::Index(i) => format!("/{i}"),
        })
        .collect();
    v.pointer_mut(&pointer)
}

/// A fault in the model's content.
#[derive(Clone, Debug)]
enum ModelFault {
    /// The value at a path replaced.
    Replace(usize, Value),
    /// An array at a path cut to a length.
    Cut(usize, usize),
    /// A member removed.
    Remove(usize),
}

fn value() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        Just(Value::from(-1)),
        Just(Value::from(0)),
        Just(Value::from(1)),
        Just(Value::from(u64::MAX)),
        Just(Value::from(1e300)),
        Just(Value::from(-1e-300)),
        Just(Value::from("x")),
        Just(Value::Array(Vec::new())),
        Just(Value::Object(Default::default())),
        any::<f64>()
            .prop_filter("finite", |x| x.is_finite())
            .prop_map(Value::from),
    ]
}

fn model_fault() -> impl Strategy<Value = ModelFault> {
    prop_oneof![
        (any::<usize>(), value()).prop_map(|(p, v)| ModelFault::Replace(p, v)),
        (any::<usize>(), 0..4usize).prop_map(|(p, n)| ModelFault::Cut(p, n)),
        any::<usize>().prop_map(ModelFault::Remove),
    ]
}

/// The model file text of `model`, with a matching checksum.
fn envelope(model: &Value) -> String {
    let m = serde_json::to_string(model).unwrap();
    format!(
        r#"{{"format":"{}","format_version":{},"checksum":"crc32:{:08x}","model":{m}}}"#,
        surrogate::rom::model::FORMAT_NAME,
        surrogate::rom::model::FORMAT_VERSION,
        crc32fast::hash(m.as_bytes())
    )
}

/// A query in the middle of `m`'s ranges.
fn middle(m: &Surrogate) -> Query {
    let mid = |k: usize| m.inputs.get(k).map_or(0.5, |i| 0.5 * (i.min + i.max));
    let n = m.n_allowed.first().copied().unwrap_or(9);
    Query::new(
        n,
        mid(1),
        mid(2),
        OgdenSet::from_array([mid(3), mid(4), mid(5), mid(6)]),
    )
}

const QUERIES: &str = "id,n_bellows,wall_thickness_mm,pressure_bar,material\n\
                       a,11,2.0,1.5,ogden_002\n\
                       b,9,1.6,3.0,\"0.03821,5.996,-5.195,-1.996\"\n\
                       c,13,2.4,0.5,ogden_002\n";

fn query_cell() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("NaN".to_string()),
        Just("-inf".to_string()),
        Just("9.0".to_string()),
        Just("10".to_string()),
        Just("1e308".to_string()),
        Just("ogden_002".to_string()),
        Just("\"1,2,3,4\"".to_string()),
        Just("neo_hookean:0.5".to_string()),
        any::<f64>().prop_map(|x| x.to_string()),
        "[ -~]{0,10}",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn faulty_queries_are_read_or_refused_by_name(
        faults in prop::collection::vec((0..4usize, 0..5usize, query_cell()), 1..4),
        cut in prop::option::of(0..200usize),
    ) {
        let mut rows: Vec<Vec<String>> = QUERIES
            .lines()
            .map(|l| vec![l.to_string()])
            .collect();
        // cells of the data rows, split outside quotes
        for row in rows.iter_mut().skip(1) {
            let mut r = csv::ReaderBuilder::new()
                .has_headers(false)
                .from_reader(row[0].as_bytes());
            let rec = r.records().next().unwrap().unwrap();
            *row = rec.iter().map(|c| {
                if c.contains(',') { format!("\"{c}\"") } else { c.to_string() }
            }).collect();
        }
        let mut header: Vec<String> = rows[0][0].split(',').map(str::to_string).collect();
        for (r, c, v) in &faults {
            if *r == 0 {
                let k = c % header.len();
                header[k] = v.clone();
            } else {
                let row = &mut rows[*r];
                let k = c % row.len();
                row[k] = v.clone();
            }
        }
        let mut text = header.join(",") + "\n";
        for row in rows.iter().skip(1) {
            text.push_str(&row.join(","));
            text.push('\n');
        }
        if let Some(b) = cut {
            let b = (0..=b.min(text.len())).rev().find(|&i| text.is_char_boundary(i)).unwrap();
            text.truncate(b);
        }
        match read_queries(text.as_bytes(), "q.csv", model()) {
            Ok(t) => {
                for row in &t.rows {
                    prop_assert!(model().check_query(&row.query).is_ok());
                }
            }
            Err(e) => prop_assert!(e.to_string().contains("q.csv"), "{}", e),
        }
    }

    #[test]
    fn arbitrary_query_text_never_panics(text in "\\PC{0,300}") {
        if let Err(e) = read_queries(text.as_bytes(), "q.csv", model()) {
            prop_assert!(!e.to_string().is_empty());
        }
    }

    #[test]
    fn faulty_model_files_are_refused_or_answer(
        faults in prop::collection::vec(model_fault(), 1..3)
    ) {
        let (clean, paths) = content();
        let mut m = clean.clone();
        for f in &faults {
            match f {
                ModelFault::Replace(p, v) => {
                    if let Some(x) = at(&mut m, &paths[p % paths.len()]) {
                        *x = v.clone();
                    }
                }
                ModelFault::Cut(p, n) => {
                    if let Some(Value::Array(a)) = at(&mut m, &paths[p % paths.len()]) {
                        a.truncate(*n);
                    }
                }
                ModelFault::Remove(p) => {
                    let path = &paths[p % paths.len()];
                    if let Some((Step::Key(k), parent)) = path.split_last() {
                        if let Some(Value::Object(o)) = at(&mut m, parent) {
                            o.remove(k);
                        }
                    }
                }
            }
        }
        match Surrogate::from_json(&envelope(&m), "m.json") {
            Err(e) => prop_assert!(e.to_string().contains("m.json"), "{}", e),
            Ok(model) => {
                let q = middle(&model);
                let _ = model.predict(&q);
                let mut p = model.new_prediction();
                let _ = model.predict_with_std_into(&q, &mut p);
            }
        }
    }

    #[test]
    fn cut_model_files_are_refused(cut in 0..564_000usize) {
        let text = std::fs::read_to_string(root("models/synthetic_demo.json")).unwrap();
        let b = cut.min(text.len() - 1);
        let e = Surrogate::from_json(&text[..b], "m.json").map(|_| ()).unwrap_err();
        prop_assert!(e.to_string().contains("corrupt or truncated"), "{}", e);
    }
}

#[test]
fn the_clean_envelope_loads() {
    let (clean, _) = content();
    let m = Surrogate::from_json(&envelope(clean), "m.json").unwrap();
    assert!(m.predict(&middle(&m)).is_ok());
}
