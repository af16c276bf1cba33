//! The floors: which floor each module stands on, and the check of the graph against them.

use crate::graph::{Graph, Reference};
use crate::source::Module;

/// A floor: its name and the top-level modules of the library on it (a file or folder of
/// `src/`; `lib.rs` is the crate root; `bin` stands for every module of every binary).
pub(crate) type Floor = (&'static str, &'static [&'static str]);

/// A known upward import: the importing module, the imported module (as [`Module::name`]
/// writes them) and why it is still there.
pub(crate) type Known = (&'static str, &'static str, &'static str);

/// An import of a module on a higher floor.
pub(crate) struct Upward {
    pub from: Module,
    pub to: Module,
    pub from_floor: &'static str,
    pub to_floor: &'static str,
    pub reference: Reference,
}

/// What the check found; [`Self::is_clean`] when nothing.
pub(crate) struct Check {
    /// Modules on no floor (a top-level module the table does not list).
    pub unplaced: Vec<Module>,
    /// Table entries that name no module.
    pub empty: Vec<&'static str>,
    /// Upward imports that are not known.
    pub upward: Vec<Upward>,
    /// Known upward imports that are gone (the list only shrinks).
    pub gone: Vec<Known>,
    /// Cycles (strongly connected components of more than one module).
    pub cycles: Vec<Vec<Module>>,
}

/// The top-level name a module stands under in the floor table.
fn key(m: &Module) -> &str {
    if m.krate != "lib" {
        return "bin";
    }
    m.path.first().map_or("lib.rs", String::as_str)
}

/// The floor of a module: its index (0 is the ground) and name.
fn floor_of(floors: &[Floor], m: &Module) -> Option<(usize, &'static str)> {
    let k = key(m);
    let i = floors.iter().position(|(_, ms)| ms.contains(&k))?;
    Some((i, floors[i].0))
}

/// Checks `graph` against `floors` (from the ground up): every module stands on a floor,
/// imports no module of a higher floor but the `known` ones, every known one still exists,
/// and there is no cycle.
pub(crate) fn check(graph: &Graph, floors: &[Floor], known: &[Known]) -> Check {
    let unplaced = graph
        .modules
        .iter()
        .filter(|m| floor_of(floors, m).is_none())
        .cloned()
        .collect();
    let empty = floors
        .iter()
        .flat_map(|(_, ms)| ms.iter().copied())
        .filter(|k| !graph.modules.iter().any(|m| key(m) == *k))
        .collect();
    let mut all = Vec::new();
    for ((from, to), reference) in &graph.edges {
        let (Some((a, from_floor)), Some((b, to_floor))) =
            (floor_of(floors, from), floor_of(floors, to))
        else {
            continue;
        };
        if b > a {
            all.push(Upward {
                from: from.clone(),
                to: to.clone(),
                from_floor,
                to_floor,
                reference: reference.clone(),
            });
        }
    }
    let is_known = |u: &Upward| {
        known
            .iter()
            .any(|(f, t, _)| u.from.name() == *f && u.to.name() == *t)
    };
    let gone = known
        .iter()
        .filter(|(f, t, _)| !all.iter().any(|u| u.from.name() == *f && u.to.name() == *t))
        .copied()
        .collect();
    Check {
        unplaced,
        empty,
        upward: all.into_iter().filter(|u| !is_known(u)).collect(),
        gone,
        cycles: graph.cycles(),
    }
}

impl Check {
    pub(crate) fn is_clean(&self) -> bool {
        self.unplaced.is_empty()
            && self.empty.is_empty()
            && self.upward.is_empty()
            && self.gone.is_empty()
            && self.cycles.is_empty()
    }

    /// Every finding, one per line (with the reference behind each edge).
    pub(crate) fn describe(&self, graph: &Graph) -> String {
        let mut s = String::new();
        for m in &self.unplaced {
            s.push_str(&format!(
                "{} stands on no floor: add it to FLOORS\n",
                m.name()
            ));
        }
        for k in &self.empty {
            s.push_str(&format!("FLOORS lists `{k}`, which is no module of src/\n"));
        }
        for u in &self.upward {
            let (file, line, what) = &u.reference;
            s.push_str(&format!(
                "{} (floor {}) imports {} (floor {}, above): src/{file}:{line} {what}\n",
                u.from.name(),
                u.from_floor,
                u.to.name(),
                u.to_floor
            ));
        }
        for (f, t, why) in &self.gone {
            s.push_str(&format!(
                "{f} no longer imports {t} from a floor above: remove it from KNOWN_UPWARD \
                 (\"{why}\")\n"
            ));
        }
        s.push_str(&graph.describe(&self.cycles));
        s
    }
}

/// The graph as the floors see it: each floor and its modules, the number of imports between
/// floors, then every import with the reference that makes it.
pub(crate) fn print(graph: &Graph, floors: &[Floor]) -> String {
    let floor = |m: &Module| floor_of(floors, m).map_or("?", |f| f.1);
    let mut s = format!(
        "{} modules, {} imports\n\nfloors, from the ground up:\n",
        graph.modules.len(),
        graph.edges.len()
    );
    for (name, ms) in floors {
        let n = graph.modules.iter().filter(|m| floor(m) == *name).count();
        s.push_str(&format!("  {name}: {} ({n} modules)\n", ms.join(", ")));
    }
    let mut between = std::collections::BTreeMap::new();
    for (a, b) in graph.edges.keys() {
        let pair = (floor_of(floors, a), floor_of(floors, b));
        *between.entry(pair).or_insert(0) += 1;
    }
    s.push_str("\nimports between floors:\n");
    for ((a, b), n) in &between {
        let name = |f: &Option<(usize, &str)>| f.map_or("?".to_string(), |f| f.1.to_string());
        s.push_str(&format!("  {} -> {}: {n}\n", name(a), name(b)));
    }
    s.push_str("\nimports:\n");
    for ((a, b), (file, line, what)) in &graph.edges {
        s.push_str(&format!(
            "  {} [{}] -> {} [{}]: src/{file}:{line} {what}\n",
            a.name(),
            floor(a),
            b.name(),
            floor(b)
        ));
    }
    s
}
