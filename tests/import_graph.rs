//! The module import graph of `src/` has no cycles: no module (file) depends, through others,
//! on a module that depends on it. The library and each binary are checked apart.
//!
//! The rules are those of `tools/import_graph.py`, which prints the graph and its cycles:
//! a module depends on another when its code names an item of it by a path (`use crate::…`,
//! `use super::…`, `use self::…`, a child module's name, or the same paths inline); a name
//! re-exported by a `use` is followed to the module that defines it; a `pub use` of a
//! descendant's item (a parent's facade) is not an edge; `mod` declarations, comments, string
//! literals and `#[cfg(test)]` modules are ignored.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

/// Cycles known and left as they are (their modules, sorted): the material module and its
/// isotropic kinematics share `Tangent9` and the Jacobian helpers in both directions.
const KNOWN: &[&[&str]] = &[&["fe/material", "fe/material/isotropic"]];

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

/// `(path relative to src/, text)` of every `.rs` file under `dir`.
fn collect(root: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect(root, &p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            let rel = p
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            out.push((rel, std::fs::read_to_string(&p).unwrap()));
        }
    }
}

/// A module: its crate (`lib` or `bin:<name>`) and its path in that crate.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
struct Module {
    krate: String,
    path: Vec<String>,
}

impl Module {
    fn name(&self) -> String {
        let m = if self.path.is_empty() {
            if self.krate == "lib" {
                "lib.rs"
            } else {
                "main.rs"
            }
            .to_string()
        } else {
            self.path.join("/")
        };
        if self.krate == "lib" {
            m
        } else {
            format!("{}:{m}", self.krate)
        }
    }
}

/// The module of a file (path relative to `src/`).
fn module_of(rel: &str) -> Module {
    let mut parts: Vec<String> = rel.split('/').map(str::to_string).collect();
    let krate = if parts[0] == "bin" {
        let name = parts[1].trim_end_matches(".rs").to_string();
        parts.drain(..2.min(parts.len()));
        if parts == ["main.rs"] {
            parts.clear();
        }
        format!("bin:{name}")
    } else {
        if parts == ["lib.rs"] || parts == ["main.rs"] {
            parts.clear();
        }
        "lib".to_string()
    };
    if parts.last().is_some_and(|p| p == "mod.rs") {
        parts.pop();
    } else if let Some(last) = parts.last_mut() {
        *last = last.trim_end_matches(".rs").to_string();
    }
    Module { krate, path: parts }
}

/// The source with comments, string and char literals blanked (newlines kept).
fn strip(src: &str) -> Vec<u8> {
    let s = src.as_bytes();
    let n = s.len();
    let mut out = s.to_vec();
    let blank = |out: &mut Vec<u8>, a: usize, b: usize| {
        for c in &mut out[a..b.min(n)] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
    };
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut i = 0;
    while i < n {
        if s[i..].starts_with(b"//") {
            let j = s[i..].iter().position(|&c| c == b'\n').map_or(n, |k| i + k);
            blank(&mut out, i, j);
            i = j;
        } else if s[i..].starts_with(b"/*") {
            let (mut depth, mut j) = (1, i + 2);
            while j < n && depth > 0 {
                if s[j..].starts_with(b"/*") {
                    depth += 1;
                    j += 2;
                } else if s[j..].starts_with(b"*/") {
                    depth -= 1;
                    j += 2;
                } else {
                    j += 1;
                }
            }
            blank(&mut out, i, j);
            i = j;
        } else if (s[i] == b'r' || s[i..].starts_with(b"br")) && (i == 0 || !ident(s[i - 1])) && {
            let k = i + if s[i] == b'b' { 2 } else { 1 };
            let h = s[k..].iter().take_while(|&&c| c == b'#').count();
            s.get(k + h) == Some(&b'"')
        } {
            let k = i + if s[i] == b'b' { 2 } else { 1 };
            let h = s[k..].iter().take_while(|&&c| c == b'#').count();
            let close: Vec<u8> = std::iter::once(b'"')
                .chain(std::iter::repeat_n(b'#', h))
                .collect();
            let body = k + h + 1;
            let j = s[body..]
                .windows(close.len())
                .position(|w| w == close.as_slice())
                .map_or(n, |p| body + p + close.len());
            blank(&mut out, i, j);
            i = j;
        } else if s[i] == b'"' {
            let mut j = i + 1;
            while j < n && s[j] != b'"' {
                j += if s[j] == b'\\' { 2 } else { 1 };
            }
            blank(&mut out, i, j + 1);
            i = j + 1;
        } else if s[i] == b'\'' {
            // a char literal ('a', '\n', '\u{..}', 'é'), not a lifetime ('a)
            let end = if s.get(i + 1) == Some(&b'\\') {
                let from = (i + 3).min(n);
                s[from..].iter().position(|&c| c == b'\'').map(|p| from + p)
            } else {
                let len = match s.get(i + 1) {
                    Some(&c) if c >= 0xF0 => 4,
                    Some(&c) if c >= 0xE0 => 3,
                    Some(&c) if c >= 0xC0 => 2,
                    _ => 1,
                };
                (s.get(i + 1 + len) == Some(&b'\'')).then_some(i + 1 + len)
            };
            match end {
                Some(e) if e - i <= 12 => {
                    blank(&mut out, i, e + 1);
                    i = e + 1;
                }
                _ => i += 1,
            }
        } else {
            i += 1;
        }
    }
    out
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    PathSep,
    Punct(u8),
}

/// Tokens of stripped source, with their line numbers.
fn tokens(s: &[u8]) -> Vec<(Tok, usize)> {
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < s.len() {
        let c = s[i];
        if c == b'\n' {
            line += 1;
            i += 1;
        } else if c.is_ascii_whitespace() || c >= 0x80 {
            i += 1;
        } else if c.is_ascii_digit() {
            while i < s.len() && (s[i].is_ascii_alphanumeric() || s[i] == b'_') {
                i += 1;
            }
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let j = i + s[i..]
                .iter()
                .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_')
                .count();
            let word = std::str::from_utf8(&s[i..j]).unwrap();
            out.push((Tok::Ident(word.to_string()), line));
            i = j;
        } else if s[i..].starts_with(b"::") {
            out.push((Tok::PathSep, line));
            i += 2;
        } else {
            out.push((Tok::Punct(c), line));
            i += 1;
        }
    }
    out
}

fn is(t: &Tok, word: &str) -> bool {
    matches!(t, Tok::Ident(w) if w == word)
}

/// Index of the token that closes the bracket opened at `open` (or the last token).
fn closing(toks: &[(Tok, usize)], open: usize) -> usize {
    let (o, c) = match toks[open].0 {
        Tok::Punct(b'{') => (b'{', b'}'),
        Tok::Punct(b'(') => (b'(', b')'),
        _ => (b'[', b']'),
    };
    let mut depth = 0;
    for (k, (t, _)) in toks.iter().enumerate().skip(open) {
        match t {
            Tok::Punct(x) if *x == o => depth += 1,
            Tok::Punct(x) if *x == c => {
                depth -= 1;
                if depth == 0 {
                    return k;
                }
            }
            _ => {}
        }
    }
    toks.len() - 1
}

/// Index of the token that opens the bracket closed at `close`.
fn opening(toks: &[(Tok, usize)], close: usize) -> Option<usize> {
    let (o, c) = match toks[close].0 {
        Tok::Punct(b'}') => (b'{', b'}'),
        Tok::Punct(b')') => (b'(', b')'),
        _ => (b'[', b']'),
    };
    let mut depth = 0;
    for k in (0..=close).rev() {
        match toks[k].0 {
            Tok::Punct(x) if x == c => depth += 1,
            Tok::Punct(x) if x == o => {
                depth -= 1;
                if depth == 0 {
                    return Some(k);
                }
            }
            _ => {}
        }
    }
    None
}

/// Start of the visibility (`pub`, `pub(…)`) ending just before `k`, if any.
fn visibility_before(toks: &[(Tok, usize)], k: usize) -> Option<usize> {
    let p = k.checked_sub(1)?;
    if is(&toks[p].0, "pub") {
        return Some(p);
    }
    if toks[p].0 == Tok::Punct(b')') {
        let open = opening(toks, p)?;
        return (open > 0 && is(&toks[open - 1].0, "pub")).then_some(open - 1);
    }
    None
}

/// Whether the item starting at `k` carries `#[cfg(test)]`.
fn is_cfg_test(toks: &[(Tok, usize)], mut k: usize) -> bool {
    while k > 0 && toks[k - 1].0 == Tok::Punct(b']') {
        let Some(open) = opening(toks, k - 1) else {
            return false;
        };
        let inner: Vec<&Tok> = toks[open + 1..k - 1].iter().map(|(t, _)| t).collect();
        let test = [
            Tok::Ident("cfg".into()),
            Tok::Punct(b'('),
            Tok::Ident("test".into()),
            Tok::Punct(b')'),
        ];
        if inner.len() == 4 && inner.iter().zip(&test).all(|(a, b)| *a == b) {
            return true;
        }
        k = open.saturating_sub(1); // the `#`
    }
    false
}

/// An inline module: its token span, its path inside the file, whether it is `cfg(test)`.
struct Inline {
    span: (usize, usize),
    path: Vec<String>,
    test: bool,
}

struct File {
    module: Module,
    rel: String,
    toks: Vec<(Tok, usize)>,
    inline: Vec<Inline>,
    defined: BTreeSet<String>,
}

impl File {
    fn new(rel: &str, text: &str) -> Self {
        let toks = tokens(&strip(text));
        let mut raw = Vec::new();
        let mut defined = BTreeSet::new();
        for k in 0..toks.len().saturating_sub(1) {
            if let (Tok::Ident(kw), Tok::Ident(name)) = (&toks[k].0, &toks[k + 1].0) {
                let item = [
                    "fn", "struct", "enum", "trait", "type", "const", "static", "union", "mod",
                ];
                if item.contains(&kw.as_str()) {
                    defined.insert(name.clone());
                }
                if kw == "mod" && toks.get(k + 2).is_some_and(|t| t.0 == Tok::Punct(b'{')) {
                    let start = visibility_before(&toks, k).unwrap_or(k);
                    let test = is_cfg_test(&toks, start);
                    raw.push((k + 2, closing(&toks, k + 2), name.clone(), test));
                }
            }
            if is(&toks[k].0, "macro_rules") && toks[k + 1].0 == Tok::Punct(b'!') {
                if let Some((Tok::Ident(name), _)) = toks.get(k + 2) {
                    defined.insert(name.clone());
                }
            }
        }
        let inline = raw
            .iter()
            .map(|&(a, b, ref name, test)| {
                let outer: Vec<_> = raw.iter().filter(|o| o.0 < a && b <= o.1).collect();
                let mut path: Vec<String> = outer.iter().map(|o| o.2.clone()).collect();
                path.push(name.clone());
                Inline {
                    span: (a, b),
                    path,
                    test: test || outer.iter().any(|o| o.3),
                }
            })
            .collect();
        File {
            module: module_of(rel),
            rel: rel.to_string(),
            toks,
            inline,
            defined,
        }
    }

    /// Inline module path and `cfg(test)` at token `k`.
    fn scope_at(&self, k: usize) -> (Vec<String>, bool) {
        self.inline
            .iter()
            .filter(|m| m.span.0 <= k && k <= m.span.1)
            .max_by_key(|m| m.path.len())
            .map_or((Vec::new(), false), |m| (m.path.clone(), m.test))
    }
}

/// Leaves of a use tree as (segments, bound name); `self` in braces is the prefix.
fn use_leaves(toks: &[Tok]) -> Vec<(Vec<String>, String)> {
    fn tree(toks: &[Tok], pos: &mut usize, prefix: &[String]) -> Vec<(Vec<String>, String)> {
        let mut segs = prefix.to_vec();
        while *pos < toks.len() {
            match &toks[*pos] {
                Tok::Punct(b'{') => {
                    *pos += 1;
                    let mut out = Vec::new();
                    while *pos < toks.len() && toks[*pos] != Tok::Punct(b'}') {
                        out.extend(tree(toks, pos, &segs));
                        if toks.get(*pos) == Some(&Tok::Punct(b',')) {
                            *pos += 1;
                        }
                    }
                    *pos += 1;
                    return out;
                }
                Tok::Punct(b',') | Tok::Punct(b'}') => break,
                Tok::PathSep => *pos += 1,
                Tok::Punct(b'*') => {
                    *pos += 1;
                    segs.push("*".into());
                }
                Tok::Ident(w) if w == "as" => {
                    *pos += 1;
                    let alias = match toks.get(*pos) {
                        Some(Tok::Ident(a)) => a.clone(),
                        _ => String::from("_"),
                    };
                    *pos += 1;
                    return vec![(segs, alias)];
                }
                Tok::Ident(w) if w == "self" && !prefix.is_empty() && segs == prefix => {
                    *pos += 1;
                }
                Tok::Ident(w) => {
                    segs.push(w.clone());
                    *pos += 1;
                }
                Tok::Punct(_) => *pos += 1,
            }
        }
        match segs.last().cloned() {
            Some(last) => vec![(segs, last)],
            None => Vec::new(),
        }
    }
    let mut pos = 0;
    let mut out = Vec::new();
    while pos < toks.len() {
        out.extend(tree(toks, &mut pos, &[]));
        pos += 1;
    }
    out
}

/// A reference: the file and line that make an edge, and the path as written.
type Reference = (String, usize, String);

struct Graph {
    modules: BTreeSet<Module>,
    edges: BTreeMap<(Module, Module), Reference>,
}

struct Uses {
    /// Per module: names bound by its top-level `use`s → the absolute paths they name.
    bindings: HashMap<Module, HashMap<String, Vec<Vec<String>>>>,
    /// Per module: the absolute prefixes of its glob imports.
    globs: HashMap<Module, Vec<Vec<String>>>,
}

impl Graph {
    fn new(sources: &[(String, String)]) -> Self {
        let files: Vec<File> = sources.iter().map(|(r, t)| File::new(r, t)).collect();
        let by_mod: HashMap<Module, &File> = files.iter().map(|f| (f.module.clone(), f)).collect();
        let is_module = |krate: &str, path: &[String]| {
            by_mod.contains_key(&Module {
                krate: krate.to_string(),
                path: path.to_vec(),
            })
        };
        // an absolute path for a path written in `f` at inline `scope`
        let absolute = |f: &File, scope: &[String], segs: &[String]| -> Option<Vec<String>> {
            let first = segs.first()?;
            if first == "crate" {
                return Some(segs[1..].to_vec());
            }
            if first == "self" || first == "super" {
                let mut cur: Vec<String> = f.module.path.iter().chain(scope).cloned().collect();
                let mut i = 0;
                while i < segs.len() && (segs[i] == "self" || segs[i] == "super") {
                    if segs[i] == "super" {
                        cur.pop();
                    }
                    i += 1;
                }
                cur.extend_from_slice(&segs[i..]);
                return Some(cur);
            }
            let mut child = f.module.path.clone();
            child.push(first.clone());
            (scope.is_empty() && is_module(&f.module.krate, &child)).then(|| {
                let mut p = f.module.path.clone();
                p.extend_from_slice(segs);
                p
            })
        };
        // every `use` (file, token, absolute path, pub), and the bindings it makes
        let mut uses = Uses {
            bindings: HashMap::new(),
            globs: HashMap::new(),
        };
        let mut use_refs = Vec::new();
        let mut use_spans: HashMap<&str, Vec<(usize, usize)>> = HashMap::new();
        for f in &files {
            let t = &f.toks;
            for k in 0..t.len() {
                if !is(&t[k].0, "use") {
                    continue;
                }
                let end = (k..t.len())
                    .find(|&e| t[e].0 == Tok::Punct(b';'))
                    .unwrap_or(t.len() - 1);
                use_spans.entry(&f.rel).or_default().push((k, end));
                let (scope, test) = f.scope_at(k);
                if test {
                    continue;
                }
                let is_pub = visibility_before(t, k).is_some();
                let tree: Vec<Tok> = t[k + 1..end].iter().map(|(x, _)| x.clone()).collect();
                for (segs, alias) in use_leaves(&tree) {
                    let Some(abs) = absolute(f, &scope, &segs) else {
                        continue;
                    };
                    use_refs.push((f, k, abs.clone(), is_pub, segs.join("::")));
                    if !scope.is_empty() {
                        continue;
                    }
                    if segs.last().is_some_and(|s| s == "*") {
                        let prefix = abs[..abs.len() - 1].to_vec();
                        uses.globs.entry(f.module.clone()).or_default().push(prefix);
                    } else {
                        let b = uses.bindings.entry(f.module.clone()).or_default();
                        b.entry(alias).or_default().push(abs);
                    }
                }
            }
        }
        let resolve = |krate: &str, path: &[String]| resolve(&by_mod, &uses, krate, path, 0);
        let mut edges = BTreeMap::new();
        let mut add = |f: &File, k: usize, abs: &[String], what: String| {
            let Some(target) = resolve(&f.module.krate, abs) else {
                return;
            };
            let to = Module {
                krate: f.module.krate.clone(),
                path: target,
            };
            if to != f.module {
                let r = (f.rel.clone(), f.toks[k].1, what);
                edges.entry((f.module.clone(), to)).or_insert(r);
            }
        };
        for (f, k, abs, is_pub, what) in &use_refs {
            let facade =
                resolve(&f.module.krate, abs).is_some_and(|t| t.starts_with(&f.module.path));
            if !(*is_pub && facade) {
                add(f, *k, abs, format!("use {what}"));
            }
        }
        for f in &files {
            let t = &f.toks;
            let spans = use_spans.get(f.rel.as_str()).cloned().unwrap_or_default();
            for k in 0..t.len() {
                let Tok::Ident(head) = &t[k].0 else {
                    continue;
                };
                if t.get(k + 1).map(|x| &x.0) != Some(&Tok::PathSep) {
                    continue;
                }
                let prev = k.checked_sub(1).map(|p| &t[p].0);
                if matches!(prev, Some(Tok::PathSep) | Some(Tok::Punct(b'$')))
                    || prev.is_some_and(|p| is(p, "in"))
                    || spans.iter().any(|&(a, b)| a <= k && k <= b)
                {
                    continue;
                }
                let (scope, test) = f.scope_at(k);
                if test {
                    continue;
                }
                let mut child = f.module.path.clone();
                child.push(head.clone());
                let relative = ["crate", "super", "self"].contains(&head.as_str());
                let child_module = scope.is_empty() && is_module(&f.module.krate, &child);
                if !(relative || child_module) {
                    continue;
                }
                let mut segs = vec![head.clone()];
                let mut j = k + 1;
                while t.get(j).map(|x| &x.0) == Some(&Tok::PathSep) {
                    match t.get(j + 1).map(|x| &x.0) {
                        Some(Tok::Ident(s)) => segs.push(s.clone()),
                        _ => break,
                    }
                    j += 2;
                }
                if let Some(abs) = absolute(f, &scope, &segs) {
                    add(f, k, &abs, segs.join("::"));
                }
            }
        }
        Graph {
            modules: files.iter().map(|f| f.module.clone()).collect(),
            edges,
        }
    }

    /// Strongly connected components of more than one module (Tarjan), sorted.
    fn cycles(&self) -> Vec<Vec<Module>> {
        let nodes: Vec<&Module> = self.modules.iter().collect();
        let index_of: HashMap<&Module, usize> =
            nodes.iter().enumerate().map(|(i, m)| (*m, i)).collect();
        let mut adj = vec![Vec::new(); nodes.len()];
        for (a, b) in self.edges.keys() {
            if let (Some(&i), Some(&j)) = (index_of.get(a), index_of.get(b)) {
                adj[i].push(j);
            }
        }
        struct Tarjan {
            index: Vec<Option<usize>>,
            low: Vec<usize>,
            stack: Vec<usize>,
            on: Vec<bool>,
            next: usize,
            comps: Vec<Vec<usize>>,
        }
        fn visit(v: usize, adj: &[Vec<usize>], s: &mut Tarjan) {
            s.index[v] = Some(s.next);
            s.low[v] = s.next;
            s.next += 1;
            s.stack.push(v);
            s.on[v] = true;
            for &w in &adj[v] {
                match s.index[w] {
                    None => {
                        visit(w, adj, s);
                        s.low[v] = s.low[v].min(s.low[w]);
                    }
                    Some(iw) if s.on[w] => s.low[v] = s.low[v].min(iw),
                    _ => {}
                }
            }
            if Some(s.low[v]) == s.index[v] {
                let mut comp = Vec::new();
                while let Some(w) = s.stack.pop() {
                    s.on[w] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                s.comps.push(comp);
            }
        }
        let n = nodes.len();
        let mut s = Tarjan {
            index: vec![None; n],
            low: vec![0; n],
            stack: Vec::new(),
            on: vec![false; n],
            next: 0,
            comps: Vec::new(),
        };
        for v in 0..n {
            if s.index[v].is_none() {
                visit(v, &adj, &mut s);
            }
        }
        let mut cycles: Vec<Vec<Module>> = s
            .comps
            .into_iter()
            .filter(|c| c.len() > 1)
            .map(|c| {
                let mut m: Vec<Module> = c.into_iter().map(|i| nodes[i].clone()).collect();
                m.sort();
                m
            })
            .collect();
        cycles.sort();
        cycles
    }

    /// Each cycle and the reference behind each of its edges.
    fn describe(&self, cycles: &[Vec<Module>]) -> String {
        let mut s = String::new();
        for c in cycles {
            let names: Vec<String> = c.iter().map(Module::name).collect();
            s.push_str(&format!("cycle: {}\n", names.join(" <-> ")));
            for ((a, b), (file, line, what)) in &self.edges {
                if c.contains(a) && c.contains(b) {
                    s.push_str(&format!(
                        "  {} -> {}: src/{file}:{line} {what}\n",
                        a.name(),
                        b.name()
                    ));
                }
            }
        }
        s
    }
}

/// The module that defines the item an absolute path names, following `use` bindings.
fn resolve(
    by_mod: &HashMap<Module, &File>,
    uses: &Uses,
    krate: &str,
    path: &[String],
    depth: usize,
) -> Option<Vec<String>> {
    if depth > 16 {
        return None;
    }
    let module = |k: usize| Module {
        krate: krate.to_string(),
        path: path[..k].to_vec(),
    };
    let k = (0..=path.len())
        .rev()
        .find(|&k| by_mod.contains_key(&module(k)))?;
    let m = module(k);
    let rest = &path[k..];
    let Some(name) = rest.first().filter(|n| *n != "*") else {
        return Some(m.path);
    };
    if by_mod[&m].defined.contains(name) {
        return Some(m.path);
    }
    let follow = |target: &Vec<String>| {
        let mut p = target.clone();
        p.extend_from_slice(&rest[1..]);
        resolve(by_mod, uses, krate, &p, depth + 1)
    };
    if let Some(targets) = uses.bindings.get(&m).and_then(|b| b.get(name)) {
        if let Some(r) = targets.iter().find_map(follow) {
            return Some(r);
        }
    }
    for g in uses.globs.get(&m).into_iter().flatten() {
        let mut p = g.clone();
        p.extend_from_slice(rest);
        if let Some(r) = resolve(by_mod, uses, krate, &p, depth + 1).filter(|r| r != g) {
            return Some(r);
        }
    }
    Some(m.path)
}
