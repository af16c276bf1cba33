#!/usr/bin/env python3
"""Module import graph of the crate's sources, and its cycles.

A module is a file: `src/rom/train.rs` is `rom::train`, `src/rom/mod.rs` is `rom`; the binary's
files under `src/bin/<name>/` form a graph of their own (`bin:<name>`). A module depends on
another when its code names an item of it by a path: `use crate::…`, `use super::…`,
`use self::…`, a child module's name (`use pod::PodBasis` in `rom/mod.rs`), or the same paths
written inline (`crate::rom::Q_FORCE`, `super::warp::PressureWarp::fit`).

  * A path is resolved to the file that defines the item: a name brought into a module by a
    `use` (a re-export such as `pub use surrogate::Surrogate` in `rom/mod.rs`) is followed to
    the module that defines it, so `use super::Surrogate` in `rom/train.rs` is an edge to
    `rom::surrogate`, not to `rom`.
  * A `pub use` of a descendant's item is an alias, not an edge: a parent that re-exports its
    children's items (a facade) does not depend on them. Any other `pub use` is an edge.
  * `mod` declarations are not edges; comments (doc links included) and string literals are
    ignored; `#[cfg(test)]` modules are ignored unless `--tests` is given.

Prints every strongly connected component of more than one module (a cycle), with the
references that make its edges, and exits with status 1 if there is any. `tests/import_graph/`
applies the same rules in `cargo test` (same edges) and fails on any cycle but the known one
listed there.

    python3 tools/import_graph.py            # cycles of src/
    python3 tools/import_graph.py --edges    # also every edge
"""

import argparse
import re
import sys
from collections import defaultdict
from pathlib import Path

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
DEF_RE = r"\b(?:fn|struct|enum|trait|type|const|static|union|mod)\s+{name}\b|macro_rules!\s*{name}\b"


def strip(src):
    """Source with comments, string and char literals blanked (newlines kept)."""
    out = []
    i, n = 0, len(src)
    while i < n:
        c = src[i]
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif src.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if src.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif src.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif c == "r" and re.match(r'r#*"', src[i:]) and not re.match(r"[A-Za-z0-9_]", src[i - 1 : i] or " "):
            hashes = re.match(r"r(#*)\"", src[i:]).group(1)
            end = src.find('"' + hashes, i + 2 + len(hashes))
            end = n if end < 0 else end + 1 + len(hashes)
            out.append(re.sub(r"[^\n]", " ", src[i:end]))
            i = end
        elif c == '"':
            j = i + 1
            while j < n and src[j] != '"':
                j += 2 if src[j] == "\\" else 1
            out.append(re.sub(r"[^\n]", " ", src[i : j + 1]))
            i = j + 1
        elif c == "'":
            # a char literal ('a', '\n', '\u{..}'), not a lifetime ('a)
            m = re.match(r"'(?:\\u\{[0-9a-fA-F]+\}|\\.|[^\\'])'", src[i:])
            if m:
                out.append(" " * len(m.group(0)))
                i += len(m.group(0))
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


class File:
    def __init__(self, path, crate, module):
        self.path = path
        self.crate = crate
        self.module = module  # tuple of segments
        self.text = strip(path.read_text())
        self.inline = self._inline_modules()  # (start, end, segments, is_test)

    def _inline_modules(self):
        """Inline `mod name { … }` blocks: their span, path inside the file, cfg(test)."""
        found = []
        for m in re.finditer(r"\bmod\s+(" + IDENT + r")\s*\{", self.text):
            start = m.end() - 1
            depth, j = 0, start
            while j < len(self.text):
                if self.text[j] == "{":
                    depth += 1
                elif self.text[j] == "}":
                    depth -= 1
                    if depth == 0:
                        break
                j += 1
            before = self.text[max(0, m.start() - 200) : m.start()]
            attrs = re.findall(r"#\[[^\]]*\]", before.rsplit(";", 1)[-1].rsplit("}", 1)[-1])
            is_test = any(re.fullmatch(r"#\[\s*cfg\s*\(\s*test\s*\)\s*\]", a) for a in attrs)
            found.append([start, j, m.group(1), is_test])
        spans = []
        for start, end, name, is_test in found:
            outer = [s for s in found if s[0] < start and end <= s[1]]
            outer.sort()
            segs = tuple(s[2] for s in outer) + (name,)
            test = is_test or any(s[3] for s in outer)
            spans.append((start, end, segs, test))
        return spans

    def scope_at(self, pos):
        """(inline module path, inside a cfg(test) module) at a byte offset."""
        best, test = (), False
        for start, end, segs, is_test in self.inline:
            if start <= pos <= end and len(segs) > len(best):
                best, test = segs, is_test
        return best, test

    def line_of(self, pos):
        return self.text.count("\n", 0, pos) + 1


def collect(src):
    """Files of the library and of each binary, with their module paths."""
    files = []
    for p in sorted(src.rglob("*.rs")):
        rel = p.relative_to(src).parts
        if rel[0] == "bin":
            if len(rel) == 2:
                crate, parts = "bin:" + rel[1][:-3], ()
            else:
                crate, parts = "bin:" + rel[1], rel[2:]
                parts = () if parts == ("main.rs",) else parts
        else:
            crate = "lib"
            parts = () if rel in (("lib.rs",), ("main.rs",)) else rel
        if parts and parts[-1] == "mod.rs":
            parts = parts[:-1]
        elif parts:
            parts = parts[:-1] + (parts[-1][:-3],)
        files.append(File(p, crate, tuple(parts)))
    return files


def parse_use_tree(text):
    """Leaves of a use tree as (segments, bound name); `self` in braces is the prefix."""
    toks = re.findall(IDENT + r"|\{|\}|,|\*", text)
    pos = 0

    def tree(prefix):
        nonlocal pos
        segs = list(prefix)
        while pos < len(toks):
            t = toks[pos]
            if t == "{":
                pos += 1
                out = []
                while pos < len(toks) and toks[pos] != "}":
                    out += tree(segs)
                    if pos < len(toks) and toks[pos] == ",":
                        pos += 1
                pos += 1
                return out
            if t in (",", "}"):
                break
            pos += 1
            if t == "as":
                alias = toks[pos]
                pos += 1
                return [(segs, alias)]
            if t == "self" and prefix and segs == list(prefix):
                continue
            segs.append(t)
        return [(segs, segs[-1])] if segs else []

    return tree([])


class Graph:
    def __init__(self, root, files, tests):
        self.root = root
        self.files = files
        self.tests = tests
        self.by_mod = {(f.crate, f.module): f for f in files}
        self.bindings = {}  # (crate, module) -> {name: [(abs path, is_pub)]}, globs
        self.globs = defaultdict(list)
        self.uses = []  # (file, pos, abs path, is_pub)
        for f in files:
            self._scan_uses(f)

    def is_module(self, crate, segs):
        return (crate, tuple(segs)) in self.by_mod

    def absolute(self, f, scope, segs):
        """An absolute path (in f's crate) for a path written in f at inline scope, or None."""
        here = list(f.module) + list(scope)
        if not segs:
            return None
        if segs[0] == "crate":
            return segs[1:]
        if segs[0] in ("self", "super"):
            cur = here
            i = 0
            while i < len(segs) and segs[i] in ("self", "super"):
                if segs[i] == "super":
                    cur = cur[:-1]
                i += 1
            return cur + segs[i:]
        # a child module, or a name bound in this module (2018 paths)
        if self.is_module(f.crate, f.module + (segs[0],)) and not scope:
            return list(f.module) + segs
        return None

    def _scan_uses(self, f):
        b = self.bindings.setdefault((f.crate, f.module), defaultdict(list))
        for m in re.finditer(r"(\bpub(?:\s*\([^)]*\))?\s+)?\buse\s+([^;]+);", f.text):
            scope, test = f.scope_at(m.start())
            if test and not self.tests:
                continue
            is_pub = m.group(1) is not None
            for segs, alias in parse_use_tree(m.group(2)):
                a = self.absolute(f, scope, segs)
                if a is None:
                    continue
                self.uses.append((f, m.start(), a, is_pub))
                if scope:
                    continue
                if segs[-1] == "*":
                    self.globs[(f.crate, f.module)].append(a[:-1])
                else:
                    b[alias].append(a)

    def defines(self, f, name):
        return re.search(DEF_RE.format(name=re.escape(name)), f.text) is not None

    def resolve(self, crate, segs, seen=None):
        """The module (segments) that defines the item named by an absolute path."""
        seen = seen or set()
        key = (crate, tuple(segs))
        if key in seen:
            return None
        seen.add(key)
        k = len(segs)
        while k > 0 and not self.is_module(crate, segs[:k]):
            k -= 1
        mod = tuple(segs[:k])
        rest = segs[k:]
        if not rest or rest == ["*"]:
            return mod
        f = self.by_mod[(crate, mod)]
        name = rest[0]
        if self.defines(f, name):
            return mod
        for target in self.bindings.get((crate, mod), {}).get(name, []):
            r = self.resolve(crate, target + rest[1:], seen)
            if r is not None:
                return r
        for g in self.globs.get((crate, mod), []):
            r = self.resolve(crate, g + rest, seen)
            if r is not None and r != tuple(g):
                return r
        return mod

    def edges(self):
        """{(crate, from, to): [(file, line, text)]}."""
        out = defaultdict(list)

        def add(f, pos, a, what):
            target = self.resolve(f.crate, a)
            if target is None or target == f.module:
                return
            rel = f.path.relative_to(self.root)
            out[(f.crate, f.module, target)].append((rel, f.line_of(pos), what))

        for f, pos, a, is_pub in self.uses:
            target = self.resolve(f.crate, a)
            facade = target is not None and target[: len(f.module)] == f.module
            if not (is_pub and facade):
                add(f, pos, a, ("pub use " if is_pub else "use ") + "::".join(["crate"] + a))
        for f in self.files:
            children = [c for (cr, m) in self.by_mod if cr == f.crate and m[:-1] == f.module and m
                        for c in [m[-1]]]
            head = r"(?:crate|super|self)" + (r"|" + "|".join(map(re.escape, children)) if children else "")
            pat = re.compile(r"(?<![\w:$])((?:" + head + r")(?:\s*::\s*" + IDENT + r")+)")
            use_spans = [(m.start(), m.end()) for m in re.finditer(r"\buse\s+[^;]+;", f.text)]
            vis_spans = [(m.start(), m.end()) for m in re.finditer(r"\bpub\s*\(\s*in\s+[^)]*\)", f.text)]
            for m in pat.finditer(f.text):
                if any(s <= m.start() < e for s, e in use_spans + vis_spans):
                    continue
                scope, test = f.scope_at(m.start())
                if test and not self.tests:
                    continue
                segs = [s.strip() for s in m.group(1).split("::")]
                a = self.absolute(f, scope, segs)
                if a is None:
                    continue
                add(f, m.start(), a, m.group(1))
        return out


def sccs(nodes, adj):
    """Tarjan's strongly connected components."""
    index, low, stack, on, comps = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(adj.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            comps.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return comps


def name(crate, mod):
    m = "/".join(mod) if mod else ("lib.rs" if crate == "lib" else "main.rs")
    return m if crate == "lib" else f"{crate}:{m}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("src", nargs="?", default=str(Path(__file__).resolve().parent.parent / "src"))
    ap.add_argument("--edges", action="store_true", help="print every edge")
    ap.add_argument("--tests", action="store_true", help="include #[cfg(test)] modules")
    args = ap.parse_args()
    files = collect(Path(args.src))
    src = Path(args.src).resolve()
    g = Graph(src.parent, files, args.tests)
    edges = g.edges()
    nodes = {(f.crate, f.module) for f in files}
    adj = defaultdict(set)
    for crate, a, b in edges:
        adj[(crate, a)].add((crate, b))
    if args.edges:
        for crate, a, b in sorted(edges):
            print(f"{name(crate, a)} -> {name(crate, b)}")
    cycles = [c for c in sccs(nodes, adj) if len(c) > 1]
    print(f"{len(nodes)} modules, {len(edges)} edges, {len(cycles)} cycle(s)")
    for c in sorted(cycles):
        print("cycle: " + " <-> ".join(name(*v) for v in c))
        members = set(c)
        for (crate, a, b), refs in sorted(edges.items()):
            if (crate, a) in members and (crate, b) in members:
                path, line, what = refs[0]
                more = f" (+{len(refs) - 1} more)" if len(refs) > 1 else ""
                print(f"  {name(crate, a)} -> {name(crate, b)}: {path}:{line} {what}{more}")
    return 1 if cycles else 0


if __name__ == "__main__":
    sys.exit(main())
