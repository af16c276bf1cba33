//! The graph: paths resolved to the modules that define their items, edges, cycles.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::source::{is, use_leaves, visibility_before, File, Module, Tok};

/// A reference: the file and line that make an edge, and the path as written.
pub(crate) type Reference = (String, usize, String);

pub(crate) struct Graph {
    pub modules: BTreeSet<Module>,
    pub edges: BTreeMap<(Module, Module), Reference>,
}

struct Uses {
    /// Per module: names bound by its top-level `use`s → the absolute paths they name.
    bindings: HashMap<Module, HashMap<String, Vec<Vec<String>>>>,
    /// Per module: the absolute prefixes of its glob imports.
    globs: HashMap<Module, Vec<Vec<String>>>,
}

impl Graph {
    pub(crate) fn new(sources: &[(String, String)]) -> Self {
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
    pub(crate) fn cycles(&self) -> Vec<Vec<Module>> {
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
    pub(crate) fn describe(&self, cycles: &[Vec<Module>]) -> String {
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
