//! Reading the sources: files and their modules, a lexer that blanks comments and literals,
//! inline modules, item definitions and `use` trees.

use std::collections::BTreeSet;
use std::path::Path;

/// `(path relative to src/, text)` of every `.rs` file under `dir`.
pub(crate) fn collect(root: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
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
pub(crate) struct Module {
    pub krate: String,
    pub path: Vec<String>,
}

impl Module {
    pub(crate) fn name(&self) -> String {
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

/// The unit tests left in the library: `(path relative to src/, line)` of every `#[test]`,
/// `#[cfg(test)]` or other `cfg` attribute naming `test` (spaces allowed, comments and literals
/// aside) in a file outside `bin/`.
pub(crate) fn unit_tests(sources: &[(String, String)]) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    for (rel, text) in sources {
        if rel.starts_with("bin/") {
            continue;
        }
        let stripped = strip(text);
        for (i, line) in stripped.split(|&c| c == b'\n').enumerate() {
            let compact: String = String::from_utf8_lossy(line)
                .chars()
                .filter(|c| !c.is_whitespace())
                .collect();
            let cfg = ["#[cfg", "#![cfg", "#[cfg_attr", "#![cfg_attr"]
                .iter()
                .filter_map(|a| compact.find(&format!("{a}(")))
                .min()
                .map(|k| &compact[k..]);
            let names_test = cfg.is_some_and(|c| {
                ["(test)", "(test,", ",test)", ",test,"]
                    .iter()
                    .any(|t| c.contains(t))
            });
            if compact.contains("#[test]") || names_test {
                out.push((rel.clone(), i + 1));
            }
        }
    }
    out
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
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

pub(crate) fn is(t: &Tok, word: &str) -> bool {
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
pub(crate) fn visibility_before(toks: &[(Tok, usize)], k: usize) -> Option<usize> {
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

pub(crate) struct File {
    pub module: Module,
    pub rel: String,
    pub toks: Vec<(Tok, usize)>,
    inline: Vec<Inline>,
    pub defined: BTreeSet<String>,
}

impl File {
    pub(crate) fn new(rel: &str, text: &str) -> Self {
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
    pub(crate) fn scope_at(&self, k: usize) -> (Vec<String>, bool) {
        self.inline
            .iter()
            .filter(|m| m.span.0 <= k && k <= m.span.1)
            .max_by_key(|m| m.path.len())
            .map_or((Vec::new(), false), |m| (m.path.clone(), m.test))
    }
}

/// Leaves of a use tree as (segments, bound name); `self` in braces is the prefix.
pub(crate) fn use_leaves(toks: &[Tok]) -> Vec<(Vec<String>, String)> {
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
