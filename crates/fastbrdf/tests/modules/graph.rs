//! The import graph of a crate (modules, edges followed through re-exports) and its cycles,
//! looked for at every level of the module tree.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::source::{Module, analyse};

pub struct Graph {
    pub label: String,
    /// The crate's `src/` folder relative to the repository, for messages.
    pub prefix: String,
    pub modules: Vec<Module>,
    /// (from, to, file:line and the path) for every import between two different modules.
    pub edges: Vec<Edge>,
}

#[derive(Clone, Debug)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    pub line: usize,
    pub what: String,
}

/// Reads the crate whose root file is `root_file` (relative to `base`) with `read`.
pub fn build(
    label: &str,
    base: &Path,
    root_file: &str,
    read: &dyn Fn(&Path) -> Option<String>,
) -> Graph {
    let mut modules: Vec<Module> = Vec::new();
    // (path, file) still to read.
    let mut todo = vec![(
        Vec::<String>::new(),
        PathBuf::from(root_file),
        None::<usize>,
    )];
    while let Some((path, file, parent)) = todo.pop() {
        let src = read(&base.join(&file))
            .unwrap_or_else(|| panic!("{label}: cannot read {}", base.join(&file).display()));
        let is_dir_module = path.is_empty() || file.file_name().is_some_and(|f| f == "mod.rs");
        let (module, children) = analyse(
            path.clone(),
            file.display().to_string(),
            &src,
            is_dir_module,
        );
        let me = modules.len();
        modules.push(module);
        if let Some(p) = parent {
            modules[p].children.insert(path.last().unwrap().clone(), me);
        }
        let dir = if is_dir_module {
            file.parent().unwrap().to_path_buf()
        } else {
            file.with_extension("")
        };
        for c in children {
            let flat = dir.join(format!("{c}.rs"));
            let folder = dir.join(&c).join("mod.rs");
            let child_file = if read(&base.join(&flat)).is_some() {
                flat
            } else {
                folder
            };
            let mut p = path.clone();
            p.push(c);
            todo.push((p, child_file, Some(me)));
        }
    }
    let mut g = Graph {
        label: label.to_string(),
        prefix: String::new(),
        modules,
        edges: Vec::new(),
    };
    g.edges = edges(&g);
    g
}

impl Graph {
    /// The file of module `m`, relative to the repository.
    pub fn file(&self, m: usize) -> String {
        format!("{}{}", self.prefix, self.modules[m].file)
    }

    pub fn name(&self, m: usize) -> String {
        std::iter::once(self.label.as_str())
            .chain(self.modules[m].path.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join("::")
    }

    /// An edge for a message: `file:line `path` (-> file)`, indented, one line.
    pub fn edge_line(&self, e: &Edge) -> String {
        format!(
            "    {}:{} `{}` (-> {})\n",
            self.file(e.from),
            e.line,
            e.what,
            self.file(e.to)
        )
    }

    pub fn find(&self, path: &[String]) -> Option<usize> {
        self.modules.iter().position(|m| m.path == path)
    }

    /// Walks `segs` (absolute) down the module tree: the module reached and the first segment
    /// that is not a module (an item of it), if any.
    fn walk(&self, segs: &[String]) -> (usize, Option<String>) {
        let mut m = self.find(&[]).unwrap();
        for s in segs {
            match self.modules[m].children.get(s) {
                Some(&c) => m = c,
                None => return (m, Some(s.clone())),
            }
        }
        (m, None)
    }

    /// The absolute path of `segs` as written in module `m` at offset `at`, if it leads into
    /// the crate.
    fn absolute(&self, m: usize, segs: &[String], at: usize, depth: usize) -> Option<Vec<String>> {
        let module = &self.modules[m];
        let first = segs.first()?;
        let mut base = module.path.clone();
        let rest;
        match first.as_str() {
            "crate" | "$crate" => {
                base.clear();
                rest = &segs[1..];
            }
            "self" => rest = &segs[1..],
            "super" => {
                // The inline modules around `at` come first.
                let mut inline = module
                    .inline
                    .iter()
                    .filter(|(a, b)| *a < at && at < *b)
                    .count();
                let mut k = 0;
                while segs.get(k).is_some_and(|s| s == "super") {
                    if inline > 0 {
                        inline -= 1;
                    } else {
                        base.pop();
                    }
                    k += 1;
                }
                rest = &segs[k..];
            }
            name => {
                if module.children.contains_key(name) {
                    rest = segs;
                } else if depth < 8
                    && let Some(target) = self.module_alias(m, name, depth + 1)
                {
                    base = self.modules[target].path.clone();
                    rest = &segs[1..];
                } else {
                    return None;
                }
            }
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// The module that a `use` in `m` binds to `name`, if any (`use super::render;`, or a
    /// child of a module glob-imported with `use super::*`).
    fn module_alias(&self, m: usize, name: &str, depth: usize) -> Option<usize> {
        let module = &self.modules[m];
        for u in module
            .uses
            .iter()
            .filter(|u| !u.glob && u.alias.as_deref() == Some(name))
        {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth)
                && let (t, None) = self.walk(&abs)
            {
                return Some(t);
            }
        }
        for u in module.uses.iter().filter(|u| u.glob) {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth)
                && let (t, None) = self.walk(&abs)
                && let Some(&c) = self.modules[t].children.get(name)
            {
                return Some(c);
            }
        }
        None
    }

    /// The module that defines item `name` seen in module `m`, following its `use`s.
    fn owner(&self, m: usize, name: &str, depth: usize) -> Option<usize> {
        if depth > 8 {
            return None;
        }
        let module = &self.modules[m];
        for u in module
            .uses
            .iter()
            .filter(|u| !u.glob && u.alias.as_deref() == Some(name))
        {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth + 1) {
                return Some(match self.walk(&abs) {
                    (t, None) => t,
                    (t, Some(item)) => self.owner(t, &item, depth + 1).unwrap_or(t),
                });
            }
        }
        if module.defines.contains(name) {
            return Some(m);
        }
        for u in module.uses.iter().filter(|u| u.glob) {
            if let Some(abs) = self.absolute(m, &u.segs, u.at, depth + 1)
                && let (t, None) = self.walk(&abs)
                && let Some(o) = self.owner(t, name, depth + 1)
            {
                return Some(o);
            }
        }
        None
    }

    /// The module a path written in `m` imports from.
    fn target(&self, m: usize, segs: &[String], at: usize) -> Option<(usize, bool)> {
        let abs = self.absolute(m, segs, at, 0)?;
        Some(match self.walk(&abs) {
            (t, None) => (t, true),
            (t, Some(item)) => (self.owner(t, &item, 0).unwrap_or(t), false),
        })
    }
}

fn edges(g: &Graph) -> Vec<Edge> {
    let mut out = Vec::new();
    let mut seen = BTreeSet::new();
    for (m, module) in g.modules.iter().enumerate() {
        let mut add = |to: usize, at: usize, what: String| {
            let line = module.line(at);
            if to != m && seen.insert((m, to, line)) {
                out.push(Edge {
                    from: m,
                    to,
                    line,
                    what,
                });
            }
        };
        for u in &module.uses {
            match g.target(m, &u.segs, u.at) {
                // `use a::b;` naming a module binds a name; its uses are the edges. A glob
                // import takes the module's items.
                Some((_, true)) if !u.glob => {}
                Some((t, _)) => add(t, u.at, format!("use {}", u.segs.join("::"))),
                None => {}
            }
        }
        for p in &module.paths {
            if let Some((t, _)) = g.target(m, &p.segs, p.at) {
                add(t, p.at, p.segs.join("::"));
            }
        }
    }
    out
}

// ---------------------------------------------------------------- cycles

/// A cycle found at one level: the scope (folder) and the nodes (its children) in it, with the
/// edges between them.
pub struct Cycle {
    pub scope: usize,
    pub nodes: Vec<usize>,
    pub edges: Vec<Edge>,
}

/// Whether `a` is `anc` or inside it.
fn within(g: &Graph, a: usize, anc: usize) -> bool {
    g.modules[a].path.starts_with(&g.modules[anc].path)
}

/// The child of `scope` that holds `a` (a strict descendant of `scope`).
pub fn child_holding(g: &Graph, scope: usize, a: usize) -> Option<usize> {
    let depth = g.modules[scope].path.len();
    if a == scope || !within(g, a, scope) {
        return None;
    }
    g.find(&g.modules[a].path[..=depth])
}

/// The strongly connected components of more than one node.
pub fn sccs(nodes: &[usize], edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let reach = |from: usize| {
        let mut seen = BTreeSet::from([from]);
        let mut stack = vec![from];
        while let Some(x) = stack.pop() {
            for (a, b) in edges {
                if *a == x && seen.insert(*b) {
                    stack.push(*b);
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<usize, BTreeSet<usize>> = nodes.iter().map(|&n| (n, reach(n))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for &n in nodes {
        if done.contains(&n) {
            continue;
        }
        let scc: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&o| reaches[&n].contains(&o) && reaches[&o].contains(&n))
            .collect();
        done.extend(scc.iter().copied());
        if scc.len() > 1 {
            out.push(scc);
        }
    }
    out
}

/// The cycles at every level: among the children of each module that has two or more.
pub fn cycles(g: &Graph) -> Vec<Cycle> {
    let mut found = Vec::new();
    for scope in 0..g.modules.len() {
        let nodes: Vec<usize> = g.modules[scope].children.values().copied().collect();
        if nodes.len() < 2 {
            continue;
        }
        // Edges lifted to the scope's children; the scope's own file takes no part.
        let mut lifted: Vec<(usize, usize, Edge)> = Vec::new();
        for e in &g.edges {
            if let (Some(a), Some(b)) = (
                child_holding(g, scope, e.from),
                child_holding(g, scope, e.to),
            ) && a != b
            {
                lifted.push((a, b, e.clone()));
            }
        }
        let pairs: Vec<(usize, usize)> = lifted.iter().map(|(a, b, _)| (*a, *b)).collect();
        for scc in sccs(&nodes, &pairs) {
            let edges = lifted
                .iter()
                .filter(|(a, b, _)| scc.contains(a) && scc.contains(b))
                .map(|(_, _, e)| e.clone())
                .collect();
            found.push(Cycle {
                scope,
                nodes: scc,
                edges,
            });
        }
    }
    found
}

/// A cycle for a message: its nodes, then its edges grouped by the pair of nodes they join.
pub fn describe(g: &Graph, c: &Cycle) -> String {
    let names: Vec<String> = c.nodes.iter().map(|&n| g.name(n)).collect();
    let mut s = format!(
        "cycle among the modules of `{}`: {}\n",
        g.name(c.scope),
        names.join(", ")
    );
    // Edges grouped by the pair of nodes they join, a few lines each.
    let mut by_pair: BTreeMap<(String, String), Vec<&Edge>> = BTreeMap::new();
    for e in &c.edges {
        let a = child_holding(g, c.scope, e.from).unwrap();
        let b = child_holding(g, c.scope, e.to).unwrap();
        by_pair.entry((g.name(a), g.name(b))).or_default().push(e);
    }
    for ((a, b), es) in &by_pair {
        s += &format!("  {a} -> {b}:\n");
        for e in es.iter().take(4) {
            s += &g.edge_line(e);
        }
        if es.len() > 4 {
            s += &format!("    (+{} more)\n", es.len() - 4);
        }
    }
    s
}
