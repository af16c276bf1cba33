//! The layering of `src/`: every module stands on a floor ([`FLOORS`], from the ground up) and
//! imports only modules of its own floor or of floors below; within a floor there is no cycle
//! (no module depends, through others, on a module that depends on it). The library and each
//! binary are read apart; a binary stands on the top floor.
//!
//! A module is a file (`src/rom/pod.rs` is `rom/pod`, `src/rom/train/mod.rs` is `rom/train`). It
//! depends on another when its code names an item of it by a path (`use crate::…`,
//! `use super::…`, `use self::…`, a child module's name, or the same paths inline); a name
//! re-exported by a `use` is followed to the module that defines it; a `pub use` of a
//! descendant's item (a parent's facade) is not an edge; `mod` declarations, comments, string
//! literals and `#[cfg(test)]` modules are ignored.
//!
//! The library has no unit-test harness (`[lib] test = false` in `Cargo.toml`: `cargo test`
//! compiles it once): its unit tests live in the test binaries, `tests/<floor>/unit/` (one file
//! per source module), and [`no_unit_test_is_left_in_the_library`] fails on a `#[cfg(test)]`
//! or `#[test]` under `src/` outside `src/bin/`, which would compile into no binary and never
//! run.
//!
//! ```sh
//! cargo test --release --test import_graph                                     # the check
//! cargo test --release --test import_graph -- --ignored --nocapture print_the_graph  # the graph
//! ```

mod floors;
mod graph;
mod source;

use std::path::Path;

use floors::{check, Floor, Known};
use graph::Graph;
use source::{collect, unit_tests};

/// The floors, from the ground up, and the top-level modules of `src/` on each. A module
/// imports only from its own floor and the floors below. The README's Layout lists the same.
const FLOORS: &[Floor] = &[
    // the shared vocabulary: the case and its parameter box, the file formats' columns and
    // units, the atomic write
    ("ground", &["case", "schema", "io", "random"]),
    // the finite-element model
    ("fe", &["fe"]),
    // sampling plans and FE snapshot campaigns
    ("snapshots", &["snapshots"]),
    // the reduced-order surrogate, trained on snapshot files
    ("rom", &["rom"]),
    // the calibrator
    ("calibrate", &["calibrate"]),
    // the design loop through the surrogate: N and T for target outputs, maps
    ("design", &["design"]),
    // the diagnoser
    ("diagnose", &["diagnose"]),
    // the crate's front: its root and the error that gathers every floor's errors
    ("crate", &["lib.rs", "error"]),
    // the program
    ("bin", &["bin"]),
];

/// Imports of a module on a higher floor that are still there, each with the reason. The test
/// fails on any other, and on one of these that is gone: the list only shrinks.
const KNOWN_UPWARD: &[Known] = &[];

fn the_crate() -> Graph {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut sources = Vec::new();
    collect(&root, &root, &mut sources);
    Graph::new(&sources)
}

#[test]
fn no_module_imports_a_floor_above_its_own() {
    let graph = the_crate();
    // the parser sees the crate: a broken one would find nothing in an empty graph
    assert!(graph.modules.len() > 40, "{} modules", graph.modules.len());
    assert!(graph.edges.len() > 150, "{} edges", graph.edges.len());
    let found = check(&graph, FLOORS, KNOWN_UPWARD);
    assert!(
        found.is_clean(),
        "the layering of src/ (FLOORS in tests/import_graph/main.rs; the whole graph: \
         cargo test --release --test import_graph -- --ignored --nocapture print_the_graph):\n{}",
        found.describe(&graph)
    );
}

/// No `#[cfg(test)]` module or `#[test]` function under `src/` outside `src/bin/`: the library
/// has no unit-test harness (`[lib] test = false`), so such a test would never run. Its unit
/// tests are in the test binary of its floor, `tests/<floor>/unit/<module>.rs`.
#[test]
fn no_unit_test_is_left_in_the_library() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut sources = Vec::new();
    collect(&root, &root, &mut sources);
    assert!(sources.len() > 40, "{} files", sources.len());
    let found: Vec<String> = unit_tests(&sources)
        .iter()
        .map(|(file, line)| format!("src/{file}:{line}"))
        .collect();
    assert!(
        found.is_empty(),
        "unit tests under src/ never run (`[lib] test = false` in Cargo.toml: the library has \
         no test harness); move each to tests/<floor>/unit/<module>.rs (see tests/fe/main.rs):\n{}",
        found.join("\n")
    );
}

#[test]
fn a_unit_test_in_the_library_is_found_and_one_in_a_binary_or_a_comment_is_not() {
    let sources = [
        src(
            "lib.rs",
            "pub mod a;\n// #[cfg(test)] in a comment\nconst S: &str = \"#[test]\";",
        ),
        src(
            "a.rs",
            "pub fn f() {}\n\n#[cfg( test )]\nmod tests {\n    #[test]\n    fn t() {}\n}",
        ),
        src(
            "b.rs",
            "#[cfg(all(unix, test))]\nfn g() {}\n#[cfg(feature = \"test\")]\nfn h() {}",
        ),
        src("bin/tool/main.rs", "#[cfg(test)]\nmod tests;"),
    ];
    let found = unit_tests(&sources);
    let found: Vec<(&str, usize)> = found.iter().map(|(f, l)| (f.as_str(), *l)).collect();
    assert_eq!(found, [("a.rs", 3), ("a.rs", 5), ("b.rs", 1)]);
}

/// Prints the graph floor by floor (`-- --ignored --nocapture print_the_graph`).
#[test]
#[ignore = "prints the module graph floor by floor, checks nothing; run: cargo test --release --test import_graph -- --ignored --nocapture print_the_graph"]
fn print_the_graph() {
    println!("{}", floors::print(&the_crate(), FLOORS));
}

fn src(path: &str, text: &str) -> (String, String) {
    (path.to_string(), text.to_string())
}

#[test]
fn an_upward_import_an_unplaced_module_and_a_stale_known_one_are_found() {
    let sources = [
        src("lib.rs", "pub mod base;\npub mod top;\npub mod stray;"),
        // the ground imports the floor above: inline, through the top's facade
        src(
            "base.rs",
            "pub struct B;\nfn f() -> crate::top::T { todo!() }",
        ),
        src("top/mod.rs", "pub mod t;\npub mod u;\npub use t::T;"),
        src("top/t.rs", "pub struct T;"),
        // a downward import
        src("top/u.rs", "use crate::base::B;\npub struct U(B);"),
        src("stray.rs", "pub struct S;"),
        src("bin/tool/main.rs", "mod args;\nuse args::A;"),
        src("bin/tool/args.rs", "pub struct A;"),
    ];
    let graph = Graph::new(&sources);
    let floors: &[Floor] = &[
        ("ground", &["base"]),
        ("top", &["top", "lib.rs", "gone"]),
        ("bin", &["bin"]),
    ];
    let known: &[Known] = &[
        ("top/u", "base", "not upward"),
        ("base", "top", "no such edge"),
    ];
    let found = check(&graph, floors, known);
    let text = found.describe(&graph);
    assert!(!found.is_clean());
    let upward: Vec<_> = found
        .upward
        .iter()
        .map(|u| (u.from.name(), u.from_floor, u.to.name(), u.to_floor))
        .collect();
    assert_eq!(
        upward,
        [("base".to_string(), "ground", "top/t".to_string(), "top")],
        "{text}"
    );
    assert!(
        text.contains("base (floor ground) imports top/t (floor top, above): src/base.rs:2"),
        "{text}"
    );
    let unplaced: Vec<_> = found.unplaced.iter().map(|m| m.name()).collect();
    assert_eq!(unplaced, ["stray"], "{text}");
    assert_eq!(found.empty, ["gone"], "{text}");
    assert_eq!(found.gone, known, "{text}");
    assert!(found.cycles.is_empty(), "{text}");
    // listed, the upward import is let through and its entry is not stale
    let known: &[Known] = &[("base", "top/t", "a reason")];
    let floors: &[Floor] = &[
        ("ground", &["base"]),
        ("top", &["top", "lib.rs", "stray"]),
        ("bin", &["bin"]),
    ];
    let found = check(&graph, floors, known);
    assert!(found.is_clean(), "{}", found.describe(&graph));
}

#[test]
fn a_cycle_within_a_floor_is_found_and_a_facade_is_not_one() {
    let sources = [
        src("lib.rs", "pub mod a;\npub use a::A;"),
        // a facade: re-exports its children's items
        src(
            "a/mod.rs",
            "pub mod b;\npub mod c;\npub mod d;\npub use b::B;\npub use c::C;\n\
             /// [crate::a::d] in a comment\npub struct A;",
        ),
        // b → c through the parent's re-export, c → b inline: a cycle
        src("a/b.rs", "use super::C;\npub struct B(C);"),
        src(
            "a/c.rs",
            "pub struct C;\nfn f() -> super::b::B { todo!(\"crate::a::d\") }\n\
             #[cfg(test)]\nmod tests { use crate::a::A; }",
        ),
        src("a/d.rs", "use super::super::a::b::B;"),
    ];
    let graph = Graph::new(&sources);
    let found = check(&graph, &[("one", &["a", "lib.rs"])], &[]);
    let text = found.describe(&graph);
    let names: Vec<Vec<String>> = found
        .cycles
        .iter()
        .map(|c| c.iter().map(|m| m.name()).collect())
        .collect();
    assert_eq!(names, [["a/b", "a/c"]], "{text}");
    assert!(found.upward.is_empty() && !found.is_clean(), "{text}");
    assert!(text.contains("cycle: a/b <-> a/c"), "{text}");
    let edge = |from: &str, to: &str| {
        graph
            .edges
            .keys()
            .any(|(f, t)| f.name() == from && t.name() == to)
    };
    assert!(edge("a/b", "a/c") && edge("a/c", "a/b") && edge("a/d", "a/b"));
    assert!(!edge("a", "a/b") && !edge("a", "a/d") && !edge("a/c", "a") && !edge("a/c", "a/d"));
}
