//! The module import graph of `src/` has no cycles: no module (file) depends, through others,
//! on a module that depends on it. The library and each binary are checked apart.
//!
//! The rules are those of `tools/import_graph.py`, which prints the graph and its cycles:
//! a module depends on another when its code names an item of it by a path (`use crate::…`,
//! `use super::…`, `use self::…`, a child module's name, or the same paths inline); a name
//! re-exported by a `use` is followed to the module that defines it; a `pub use` of a
//! descendant's item (a parent's facade) is not an edge; `mod` declarations, comments, string
//! literals and `#[cfg(test)]` modules are ignored.

mod graph;
mod source;

use std::path::Path;

use graph::Graph;
use source::collect;

/// Cycles known and left as they are (their modules, sorted): none.
const KNOWN: &[&[&str]] = &[];

#[test]
fn the_module_graph_of_src_has_no_cycles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut sources = Vec::new();
    collect(&root, &root, &mut sources);
    let graph = Graph::new(&sources);
    // the parser sees the crate: a broken one would find no cycle in an empty graph
    assert!(graph.modules.len() > 40, "{} modules", graph.modules.len());
    assert!(graph.edges.len() > 150, "{} edges", graph.edges.len());
    let known: Vec<Vec<String>> = KNOWN
        .iter()
        .map(|c| c.iter().map(|m| m.to_string()).collect())
        .collect();
    let new: Vec<_> = graph
        .cycles()
        .into_iter()
        .filter(|c| !known.contains(&c.iter().map(|m| m.name()).collect()))
        .collect();
    assert!(
        new.is_empty(),
        "import cycles (run tools/import_graph.py for the whole graph):\n{}",
        graph.describe(&new)
    );
}

#[test]
fn a_cycle_is_found_and_a_facade_is_not_one() {
    let src = |path: &str, text: &str| (path.to_string(), text.to_string());
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
    let names: Vec<Vec<String>> = graph
        .cycles()
        .iter()
        .map(|c| c.iter().map(|m| m.name()).collect())
        .collect();
    assert_eq!(
        names,
        [["a/b", "a/c"]],
        "{}",
        graph.describe(&graph.cycles())
    );
    let edge = |from: &str, to: &str| {
        graph
            .edges
            .keys()
            .any(|(f, t)| f.name() == from && t.name() == to)
    };
    assert!(edge("a/b", "a/c") && edge("a/c", "a/b") && edge("a/d", "a/b"));
    assert!(!edge("a", "a/b") && !edge("a", "a/d") && !edge("a/c", "a") && !edge("a/c", "a/d"));
}
